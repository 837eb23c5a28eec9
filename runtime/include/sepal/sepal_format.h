// sepal_format.h - the .sepal asset format, defined once for the writer (offline/) and
// the reader (runtime/). Plain C structs; every integer and float is little-endian.
//
// File layout (versions 1 and 2):
//   sepal_fmt_header                       64 bytes, magic "SEPALBRD"
//   sepal_fmt_chunk[chunk_count]           24 bytes each: tag, CRC-32, offset, size
//   chunk payloads                       each at an 8-byte-aligned offset
// Chunks:
//   'MATL' exactly one   sepal_fmt_material
//   'TEXR' 1..32         sepal_fmt_texture followed by its MIP levels (level 0 first); each
//                        level is rows of width*channels*(bits/8) bytes, row 0 first, row 0
//                        being texture coordinate t = 0 (the order glTexImage2D takes)
//   'PLAN' exactly one   sepal_fmt_plan followed by pass_count sepal_fmt_pass
//   'DIFF' optional (v2) sepal_fmt_diffuse followed by its samples in its layout: the shape
//                        of a radiance material's diffuse part (see below)
//   'PROF' optional (2.4) sepal_fmt_profile: the device profile the bake judged it for
//   'META' optional      UTF-8 JSON for people and tools; the runtime ignores it
//   unknown tags are skipped (forward compatibility), but still checksummed.
// Bounds (enforced by the reader, respected by the writer): see SEPAL_FMT_MAX_*.
//
// Meaning: the material approximates f(wi, wo) ~= sum_k G_k(x) H_k(y) (Kautz-McCool),
// x and y from the parameterization and hemisphere map. A texture stores q in [0,1]
// per channel and means value = scale[c] * q + bias[c]. The pass plan adds and
// subtracts products of those stored values, each times a constant colour, into a
// framebuffer that holds [0,1]; the final `doublings` passes double the framebuffer.
// See sepal_material.h for how the runtime executes the plan.
// Version 2 adds radiance materials (SEPAL_MATERIAL_RADIANCE): the factors hold the
// reflected radiance per unit irradiance, f(wi, wo) cos(theta_i) - diffuse cos(theta_i)
// (usually capped where a display shows white), so a light contributes
//   E (sum_k G_k H_k) + E cos(theta_i) diffuse,      E = I / d^2 (0 below the horizon),
// instead of E cos(theta_i) f. The diffuse part, diffuse[c] times an optional profile
// P_c(cos theta_i, cos theta_o) in [0,1] (the DIFF chunk; 1 without it: rho_d / pi for a
// Lambert floor), costs no texture: one DIFFUSE pass whose vertex colour carries the cosine
// and the profile, evaluated per vertex like the texture coordinates. A version-1 file means
// what it always meant (flags 0, diffuse 0). Writers write 1.0 unless a version-2 feature
// is used, so older assets stay byte-identical; readers of 1.x refuse 2.x (major).
// Version 2.1 adds reciprocal materials (SEPAL_MATERIAL_RECIPROCAL: homomorphic
// factorization, McCool, Ang and Ahmad 2001): each term is G_k(x) H_k(y) G_k(x~), x~ the G
// coordinate of the swapped pair (wo, wi) (with vh: p(wo) q(h) p(wi), reciprocal by
// construction), drawn by SEPAL_OP_RECIPROCAL passes. The third lookup depends on the light
// but not on the pixel's texture coordinates, so the multipass backends evaluate it per
// vertex into the vertex colour, like the diffuse profile (GL ES 1.1 has two texture
// units); the CPU backend and the fused per-pixel shader evaluate it per pixel. Writers write
// 2.1 only for reciprocal assets; a 2.0 reader refuses them at the unknown op.
// Version 2.2 adds the axis parameterization (SEPAL_PARAM_AXIS: angles about the tangent,
// per vertex like iv, gs-half and vh). Writers write 2.2 only for axis assets; older readers
// refuse them at the unknown parameterization.
// Version 2.3 adds the light range to the material (a 96-byte MATL chunk; 64 bytes before,
// the new words read as 0): the white level the factors were capped at and the lighting the
// bake judged them under (the dimmest and brightest light's irradiance at the object, the
// cone of light directions, the lights at once). A light dimmer than irradiance_min shows
// the capped highlight as a flat grey plateau; the runtime counts such lights per frame
// (sepal_draw_stats.dim_lights). An older asset whose META holds "white_level" W reads with
// white_level W and irradiance_min 1/W (below it the cap no longer shows white). Writers
// write 2.3 only for assets with a light range; older readers refuse its MATL size.
// Version 2.4 adds the device profile (the PROF chunk, sepal_fmt_profile): the framebuffer
// bits, texture units, texture size limit and blend subtraction the bake judged the asset
// on (`sepal bake --target gles1:PROFILE`, docs/devices.md). The runtime compares it with
// the context's caps (sepal_profile_check) and counts frames drawn on a weaker context
// (sepal_draw_stats.weaker_context). An asset without the chunk was judged for the default
// profile: SEPAL_FMT_DEFAULT_PROFILE_BITS per channel, SEPAL_FMT_DEFAULT_PROFILE_UNITS
// units, its own largest texture, blend subtraction. Writers write 2.4 (and the chunk) only
// for assets baked for another profile, so default bakes stayed byte-identical (until 2.5); older readers
// skip the chunk (unknown tags are skipped) and read the rest as before.
// Version 2.5 stores the diffuse profile in 16 bits (sepal_fmt_diffuse.layout): per channel
// (RGB_U16) or, when its three channels are equal, once (GREY_U16): 512 or 1536 bytes for
// the default 16 x 16 profile where RGB floats took 3072, with a step of 1/65535 against the
// 8-bit framebuffer's 1/255. Writers write 2.5 for every asset with a profile (they no longer
// write RGB_F32); readers take all three layouts, RGB_F32 in any version 2 file. A 2.4 reader
// refuses a 16-bit profile (the layout word was reserved, 0).
// Version 2.6 adds the gs-mirror parameterization (SEPAL_PARAM_GS_MIRROR: gs-half's
// Gram-Schmidt frame about the mirror direction of wi instead of h, per vertex like
// gs-half). Writers write 2.6 only for gs-mirror assets; older readers refuse them at the
// unknown parameterization.
// Version 2.7 adds the horizon window of radiance materials (sepal_fmt_material.horizon,
// c0 in (0, 1]): the factors hold g / w(cos theta_i) with w(c) = min(1, c / c0), and the
// backends multiply E by w (the multipass ones in the vertex colour, per vertex), so a
// light contributes
//   E w(cos theta_i) (sum_k G_k H_k) + E cos(theta_i) diffuse.
// Why: f cos(theta_i) falls to 0 at the horizon, a fall no product of two textures makes
// (their last texels are what a lit crescent ends on), while w is computed from the light
// itself; over cos(theta_i) < c0 the factors hold f c0, bounded and smooth.
// Writers write 2.7 only for assets with a window; a 2.6 reader refuses them (the word was
// reserved, 0), and an asset without one means what it meant.
//
// Data only: constants, enums and the file's structs. The reader (sepal_asset_parse), the
// texture coordinates of the parameterizations and the checksum are in sepal_asset.h.
// Thread safety: constants and types only.
#pragma once
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SEPAL_FMT_MAGIC "SEPALBRD"
// The newest version this header reads and writes; readers also take major 1.
#define SEPAL_FMT_VERSION_MAJOR 2
#define SEPAL_FMT_VERSION_MINOR 7
// The minor version that introduced reciprocal materials (2.1), the axis parameterization
// (2.2), the light range (2.3), the device profile (2.4), the 16-bit diffuse profile (2.5),
// the gs-mirror parameterization (2.6) and the horizon window (2.7); other version-2
// assets are 2.0.
#define SEPAL_FMT_VERSION_MINOR_RECIPROCAL 1
#define SEPAL_FMT_VERSION_MINOR_AXIS 2
#define SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE 3
#define SEPAL_FMT_VERSION_MINOR_PROFILE 4
#define SEPAL_FMT_VERSION_MINOR_DIFFUSE16 5
#define SEPAL_FMT_VERSION_MINOR_MIRROR 6
#define SEPAL_FMT_VERSION_MINOR_HORIZON 7
// The MATL chunk's size before 2.3 (the material up to and including diffuse).
#define SEPAL_FMT_MATERIAL_BYTES_V2 64u
#define SEPAL_FMT_VERSION_MAJOR_OLDEST 1

