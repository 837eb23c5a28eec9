// sepal_tree.h - inverse shade trees at run time: a spatially varying material drawn as
// blend maps times basis materials, S(uv, wi, wo) ~= sum_j w_j(uv) f_j(wi, wo), each f_j a
// baked .sepal material (sum of separable terms). Format (written by offline/ist/
// tree_asset.h, read here) and drawing on GL ES 1.1, GL ES 2 and the CPU.
//
// Usage (a port made a GL ES context current; caps from sepal_query_caps):
//   static sepal_tree_asset asset;                       // ~100 KB: keep it static
//   sepal_tree_parse(bytes, size, &asset, &err);         // bytes must outlive asset and tree
//   static sepal_tree tree;
//   sepal_tree_create(&caps, &asset, 512, 512, &tree, &err);
//   size_t n = sepal_draw_scratch_floats(mesh.vertex_count, scene.light_count);
//   float* scratch = malloc(n * sizeof(float));           // once, at load
//   sepal_tree_draw_desc d = {0}; d.tree = &tree; d.mesh = &mesh; d.scene = &scene;
//   d.width = d.height = 512; d.scratch = scratch; d.scratch_floats = n;
//   sepal_tree_draw(&d, &stats, &err);
//   sepal_tree_destroy(&tree);
//
// File layout (version 1.0, little-endian):
//   sepal_tree_header                      64 bytes, magic "SEPALIST"
//   sepal_tree_basis[basis_count]          32 bytes each
//   per basis: its blend map (width x height bytes, row 0 at v = 0) and, 8-byte aligned,
//   a complete .sepal asset (sepal_format.h), each where its sepal_tree_basis says.
// The header's CRC-32 covers the whole file (the field itself 0); every embedded asset
// also carries its own checksums. A blend map byte q means weight q / 255: the writer
// scales each map to use the full range and folds the factor into that basis's textures
// (blend_scale records it). Bounds: 1..SEPAL_TREE_MAX_BASES bases, blend maps power-of-two
// sides up to SEPAL_TREE_MAX_BLEND_SIDE, file up to SEPAL_TREE_MAX_FILE_BYTES.
//
// How a frame is drawn (every backend computes the same sum):
//   GL ES 1.1 and GL ES 2 (multipass): each basis is drawn by sepal_draw with its blend
//   map as the diffuse texture map (its plan, then one pass multiplying by w_j at the
//   mesh's UVs); from the second basis on, the framebuffer is first copied to a texture
//   and added back with one full-screen pass. Passes per frame: the bases' own plus
//   2 (K - 1) (copies and additions); the scene's background is drawn by the last basis.
//   GL ES 2 (SEPAL_MODE_FUSED_PIXEL): one shader sums w_j G_jk H_jk over every basis and
//   term per pixel and per light in one mesh pass; factors live in two atlases (G and H,
//   one tile per term, lookups clamped inside their tile), each blend map in its own
//   texture unit (2 + bases units in all).
//   CPU: sepal_draw_cpu per basis with the blend map as diffuse map, summed in float.
// Limits: the bases must share one parameterization, hemisphere map and factor size, hold
// RGB textures and add only (non-negative factors: the trees of offline/ist are), for
// the fused shader (8-bit RGB textures of one size, per-channel materials, at most
// SEPAL_TREE_MAX_TILES terms, 2 + bases texture units); the multipass paths take any
// .sepal asset. The fused shader draws the mesh as given: no per-vertex repairs (the
// multipass paths count and repair, sepal_material.h).
//
// Thread safety: sepal_tree_parse keeps no state (distinct outputs; a parsed tree is only read
// afterwards and may be shared). sepal_tree_create, _destroy and _draw call GL: the thread
// whose context is current, one call at a time per context. sepal_tree_draw_cpu calls no
// GL: any threads at once with their own buffers.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_asset.h"
#include "sepal/sepal_material.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SEPAL_TREE_MAGIC "SEPALIST"
#define SEPAL_TREE_VERSION_MAJOR 1
#define SEPAL_TREE_VERSION_MINOR 0
#define SEPAL_TREE_MAX_BASES 8
#define SEPAL_TREE_MAX_BLEND_SIDE 1024
#define SEPAL_TREE_MAX_FILE_BYTES (256u << 20)

