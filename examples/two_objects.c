/* two_objects.c - a frame of the program's own: its clear colour and a quad, then two sepal
 * objects with their own model matrices, on GL ES 1.1 (sepal_frame.h).
 *   cc -std=c99 two_objects.c $(pkg-config --cflags --libs sepal glesv1_cm) -o two_objects
 *   ./two_objects ASSET.sepal [out.ppm]
 * Prints the lit pixels and whether what the program drew survived where no object covers
 * it; exit 1 on errors or when it did not. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLES/gl.h>
#include <sepal/sepal.h>
#include <sepal/sepal_headless.h>

enum { W = 256, H = 192, SLICES = 48, STACKS = 24 };
static sepal_asset asset; /* large structs: static, the runtime allocates nothing */
static sepal_material material;
static sepal_vertex vertices[(SLICES + 1) * (STACKS + 1)];
static uint16_t indices[SLICES * STACKS * 6];
static uint8_t before[W * H * 4], after[W * H * 4];

static int fail(const char* what, const char* why) {
    fprintf(stderr, "two_objects: %s: %s\n", what, why);
    return 1;
}

/* The program's own drawing: a clear colour, and a quad behind where the objects go. */
static void draw_own_things(void) {
    static const GLfloat quad[12] = {-0.9f, -0.8f, 0.99f, 0.1f, -0.8f, 0.99f, 0.1f, 0.2f, 0.99f, -0.9f, 0.2f, 0.99f};
    glViewport(0, 0, W, H);
    glClearColor(0.1f, 0.15f, 0.3f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, quad);
    glColor4f(0.8f, 0.6f, 0.2f, 1.0f);
    glDrawArrays(GL_TRIANGLE_FAN, 0, 4);
    glDisableClientState(GL_VERTEX_ARRAY);
}

/* Rotation about z, uniform scale, translation: column-major, as GL and sepal take them. */
static void model(float degrees, float scale, float x, float y, float z, float m[16]) {
    const float a = degrees * 3.14159265f / 180.0f, c = cosf(a) * scale, s = sinf(a) * scale;
    sepal_model_identity(m);
    m[0] = c, m[1] = s, m[4] = -s, m[5] = c, m[10] = scale;
    m[12] = x, m[13] = y, m[14] = z;
}