#define SEPAL_FMT_MAX_FILE_BYTES (64u << 20)
#define SEPAL_FMT_MAX_CHUNKS 64
#define SEPAL_FMT_MAX_TEXTURES 32
#define SEPAL_FMT_MAX_TERMS 16
#define SEPAL_FMT_MAX_TEXTURE_SIDE 1024
#define SEPAL_FMT_MAX_LEVELS 11
#define SEPAL_FMT_MAX_PASSES 256
#define SEPAL_FMT_MAX_DOUBLINGS 16
#define SEPAL_FMT_MAX_META_BYTES (1u << 20)
// Largest |scale| and |bias| of a texture, and largest colour ratio and diffuse part: a
// term's G x H stays below 4e30, sixteen terms times a ratio below 1e38, so every backend's
// f is a finite float (FLT_MAX is 3.4e38). Far above any BRDF (a mirror-like Ward peaks
// near 1e5 /sr).
#define SEPAL_FMT_MAX_FACTOR 1e15f
#define SEPAL_FMT_MAX_RATIO 1e6f

#define SEPAL_FMT_TAG(a, b, c, d) \
    ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))
#define SEPAL_FMT_TAG_MATERIAL SEPAL_FMT_TAG('M', 'A', 'T', 'L')
#define SEPAL_FMT_TAG_TEXTURE SEPAL_FMT_TAG('T', 'E', 'X', 'R')
#define SEPAL_FMT_TAG_PLAN SEPAL_FMT_TAG('P', 'L', 'A', 'N')
#define SEPAL_FMT_TAG_META SEPAL_FMT_TAG('M', 'E', 'T', 'A')
#define SEPAL_FMT_TAG_DIFFUSE SEPAL_FMT_TAG('D', 'I', 'F', 'F')
#define SEPAL_FMT_TAG_PROFILE SEPAL_FMT_TAG('P', 'R', 'O', 'F')
#define SEPAL_FMT_MAX_DIFFUSE_SIDE 32
// Reciprocal materials (2.1): the runtime keeps a copy of each term's G texture (level 0,
// 8 bits) for the per-vertex third lookup, so both are bounded: McCool's published factors
// are 64x64, one term.
#define SEPAL_FMT_MAX_RECIPROCAL_SIDE 64
#define SEPAL_FMT_MAX_RECIPROCAL_TERMS 2

