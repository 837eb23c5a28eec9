// sepal_rt.h - the sepal runtime: GL capability checks, meshes, preview drawing.
//
// Usage (a port has created and made current a GL ES context):
//   sepal_error err = {SEPAL_OK, ""};
//   sepal_caps caps;
//   if (sepal_query_caps(1, 0, sepal_headless_get_proc_address, &caps, &err) != SEPAL_OK) { puts(err.message); }
//   static sepal_vertex v[SEPAL_SPHERE_MAX_VERTICES]; static uint16_t idx[SEPAL_SPHERE_MAX_INDICES];
//   sepal_mesh mesh = {v, idx, SEPAL_SPHERE_MAX_VERTICES, SEPAL_SPHERE_MAX_INDICES};  // capacities in
//   sepal_mesh_sphere(32, 16, &mesh, &err);         // counts out
//   const float eye[3] = {0, -3, 0}, target[3] = {0, 0, 0}, up[3] = {0, 0, 1};
//   sepal_preview_desc d = {0};
//   d.mesh = &mesh; d.base_color[0] = d.base_color[1] = d.base_color[2] = 0.8f;
//   d.light_dir_eye[2] = 1.0f;
//   sepal_mat4_look_at(eye, target, up, d.model_view);
//   sepal_mat4_perspective(45.0f, 1.0f, 0.1f, 10.0f, d.projection);
//   sepal_preview_draw(&caps, &d, &err);
//
// Rules: C++17 inside, a C-like API outside; no exceptions, no RTTI, no iostream, no
// C++ string class; the runtime allocates nothing: callers hand in all memory. Errors are
// return codes with a message in sepal_error. The runtime never creates a window or a
// context; ports/ do that and hand the current context in.
// Limits: meshes use 16-bit indices (at most 65535 vertices).
//
// Thread safety: sepal_query_caps and sepal_preview_draw call GL (the thread whose context
// is current, one call at a time per context); the mesh generators, sepal_obj_measure,
// sepal_obj_load and the matrix helpers keep no state (any threads at once, distinct outputs).
#pragma once
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sepal_result {
    SEPAL_OK = 0,
    SEPAL_ERR_INVALID_ARGUMENT = 1,  // a caller error: NULL, out-of-range size, ...
    SEPAL_ERR_UNSUPPORTED = 2,       // the GL context lacks what the path needs
    SEPAL_ERR_GL = 3,                // GL reported an error (message names the call)
    SEPAL_ERR_CAPACITY = 4,          // a caller-provided buffer is too small
} sepal_result;

typedef struct sepal_error {
    sepal_result code;
    char message[256];
} sepal_error;

// ---- version ------------------------------------------------------------------------
// The linked library's version (a program built against one release's headers and run
// with another's shared library sees both): SEPAL_VERSION packed (major << 16 | minor << 8
// | patch) and SEPAL_VERSION_STRING. Compare majors before trusting the ABI:
//   if ((sepal_version() >> 16) != SEPAL_VERSION_MAJOR) { puts(sepal_version_string()); }
uint32_t sepal_version(void);
const char* sepal_version_string(void);

// ---- capabilities -------------------------------------------------------------------
// Bits of a mask that hides capabilities the context has, so every fallback path can be
// exercised on a driver that has everything (e.g. Mesa).
enum {
    SEPAL_MASK_BLEND_SUBTRACT = 1u << 0,  // pretend GL_OES_blend_subtract is missing
    SEPAL_MASK_MULTITEXTURE = 1u << 1,    // pretend there is one texture unit
    SEPAL_MASK_FBO = 1u << 2,             // pretend framebuffer objects are missing
    SEPAL_MASK_NPOT = 1u << 3,            // pretend non-power-of-two textures are missing
    SEPAL_MASK_FLOAT_TARGET = 1u << 4,    // pretend half-float render targets are missing
    SEPAL_MASK_THIRD_UNIT = 1u << 5,      // pretend there are at most two texture units
};