typedef struct sepal_tree_header {
    char magic[8];            // "SEPALIST"
    uint16_t version_major;   // readers refuse other majors
    uint16_t version_minor;
    uint32_t header_bytes;    // 64
    uint64_t file_bytes;      // the whole file
    uint32_t basis_count;     // 1..SEPAL_TREE_MAX_BASES
    uint32_t blend_width;     // powers of two, 1..SEPAL_TREE_MAX_BLEND_SIDE
    uint32_t blend_height;
    uint32_t crc;             // CRC-32 of the file with this field 0
    uint32_t reserved[6];     // 0
} sepal_tree_header;

typedef struct sepal_tree_basis {
    uint64_t asset_offset;  // multiple of 8
    uint64_t asset_bytes;
    uint64_t blend_offset;  // blend_width * blend_height bytes
    float blend_scale;      // the map's largest weight, folded into the asset (information)
    uint32_t reserved;      // 0
} sepal_tree_basis;

typedef struct sepal_tree_asset {
    sepal_tree_header header;
    sepal_tree_basis table[SEPAL_TREE_MAX_BASES];
    sepal_asset bases[SEPAL_TREE_MAX_BASES];       // parsed in place
    const uint8_t* blend[SEPAL_TREE_MAX_BASES];    // into the caller's bytes
} sepal_tree_asset;

// Validates the container and every embedded asset; out points into bytes.
sepal_result sepal_tree_parse(const void* bytes, size_t size, sepal_tree_asset* out, sepal_error* err);

#define SEPAL_TREE_MAX_TILES 32  // terms of all bases together, for the fused shader

typedef struct sepal_tree {
    sepal_caps caps;
    uint32_t basis_count;
    sepal_material bases[SEPAL_TREE_MAX_BASES];
    uint32_t blend_textures[SEPAL_TREE_MAX_BASES];  // LUMINANCE8 with MIP chain, repeat
    // Multipass composition: the running sum, copied from the framebuffer.
    uint32_t copy_texture;
    int copy_width, copy_height;
    int max_width, max_height;
    // GL ES 2 fused shader (0 when the tree does not qualify; fused_reason says why).
    uint32_t program_fused, atlas_g, atlas_h;
    uint32_t program_fullscreen;  // GL ES 2 composition
    int tiles, tile_n, atlas_cols, atlas_rows;
    float tile_scale[SEPAL_TREE_MAX_TILES][2][3], tile_bias[SEPAL_TREE_MAX_TILES][2][3];
    int tile_basis[SEPAL_TREE_MAX_TILES];
    float basis_ratio[SEPAL_TREE_MAX_BASES][3];
    char fused_reason[128];
} sepal_tree;

sepal_result sepal_tree_create(const sepal_caps* caps, const sepal_tree_asset* asset, int max_width, int max_height,
                               sepal_tree* out, sepal_error* err);
void sepal_tree_destroy(sepal_tree* t);

typedef struct sepal_tree_draw_desc {
    const sepal_tree* tree;
    const sepal_mesh* mesh;  // world space, with UVs
    const sepal_scene* scene;
    int width, height;
    float* scratch;          // sepal_draw_scratch_floats(vertex_count, light_count) floats
    size_t scratch_floats;
    sepal_draw_mode mode;    // MULTIPASS (GL ES 1.1, GL ES 2) or FUSED_PIXEL (GL ES 2)
} sepal_tree_draw_desc;

// Stats: sums over the bases' draws plus the composition's copies and full-screen passes.
sepal_result sepal_tree_draw(const sepal_tree_draw_desc* desc, sepal_draw_stats* stats, sepal_error* err);

// The CPU backend: color (width * height * 3 floats, linear, top row first) receives the
// sum; accum is width * height * 3 floats of scratch, depth width * height floats, and
// blend_rgba 4 * blend_width * blend_height bytes; scratch as sepal_cpu_scratch_floats.
typedef struct sepal_tree_cpu_desc {
    const sepal_tree_asset* asset;
    const sepal_mesh* mesh;
    const sepal_scene* scene;
    int width, height;
    float* color;
    float* accum;
    float* depth;
    uint8_t* blend_rgba;
    float* scratch;
    size_t scratch_floats;
    sepal_draw_stats* stats;  // optional
} sepal_tree_cpu_desc;
sepal_result sepal_tree_draw_cpu(const sepal_tree_cpu_desc* desc, sepal_error* err);

#ifdef __cplusplus
}
#endif