// Parameterizations (NOTES.md section 1; offline/factor/param.h). Per-vertex (GL ES 1.1)
// paths can use iv, gs-half, vh, axis and gs-mirror; rusinkiewicz and elev-azim need per-pixel
// evaluation (shaders or the CPU).
typedef enum sepal_param {
    SEPAL_PARAM_IV = 0,            // x = wi, y = wo
    SEPAL_PARAM_GS_HALF = 1,       // Gram-Schmidt half/difference (Kautz-McCool eq. 6)
    SEPAL_PARAM_VH = 2,            // x = wo, y = h (Lawrence 2004)
    SEPAL_PARAM_RUSINKIEWICZ = 3,  // per pixel only
    SEPAL_PARAM_ELEV_AZIM = 4,     // per pixel only
    // Angles about the tangent (version 2.2): G at (alpha_i, alpha_o), H at (beta_i, beta_o),
    // alpha = asin(w.x), beta = atan2(w.y, w.z), u = angle / pi + 1/2.
    SEPAL_PARAM_AXIS = 5,
    // Gram-Schmidt mirror/view (version 2.6): G at r = (-wi.x, -wi.y, wi.z), the mirror
    // direction of wi; H at wo in the frame (t', s', r), t' = norm(t - (r.t) r), s' = r x t'
    // (gs-half's frame about r instead of h). A lobe about the mirror direction (Phong,
    // Lafortune) is one product here: G carries cos(theta_i), H the lobe.
    SEPAL_PARAM_GS_MIRROR = 6,
    SEPAL_PARAM_COUNT = 7
} sepal_param;

typedef enum sepal_hemi_map { SEPAL_MAP_XY = 0, SEPAL_MAP_PARABOLIC = 1, SEPAL_MAP_COUNT = 2 } sepal_hemi_map;

typedef enum sepal_color_mode {
    SEPAL_COLOR_PER_CHANNEL = 0,  // each channel factored on its own
    SEPAL_COLOR_LUMINANCE = 1,    // one channel (luminance), times the material's ratio per channel
    SEPAL_COLOR_COUNT = 2
} sepal_color_mode;

typedef enum sepal_tex_role { SEPAL_ROLE_G = 0, SEPAL_ROLE_H = 1, SEPAL_ROLE_COUNT = 2 } sepal_tex_role;