typedef struct sepal_caps {
    int gles_version;        // 1 or 2 (a 3.x context reports 2: only ES 2 paths are used)
    int texture_units;       // fixed-function units (ES 1) or fragment samplers (ES 2)
    int max_texture_size;
    int has_blend_subtract;  // GL_OES_blend_subtract (ES 1) or core (ES 2)
    int has_fbo;             // GL_OES_framebuffer_object (ES 1) or core (ES 2)
    int has_npot;            // full NPOT textures (GL_OES_texture_npot or ES 3)
    // Half-float colour buffers (GL ES 3 with GL_EXT_color_buffer_half_float or _float):
    // the GL ES 2 paths can draw into one to measure what the 8-bit framebuffer costs
    // (sepal_material_create_float_target).
    int has_float_target;
    // The colour buffer bound when the caps were read (the window's or pbuffer's, normally):
    // bits per channel (GL_RED_BITS, GL_GREEN_BITS, GL_BLUE_BITS; 5/6/5 on an RGB565 surface)
    // and whether GL_DITHER is enabled (GL ES enables it by default). With fewer than 8 bits
    // in a channel, the GL paths sum each object's passes in an 8-bit target and write it
    // rounded once (has_fbo, and fbo_es1 below on GL ES 1.1; without them every pass is
    // rounded to these bits): sepal_emulate_desc takes them to show what the device shows (docs/ports.md,
    // "Framebuffer bits"). The frame's exposure, staging and doublings do not depend on them: the
    // exposure keeps every pass and partial sum at or below 1.0, the framebuffer's white at
    // any bit depth, and the doublings are the plan's (chosen by the bake for its target).
    int red_bits, green_bits, blue_bits;
    int dither;
    uint32_t mask;           // the mask that was applied
    // Extension entry points, from the port's loader (NULL when unavailable).
    void (*blend_equation)(unsigned int mode);  // glBlendEquationOES / glBlendEquation
    char renderer[128];
    char version[128];
    // GL_OES_framebuffer_object's entry points on GL ES 1.1 (from the port's loader; all NULL
    // on GL ES 2, whose core functions are linked, and when has_fbo is 0). With them the
    // GL ES 1.1 multipass path sums an object's passes in an 8-bit target when the framebuffer
    // has fewer bits (sepal_material_info.accumulates in sepal_material.h).
    struct {
        void (*gen_framebuffers)(int n, unsigned int* ids);
        void (*delete_framebuffers)(int n, const unsigned int* ids);
        void (*bind_framebuffer)(unsigned int target, unsigned int framebuffer);
        void (*framebuffer_texture_2d)(unsigned int target, unsigned int attachment, unsigned int textarget,
                                       unsigned int texture, int level);
        void (*gen_renderbuffers)(int n, unsigned int* ids);
        void (*delete_renderbuffers)(int n, const unsigned int* ids);
        void (*bind_renderbuffer)(unsigned int target, unsigned int renderbuffer);
        void (*renderbuffer_storage)(unsigned int target, unsigned int format, int width, int height);
        void (*framebuffer_renderbuffer)(unsigned int target, unsigned int attachment, unsigned int rb_target,
                                         unsigned int renderbuffer);
        unsigned int (*check_framebuffer_status)(unsigned int target);
    } fbo_es1;
} sepal_caps;

// The port's way to find GL entry points (eglGetProcAddress for EGL ports): the runtime
// never calls EGL itself, and GL ES 1.1 libraries do not export extension functions.
typedef void (*sepal_gl_proc)(void);
typedef sepal_gl_proc (*sepal_proc_loader)(const char* name);

// Reads the current context's capabilities and applies mask. gles_version must be the
// version the context was created for (1 or 2). get_proc may be NULL: capabilities
// that need an extension entry point are then reported missing.
sepal_result sepal_query_caps(int gles_version, uint32_t mask, sepal_proc_loader get_proc,
                          sepal_caps* out, sepal_error* err);

// ---- meshes ---------------------------------------------------------------------------
typedef struct sepal_vertex {
    float position[3];
    float normal[3];
    float tangent[4];  // xyz: primary tangent t, w: handedness (s = w * n x t)
    float uv[2];
} sepal_vertex;

typedef struct sepal_mesh {
    sepal_vertex* vertices;  // caller-owned storage
    uint16_t* indices;     // triangles, caller-owned storage
    int vertex_count;      // in: capacity, out: used
    int index_count;       // in: capacity, out: used
} sepal_mesh;

#define SEPAL_SPHERE_MAX_VERTICES ((256 + 1) * (128 + 1))
#define SEPAL_SPHERE_MAX_INDICES (256 * 128 * 6)
// The sphere of the default scene (`sepal render`, the bake's judged views, the ports).
// Texture coordinates and the diffuse colour are interpolated between its vertices on GL ES
// 1.1; 128 x 64 keeps that interpolation's error below the factors' own (docs/fidelity.md).
#define SEPAL_SCENE_SPHERE_SLICES 128
#define SEPAL_SCENE_SPHERE_STACKS 64