int main(int argc, char** argv) {
    if (argc < 2) return fail("usage", "two_objects ASSET.sepal [out.ppm]");
    FILE* f = fopen(argv[1], "rb");
    if (!f) return fail(argv[1], "cannot open");
    static uint8_t bytes[SEPAL_FMT_MAX_FILE_BYTES];
    const size_t size = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    sepal_error err = {0};
    if (sepal_asset_parse(bytes, size, &asset, &err) != SEPAL_OK) return fail(argv[1], err.message);

    sepal_headless_desc hd = {0};
    hd.width = W, hd.height = H, hd.gles_version = 1, hd.depth_bits = 24;
    char why[256];
    sepal_headless_context* ctx = sepal_headless_create(&hd, why, sizeof why);
    if (!ctx) return fail("context", why);
    sepal_caps caps;
    if (sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &err) != SEPAL_OK ||
        sepal_material_create(&caps, &asset, W, H, &material, &err) != SEPAL_OK)
        return fail("material", err.message);
    sepal_mesh mesh = {vertices, indices, (SLICES + 1) * (STACKS + 1), SLICES * STACKS * 6};
    if (sepal_mesh_sphere(SLICES, STACKS, &mesh, &err) != SEPAL_OK) return fail("mesh", err.message);

    /* The program's camera as matrices (here from sepal's default scene) and its lights. */
    sepal_scene scene;
    sepal_scene_default(&scene);
    sepal_frame_desc fd = {0};
    fd.caps = &caps;
    if (sepal_scene_matrices(&scene, W, H, fd.view, fd.projection, &err) != SEPAL_OK) return fail("camera", err.message);
    fd.viewport[2] = W, fd.viewport[3] = H;
    fd.scratch_floats = sepal_draw_scratch_floats(mesh.vertex_count, 2);
    fd.scratch = malloc(fd.scratch_floats * sizeof(float));
    if (!fd.scratch) return fail("scratch", "out of memory");
    sepal_light lights[2] = {scene.lights[0], scene.lights[0]};
    lights[1].type = SEPAL_LIGHT_DIRECTIONAL;
    lights[1].position[0] = -0.5f, lights[1].position[1] = -1.0f, lights[1].position[2] = 0.6f;
    lights[1].intensity[0] = 0.3f, lights[1].intensity[1] = 0.4f, lights[1].intensity[2] = 0.8f;

    draw_own_things();
    if (!sepal_headless_read_rgba(ctx, before)) return fail("read back", "glReadPixels failed");
    sepal_frame frame;
    sepal_object objects[2];
    memset(objects, 0, sizeof objects);
    for (int k = 0; k < 2; ++k) {
        objects[k].material = &material, objects[k].mesh = &mesh;
        objects[k].lights = lights, objects[k].light_count = 2;
    }
    model(0.0f, 0.6f, -0.45f, 0.2f, 0.0f, objects[0].model);
    model(35.0f, 0.45f, 0.4f, -0.4f, 0.1f, objects[1].model);
    sepal_draw_stats stats;
    int draw_calls = 0;
    if (sepal_frame_begin(&frame, &fd, &err) != SEPAL_OK) return fail("frame", err.message);
    for (int k = 0; k < 2; ++k) {
        if (sepal_frame_draw(&frame, &objects[k], &stats, &err) != SEPAL_OK) return fail("object", err.message);
        draw_calls += stats.draw_calls + stats.fullscreen_passes;
    }
    if (sepal_frame_end(&frame, &err) != SEPAL_OK) return fail("frame end", err.message);
    if (!sepal_headless_read_rgba(ctx, after)) return fail("read back", "glReadPixels failed");

    /* The corners and the quad's far corner lie outside both spheres: kept bit for bit. */
    const int probes[3][2] = {{2, 2}, {W - 3, H - 3}, {(int)(0.07f * W), (int)(0.86f * H)}};
    int kept = 1, changed = 0;
    for (int i = 0; i < 3; ++i) kept &= !memcmp(before + 4 * (probes[i][1] * W + probes[i][0]),
                                                after + 4 * (probes[i][1] * W + probes[i][0]), 4);
    for (int i = 0; i < W * H * 4; ++i) changed += before[i] != after[i];
    /* And the GL state is the program's again (a few of the items sepal_frame.h lists). */
    GLfloat clear[4];
    glGetFloatv(GL_COLOR_CLEAR_VALUE, clear);
    const int state_kept = glIsEnabled(GL_DEPTH_TEST) && glIsEnabled(GL_DITHER) && !glIsEnabled(GL_BLEND) &&
                           !glIsEnabled(GL_CULL_FACE) && fabsf(clear[2] - 0.3f) < 1e-6f;
    printf("sepal %s: two objects in %d GL passes, %d bytes changed; clear colour and quad kept: %s; "
           "GL state kept: %s\n",
           SEPAL_VERSION_STRING, draw_calls, changed, kept ? "yes" : "NO", state_kept ? "yes" : "NO");
    if (argc > 2 && (f = fopen(argv[2], "wb")) != NULL) { /* PPM: no image library needed */
        fprintf(f, "P6 %d %d 255\n", W, H);
        for (int i = 0; i < W * H; ++i) fwrite(after + 4 * i, 1, 3, f);
        fclose(f);
    }
    free(fd.scratch);
    sepal_material_destroy(&material);
    sepal_headless_destroy(ctx);
    if (!kept) return fail("frame", "pixels outside the objects changed");
    if (!state_kept) return fail("frame", "the GL state was not restored");
    return changed > 0 ? 0 : fail("frame", "nothing was drawn");
}