typedef enum sepal_pass_op {
    SEPAL_OP_PRODUCT = 0,   // colour * tex0 * tex1
    SEPAL_OP_TEXTURE = 1,   // colour * tex0
    SEPAL_OP_CONSTANT = 2,  // colour
    // colour * tex0(x) * tex1(y) * tex0(x~) (version 2.1, reciprocal materials only): tex0 is
    // a term's G texture, read a second time at x~ (the G coordinate of the swapped pair
    // (wo, wi)), tex1 the same term's H texture; always added.
    SEPAL_OP_RECIPROCAL = 3,
    SEPAL_OP_DIFFUSE = 4,   // colour, times cos(theta_i) (version 2): a radiance material's
                            // diffuse part; no texture
    SEPAL_OP_COUNT = 5
} sepal_pass_op;

typedef enum sepal_blend {
    SEPAL_BLEND_ADD = 0,       // framebuffer += source
    SEPAL_BLEND_SUBTRACT = 1,  // framebuffer -= source (reverse subtract)
    SEPAL_BLEND_COUNT = 2
} sepal_blend;

#define SEPAL_FMT_NO_TEXTURE 0xFFFFu

typedef struct sepal_fmt_header {
    char magic[8];           // "SEPALBRD"
    uint16_t version_major;  // readers refuse other majors
    uint16_t version_minor;  // readers accept any minor of their major
    uint32_t header_bytes;   // 64
    uint64_t file_bytes;     // the whole file
    uint32_t chunk_count;
    uint32_t flags;          // 0
    uint32_t header_crc;     // CRC-32 of these 64 bytes (this field 0) and the chunk table
    uint8_t reserved[28];    // 0
} sepal_fmt_header;

typedef struct sepal_fmt_chunk {
    uint32_t tag;
    uint32_t crc;     // CRC-32 (ISO-HDLC, as zlib) of the payload
    uint64_t offset;  // from the start of the file, multiple of 8
    uint64_t size;    // payload bytes
} sepal_fmt_chunk;

typedef struct sepal_fmt_material {
    uint32_t param;       // sepal_param
    uint32_t map;         // sepal_hemi_map
    uint32_t color_mode;  // sepal_color_mode
    uint32_t terms;       // 1..SEPAL_FMT_MAX_TERMS
    uint32_t channels;    // 1 (achromatic) or 3
    uint32_t reserved0;   // 0
    // Cosine-weighted RMS radiance error of this asset (Kautz-McCool metric), of the
    // float factors it came from, and relative to the BRDF's RMS; NaN when not measured.
    float error_quantized;
    float error_float;
    float error_relative;
    // Per-channel multiplier of f: a luminance factorization (1 channel) times its colour;
    // (1, 1, 1) for per-channel factorizations. 0..SEPAL_FMT_MAX_RATIO, not all 0.
    float ratio[3];
    // Version 2 (0 in version 1): SEPAL_MATERIAL_* bits, and the diffuse part of a radiance
    // material (a constant BRDF per channel, 0..SEPAL_FMT_MAX_RATIO; drawn by the plan's DIFFUSE pass).
    // Version 1 files hold 0 in these words (reserved there).
    uint32_t flags;
    float diffuse[3];
    // Version 2.3 (0 when the chunk is the older 64 bytes): the light range. All finite, >= 0.
    float white_level;     // cap on f cos(theta_i) per steradian the factors hold; 0: none or unknown
    float irradiance_min;  // the dimmest light (I / d^2 at the object, largest channel) it holds for; 0: undeclared
    float irradiance_max;  // the brightest light the bake judged it under; >= irradiance_min
    float cone_degrees;    // light directions within this of the scene's up (90: any above the horizon), 0..180
    uint32_t max_lights;   // lights at once it was judged under, 0..SEPAL_MAX_LIGHTS (0: undeclared)
    // Version 2.7 (0 before): the horizon window's c0 (see the top), 0 (none) or in (0, 1];
    // radiance materials only.
    float horizon;
    uint32_t reserved1[2]; // 0
} sepal_fmt_material;

// sepal_fmt_material.flags
#define SEPAL_MATERIAL_RADIANCE 1u  // the factors include cos(theta_i) (see the top)
// Version 2.1: each term is G_k(x) H_k(y) G_k(x~) (see the top). Not with RADIANCE; every
// pass is a RECIPROCAL one (or the all-zero plan's one CONSTANT pass); at most
// SEPAL_FMT_MAX_RECIPROCAL_TERMS terms, G textures at most SEPAL_FMT_MAX_RECIPROCAL_SIDE.
#define SEPAL_MATERIAL_RECIPROCAL 2u
#define SEPAL_MATERIAL_KNOWN_FLAGS 3u