// Unit sphere (radius 1, centre 0), slices 3..256 around z, stacks 2..128 from pole to
// pole; analytic normals and tangents (t along increasing longitude). vertex_count and
// index_count give capacities on entry (SEPAL_ERR_CAPACITY if too small).
sepal_result sepal_mesh_sphere(int slices, int stacks, sepal_mesh* mesh, sepal_error* err);
// Square grid in the z = 0 plane spanning [-1,1]^2, normal +z, tangent +x, n x n cells,
// n in 1..254.
sepal_result sepal_mesh_grid(int n, sepal_mesh* mesh, sepal_error* err);

// Torus around z: major radius R (centre to tube centre), minor radius r (0 < r < R),
// rings 3..256 around z, sides 3..128 around the tube; analytic normals and tangents
// (t along the ring direction). Capacity: (rings+1)(sides+1) vertices, 6 rings sides
// indices.
sepal_result sepal_mesh_torus(float major_radius, float minor_radius, int rings, int sides,
                          sepal_mesh* mesh, sepal_error* err);
// The curved test model: the height field z = a cos(pi x / 2) cos(pi y / 2) over
// [-1,1]^2 with a = 0.35, n x n cells (1..254), analytic normals and tangents (t is the
// normalized dP/dx: curvature in both directions rotates the frame across the surface).
sepal_result sepal_mesh_wave(int n, sepal_mesh* mesh, sepal_error* err);

// Wavefront OBJ from memory: v, vt, vn and f (polygons fanned into triangles; negative
// indices allowed); other statements ignored. Two steps, no allocation:
//   sepal_obj_info info; sepal_obj_measure(text, len, &info, &err);
//   ... provide info.max_vertices / info.max_indices storage and info.scratch_bytes ...
//   sepal_obj_load(text, len, &mesh, scratch, info.scratch_bytes, &stats, &err);
// Corners with the same v/vt/vn triple share a vertex. Missing normals are computed
// (area-weighted, per position); tangents come from the UVs (per-vertex accumulation,
// Gram-Schmidt against the normal, handedness in w). Where UVs are missing or
// degenerate the tangent is any unit vector perpendicular to the normal; stats counts
// such vertices, so nothing is silent.
typedef struct sepal_obj_info {
    int positions, texcoords, normals;
    int triangles;
    int max_vertices;  // upper bound on unified vertices (= corners)
    int max_indices;
    size_t scratch_bytes;
} sepal_obj_info;

typedef struct sepal_obj_stats {
    int computed_normals;      // vertices whose normal was computed (no vn in the file)
    int fallback_tangents;     // vertices without a usable UV-derived tangent
    int degenerate_triangles;  // zero-area triangles (kept; they draw nothing)
} sepal_obj_stats;

sepal_result sepal_obj_measure(const char* text, size_t length, sepal_obj_info* info,
                           sepal_error* err);
sepal_result sepal_obj_load(const char* text, size_t length, sepal_mesh* mesh, void* scratch,
                        size_t scratch_bytes, sepal_obj_stats* stats, sepal_error* err);

// ---- preview drawing ------------------------------------------------------------------
// A mesh lit by one directional light (Gouraud, like GL ES 1.1 fixed-function lighting)
// and modulated by an RGBA8 texture. Identical maths on GL ES 1.1 (glLight) and GL ES 2
// (a tiny shader), so both paths can be pixel-compared. Used by sepal-view before an
// asset is loaded and by the chain tests.
typedef struct sepal_preview_desc {
    const sepal_mesh* mesh;
    float model_view[16];     // column-major; must be a rigid transform (normals use it)
    float projection[16];     // column-major
    float light_dir_eye[3];   // direction towards the light, eye space
    float base_color[3];      // material colour
    float ambient;            // scene ambient level, 0..1
    const uint8_t* texture;   // RGBA8, top row first; NULL means white
    int texture_width;        // power of two, 1..max_texture_size
    int texture_height;
    float clear_color[4];
} sepal_preview_desc;

sepal_result sepal_preview_draw(const sepal_caps* caps, const sepal_preview_desc* desc,
                            sepal_error* err);

// ---- small maths helpers (column-major 4x4) -------------------------------------------
void sepal_mat4_perspective(float fovy_degrees, float aspect, float z_near, float z_far,
                          float out[16]);
void sepal_mat4_look_at(const float eye[3], const float target[3], const float up[3],
                      float out[16]);

#ifdef __cplusplus
}
#endif
