/* minimal.c - the sepal runtime from C99: a headless GL ES context, one asset, one frame.
 *   cc -std=c99 minimal.c $(pkg-config --cflags --libs sepal) -o minimal
 *   (against a build tree without make install: PKG_CONFIG_PATH=build, docs/ports.md)
 *   ./minimal ASSET.sepal [gles 1|2] [out.ppm]    (prints the lit share; exit 1 on errors) */
#include <stdio.h>
#include <stdlib.h>

#include <sepal/sepal.h>
#include <sepal/sepal_headless.h>

enum { W = 256, H = 256, SLICES = 64, STACKS = 32 };
static sepal_asset asset;        /* large structs: static, the runtime allocates nothing */
static sepal_material material;
static sepal_vertex vertices[(SLICES + 1) * (STACKS + 1)];
static uint16_t indices[SLICES * STACKS * 6];
static uint8_t pixels[W * H * 4];

static int fail(const char* what, const char* why) {
    fprintf(stderr, "minimal: %s: %s\n", what, why);
    return 1;
}

int main(int argc, char** argv) {
    if (argc < 2) return fail("usage", "minimal ASSET.sepal [1|2] [out.ppm]");
    FILE* f = fopen(argv[1], "rb");
    if (!f) return fail(argv[1], "cannot open");
    static uint8_t bytes[SEPAL_FMT_MAX_FILE_BYTES];
    const size_t size = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    sepal_error err = {0};
    if (sepal_asset_parse(bytes, size, &asset, &err) != SEPAL_OK) return fail(argv[1], err.message);

    sepal_headless_desc hd = {0};  /* zero means default */
    hd.width = W, hd.height = H, hd.gles_version = argc > 2 ? atoi(argv[2]) : 2;
    char why[256];
    sepal_headless_context* ctx = sepal_headless_create(&hd, why, sizeof why);
    if (!ctx) return fail("context", why);
    sepal_caps caps;
    if (sepal_query_caps(hd.gles_version, 0, sepal_headless_get_proc_address, &caps, &err) != SEPAL_OK ||
        sepal_material_create(&caps, &asset, W, H, &material, &err) != SEPAL_OK)
        return fail("material", err.message);

    sepal_mesh mesh = {vertices, indices, (SLICES + 1) * (STACKS + 1), SLICES * STACKS * 6};
    sepal_scene scene;
    sepal_scene_default(&scene);  /* camera on -y, one point light */
    if (sepal_mesh_sphere(SLICES, STACKS, &mesh, &err) != SEPAL_OK) return fail("mesh", err.message);
    sepal_draw_desc d = {0};
    d.material = &material, d.mesh = &mesh, d.scene = &scene, d.width = W, d.height = H;
    d.scratch_floats = sepal_draw_scratch_floats(mesh.vertex_count, scene.light_count);
    d.scratch = malloc(d.scratch_floats * sizeof(float));
    sepal_draw_stats stats;
    if (!d.scratch || sepal_draw(&d, &stats, &err) != SEPAL_OK) return fail("draw", err.message);
    if (!sepal_headless_read_rgba(ctx, pixels)) return fail("read back", "glReadPixels failed");

    int lit = 0;
    for (int i = 0; i < W * H; ++i) lit += pixels[4 * i] + pixels[4 * i + 1] + pixels[4 * i + 2] > 0;
    printf("sepal %s, %s: %d draw calls, %.1f%% of pixels lit\n", SEPAL_VERSION_STRING, caps.renderer,
           stats.draw_calls, 100.0 * lit / (W * H));
    if (argc > 3 && (f = fopen(argv[3], "wb")) != NULL) {  /* PPM: no image library needed */
        fprintf(f, "P6 %d %d 255\n", W, H);
        for (int i = 0; i < W * H; ++i) fwrite(pixels + 4 * i, 1, 3, f);
        fclose(f);
    }
    free(d.scratch);
    sepal_material_destroy(&material);
    sepal_headless_destroy(ctx);
    return lit > 0 ? 0 : fail("frame", "nothing was drawn");
}