typedef struct sepal_fmt_texture {
    uint32_t width, height;  // powers of two, 1..SEPAL_FMT_MAX_TEXTURE_SIDE
    uint32_t levels;         // 1, or the full MIP chain down to 1x1
    uint32_t channels;       // 1 (luminance) or 3 (RGB)
    uint32_t bits;           // 8 or 16 per channel (16: little-endian uint16)
    uint32_t role;           // sepal_tex_role
    uint32_t term;           // 0..terms-1
    uint32_t reserved0;      // 0
    float scale[4];          // value = scale[c] * q + bias[c], q in [0,1]; |scale|, |bias| <= SEPAL_FMT_MAX_FACTOR
    float bias[4];
    uint64_t data_bytes;     // sum over levels
} sepal_fmt_texture;

typedef struct sepal_fmt_plan {
    uint32_t pass_count;   // 1..SEPAL_FMT_MAX_PASSES
    uint32_t doublings;    // final framebuffer doublings, 0..SEPAL_FMT_MAX_DOUBLINGS
    // Largest partial sum of the plan at unit irradiance (the writer guarantees <= 1);
    // the runtime divides its per-frame exposure by it.
    float peak_partial_sum;
    uint32_t reserved[5];  // 0
} sepal_fmt_plan;

// The diffuse profile (version 2, radiance materials with a diffuse part): side x side RGB
// samples of P(cos theta_i, cos theta_o) in [0,1], sample (i, j) at cos theta_i = i / (side
// - 1), cos theta_o = j / (side - 1), row j = 0 first; looked up bilinearly (clamped).
// Stored in one of the layouts below (the word was reserved, 0, before 2.5):
typedef enum sepal_fmt_diffuse_layout {
    SEPAL_FMT_DIFFUSE_RGB_F32 = 0,   // side*side*3 floats, R G B per sample (2.0..2.4)
    SEPAL_FMT_DIFFUSE_RGB_U16 = 1,   // side*side*3 uint16 q, the value q / 65535 (2.5)
    SEPAL_FMT_DIFFUSE_GREY_U16 = 2,  // side*side uint16 q, R = G = B = q / 65535 (2.5)
    SEPAL_FMT_DIFFUSE_LAYOUT_COUNT
} sepal_fmt_diffuse_layout;

typedef struct sepal_fmt_diffuse {
    uint32_t side;         // 2..SEPAL_FMT_MAX_DIFFUSE_SIDE
    uint32_t layout;       // sepal_fmt_diffuse_layout
    uint32_t reserved[2];  // 0
} sepal_fmt_diffuse;

// The device profile the asset was judged for (version 2.4, the PROF chunk; 48 bytes).
// Without the chunk the reader fills the default profile (see the top).
#define SEPAL_FMT_DEFAULT_PROFILE_BITS 8
#define SEPAL_FMT_DEFAULT_PROFILE_UNITS 2
#define SEPAL_FMT_PROFILE_NAME_BYTES 16
typedef struct sepal_fmt_profile {
    char name[SEPAL_FMT_PROFILE_NAME_BYTES];  // NUL-terminated, [a-z0-9-], not empty
    uint32_t red_bits, green_bits, blue_bits;  // the framebuffer the bake rounded every pass to, 1..8
    uint32_t texture_units;     // units the plan was judged with, 1..32
    uint32_t max_texture_size;  // the side the bake held every texture to: a power of two, 1..SEPAL_FMT_MAX_TEXTURE_SIDE
    uint32_t flags;             // SEPAL_PROFILE_* bits
    uint32_t reserved[2];       // 0
} sepal_fmt_profile;
// sepal_fmt_profile.flags
#define SEPAL_PROFILE_BLEND_SUBTRACT 1u  // judged with blend subtraction (else by inversion)
#define SEPAL_PROFILE_KNOWN_FLAGS 1u

typedef struct sepal_fmt_pass {
    uint16_t op;         // sepal_pass_op; a PRODUCT is tex0 = a term's G times tex1 = its H
    uint16_t blend;      // sepal_blend
    uint16_t tex0;       // texture index or SEPAL_FMT_NO_TEXTURE
    uint16_t tex1;
    float color[3];      // per-channel constant in [0,1], times the light's irradiance
                         // (E cos(theta_i); E alone for a radiance material's textured
                         // and constant passes)
    uint32_t rgb_scale;  // 1, 2 or 4: GL_RGB_SCALE of the pass's last combiner stage
} sepal_fmt_pass;

#ifdef __cplusplus
}
#endif
