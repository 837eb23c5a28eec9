// sepal_sampler.h - importance sampling of a BRDF for Monte Carlo renderers: the sampler
// file format (defined once here for the writer, offline/sampling/sampler_file.cpp, and the
// reader, runtime/src/sampler.cpp) and a small C API: sample, pdf, eval.
//
// Usage (a path tracer; `bytes` holds a file written by `sepal sampler SPEC -o FILE`):
//   sepal_sampler smp; sepal_error err = {SEPAL_OK, ""};
//   if (sepal_sampler_parse(bytes, size, &smp, &err) != SEPAL_OK) { puts(err.message); }
//   sepal_sampler_view view;                     // per outgoing direction, caller-owned
//   sepal_sampler_set_view(&smp, wo, &view);      // wo in the local frame, towards the eye
//   float u[2] = {0.25f, 0.5f}, wi[3], pdf;       // u in [0,1)^2: random, stratified, QMC
//   if (sepal_sampler_sample(&view, u, wi, &pdf) == 1)
//       L += Li(wi) * f(wi, wo) * wi[2] / pdf;    // f: the BRDF (or sepal_sampler_eval)
//
// Frame: directions are unit vectors in the local frame (normal n = +z, tangent t = +x,
// s = +y), both pointing away from the surface, as in offline/brdf/brdf.h.
// Rules: as the rest of the runtime (sepal_rt.h): no allocation (the parsed sampler points
// into the caller's bytes, which must outlive it; the view is a fixed-size struct), no
// exceptions, errors as return codes with a message. sample/pdf/eval are thread-safe on a
// shared sampler (each thread its own view) and never return NaN or inf.
//
// Meaning of every kind: sample() draws wi from a density over the whole sphere of
// directions; pdf(wi) is exactly that density (per steradian; it integrates to 1 over the
// sphere, tested). Draws below the horizon are part of the density and come back with
// return value 0 (the estimator adds 0 for them: the BRDF is 0 there). Kinds:
//   FACTORED   Lawrence et al. 2004: f(wi,wo) cos(theta_i) |dwi/dwp| ~= sum_l F_l(wo)
//              u_l(theta_p) v_l(phi_p) in the view/half-angle (wp = h) or incident (wp = wi)
//              parameterization; term l chosen with probability F_l(wo) / sum F, then
//              phi_p and z = cos(theta_p) by inverting 1D CDFs, then wi (for h: the mirror
//              of wo about h, Jacobian 1/(4 wi.h)). Format 1.2: wp in angles about the
//              tangent or bitangent instead (desc.axis), for anisotropic lobes; format
//              1.3: about them in a frame turned with the view, or centred on the mirror
//              cone of wo (grooves, cylinders).
//              With a defensive share e, a cosine
//              sample is drawn instead with probability e (the factored density can be 0
//              where f cos is not; the mixture keeps the estimator unbiased).
//              Format 1.1: a Lambert part D (desc.diffuse, per steradian) is kept out of
//              the terms (they fit (f - D) cos), and cosine samples, exact for it, get the
//              share of the view's albedo it holds: e(wo) = e + (1 - e) pi D / (pi D +
//              sum_l F_l(wo)) (luminance). Under a sun a BRDF-only sampler cannot follow,
//              a paint's diffuse part is then sampled as well as cosine sampling does.
//   COSINE     cosine-weighted hemisphere, pdf = cos(theta_i)/pi.
//   LOBES      a mixture of analytic lobes (diffuse cosine, Phong/Lafortune lobes about the
//              axis C o wo, Ashikhmin-Shirley and Ward/Beckmann half-vector lobes), chosen
//              with per-view probabilities (lobe weight x the lobe's integral at wo).
//   TABULATED  Matusik 2003: for the nearest of a grid of views, a marginal CDF over
//              theta_i bins and conditional CDFs over phi_i bins (cosine share as above).
// eval() returns the sampler's own reconstruction of f(wi,wo) cos(theta_i) for FACTORED
// samplers (RGB with colour tables, the luminance in all three channels without), and 0
// (unsupported) for the other kinds.
// Cost (tests/bench/sampling.cpp): sample + pdf 170 to 180 ns on one core (the pdf sums every
// term: 8 by default, 16 about t or s and their mirror axes); a factored sampler of the
// paper's resolutions is 5..40 KB, 42 KB about t or s (192 x 96 bins, 16 terms), 59 KB about
// a mirror axis (20 x 24 views).
// Limits: see SEPAL_SMP_MAX_*; a view whose wo is at or below the horizon, or whose terms
// are all 0, draws cosine samples only (FACTORED, TABULATED) and reports it in `fallback`.
//
// Thread safety: sepal_sampler_parse keeps no state (distinct outputs); a parsed sampler is
// only read afterwards, so any threads may share it, each with its own sepal_sampler_view
// (set_view writes the view; sample, pdf and eval only read it).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_asset.h"  // sepal_crc32
#include "sepal/sepal_rt.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---- file format -------------------------------------------------------------------------
// Layout (version 1), every integer and float little-endian:
//   sepal_smp_header   64 bytes, magic "SEPALSMP"; header_crc covers it (this field 0)
//   sepal_smp_desc     64 bytes: the kind's counts
//   payload            float32 arrays in the order below, each starting at a multiple of
//                      8 bytes (zero padding); payload_crc covers the desc and the payload.
// The reader computes every array's offset from the counts and requires the file to end
// exactly after the last one. Arrays by kind (T = terms, To = n_theta_o, Po = n_phi_o,
// Tp = n_theta_p, Pp = n_phi_p, V = To x Po views, row-major with phi fastest):
//   FACTORED   z_edges[Tp+1]   c1 bin edges (desc.axis): z_edges[0] = 1 > ... > z_edges[Tp] =
//                              0 (N: cos theta_p) or -1 (T, S: wp.t or wp.s)
//              F[T][To][Po]    term weights at the view bin centres (>= 0), bilinear in
//                              (theta_o, phi_o), phi periodic, theta clamped
//              u_cdf[T][Tp+1]  CDF of term l over the z bins (0 ... 1, non-decreasing)
//              v_cdf[T][Pp+1]  CDF over c2 bins: phi_p in [j, j+1) * 2 pi / Pp (N), or
//                              the angle in [j, j+1) * pi / Pp - pi/2 (T, S)
//              if colour: ca[3][To][Po], cb[3][Tp], cc[3][Pp]: f_c / f_lum ~= ca cb cc
//   COSINE     nothing
//   LOBES      sepal_smp_lobe[lobe_count]
//   TABULATED  z_edges[Tp+1]  (cos(theta_i) bin edges), then per view:
//              marginal[Tp+1], conditional[Tp][Pp+1]
#define SEPAL_SMP_MAGIC "SEPALSMP"
#define SEPAL_SMP_VERSION_MAJOR 1
#define SEPAL_SMP_VERSION_MINOR 3  // 1.1: desc.diffuse; 1.2: desc.axis; 1.3: the view and
                                    // mirror axes (T_VIEW ... S_MIRROR). The writer writes the
                                    // lowest version that holds the file's fields

#define SEPAL_SMP_MAX_FILE_BYTES (16u << 20)
#define SEPAL_SMP_MAX_TERMS 64
#define SEPAL_SMP_MAX_VIEW_SIDE 128
#define SEPAL_SMP_MAX_DIR_SIDE 1024
#define SEPAL_SMP_MAX_LOBES 16
#define SEPAL_SMP_MAX_DIFFUSE 1e6f

typedef enum sepal_sampler_kind {
    SEPAL_SAMPLER_FACTORED = 0,
    SEPAL_SAMPLER_COSINE = 1,
    SEPAL_SAMPLER_LOBES = 2,
    SEPAL_SAMPLER_TABULATED = 3,
    SEPAL_SAMPLER_KIND_COUNT = 4
} sepal_sampler_kind;

typedef enum sepal_smp_param {
    SEPAL_SMP_PARAM_HALF = 0,      // wp = h = norm(wi + wo) (the paper's wh)
    SEPAL_SMP_PARAM_INCIDENT = 1,  // wp = wi
    SEPAL_SMP_PARAM_COUNT = 2
} sepal_smp_param;

typedef enum sepal_smp_phi {
    SEPAL_SMP_PHI_ABSOLUTE = 0,  // phi_p from the tangent (any BRDF; the paper's)
    SEPAL_SMP_PHI_VIEW = 1,      // phi_p from phi_o (isotropic BRDFs: F depends on theta_o only)
    SEPAL_SMP_PHI_COUNT = 2
} sepal_smp_phi;

typedef enum sepal_smp_axis {
    // Coordinates of wp (FACTORED). Both pairs have dOmega = dc1 dc2, so a bin's density
    // per steradian is its mass over its (c1, c2) area.
    SEPAL_SMP_AXIS_N = 0,  // polar about the normal: c1 = z = cos(theta_p) in [0, 1] (edges
                           // 1 down to 0), c2 = phi_p in [0, 2 pi) (the paper's)
    SEPAL_SMP_AXIS_T = 1,  // about the tangent t: c1 = wp.t in [-1, 1] (edges 1 down to -1),
                           // c2 = atan2(wp.s, wp.n) in [-pi/2, pi/2] (upper hemisphere).
                           // Grooves and cylinders along t (Poulin-Fournier) separate here.
    SEPAL_SMP_AXIS_S = 2,  // about s: c1 = wp.s, c2 = atan2(wp.t, wp.n). A lobe sharp across s
                           // (Ward ay << ax) gets the explicit c1 edges where it is sharp.
    // Format 1.3, half-vector parameterization only: as T and S, but c2 is measured from
    // half the view's own angle about the axis, b = atan2(wo.s, wo.n) / 2 (T) or
    // atan2(wo.t, wo.n) / 2 (S): wp is rotated by -b about the axis first (a rotation keeps
    // c1 and dOmega). Mirrors off cylinders along t have h at the cylinder normal psi, and
    // the lit, visible normals span psi in [b - pi/4, b + pi/4] for every view: a window
    // that moves with wo about t is fixed in these coordinates.
    SEPAL_SMP_AXIS_T_VIEW = 3,
    SEPAL_SMP_AXIS_S_VIEW = 4,
    // Format 1.3, incident parameterization only: as T and S, but c1 is a = wi.t (or wi.s)
    // mapped linearly on each side of the mirror cone a = m = -wo.t (-wo.s; clamped to
    // +-0.999): c1 = (a - m) / (1 - m) for a >= m, (a - m) / (1 + m) below, so the cone sits
    // at c1 = 0 for every view, where the edges are dense; the density over wi is the one
    // over (c1, c2) times dc1/da. A Phong lobe about the mirrors of wo off cylinders along
    // t has about the same width in a along the whole cone: at each view it nearly
    // separates in (c1, c2), and the cone no longer moves across views.
    SEPAL_SMP_AXIS_T_MIRROR = 5,
    SEPAL_SMP_AXIS_S_MIRROR = 6,
    SEPAL_SMP_AXIS_COUNT = 7
} sepal_smp_axis;

typedef enum sepal_smp_lobe_type {
    SEPAL_LOBE_COSINE = 0,      // cos(theta_i)/pi; no parameters
    SEPAL_LOBE_PHONG_AXIS = 1,  // p[0..2] = C, p[3] = n: density (n+1)/(2 pi) (a.wi)^n about
                                // a = norm(C o wo); selection weight x |C o wo|^n 2 pi/(n+1)
    SEPAL_LOBE_HALF_AS = 2,     // p[0] = nu, p[1] = nv: h density sqrt((nu+1)(nv+1))/(2 pi)
                                // (n.h)^(nu cos^2 phi_h + nv sin^2 phi_h) (A-S 2000; Blinn nu = nv)
    SEPAL_LOBE_HALF_WARD = 3,   // p[0] = ax, p[1] = ay: h density exp(-tan^2 theta_h (cos^2/ax^2 +
                                // sin^2/ay^2)) / (pi ax ay cos^3 theta_h) (Ward; Beckmann ax = ay = m)
    SEPAL_LOBE_TYPE_COUNT = 4
} sepal_smp_lobe_type;

typedef struct sepal_smp_header {
    char magic[8];           // "SEPALSMP"
    uint16_t version_major;  // readers refuse other majors
    uint16_t version_minor;
    uint32_t header_bytes;   // 64
    uint64_t file_bytes;     // the whole file
    uint32_t kind;           // sepal_sampler_kind
    uint32_t flags;          // 0
    uint32_t payload_crc;    // CRC-32 (sepal_crc32) of the desc and the payload
    uint32_t header_crc;     // CRC-32 of these 64 bytes with this field 0
    uint8_t reserved[24];    // 0
} sepal_smp_header;

typedef struct sepal_smp_desc {
    uint32_t param;       // sepal_smp_param (FACTORED)
    uint32_t phi_frame;   // sepal_smp_phi (FACTORED, TABULATED)
    uint32_t n_theta_o;   // view grid: 1..SEPAL_SMP_MAX_VIEW_SIDE (FACTORED, TABULATED)
    uint32_t n_phi_o;     // 1..SEPAL_SMP_MAX_VIEW_SIDE; 1 with SEPAL_SMP_PHI_VIEW
    uint32_t n_theta_p;   // direction bins 1..SEPAL_SMP_MAX_DIR_SIDE (FACTORED, TABULATED)
    uint32_t n_phi_p;     // 1..SEPAL_SMP_MAX_DIR_SIDE
    uint32_t terms;       // FACTORED: 1..SEPAL_SMP_MAX_TERMS
    uint32_t lobe_count;  // LOBES: 1..SEPAL_SMP_MAX_LOBES
    uint32_t colour;      // FACTORED: 1 when the colour tables follow (eval supported)
    float defensive;      // FACTORED, TABULATED: share of cosine samples, 0..1
    uint32_t jacobian;    // FACTORED: 1 when the terms fit f cos |dwi/dwp| (eval divides it
                          // out), 0 when they fit f cos itself (the paper's variant)
    float diffuse[3];     // FACTORED, format 1.1: the Lambert part D per channel (1/sr,
                          // 0..1e6) kept out of the terms; 0 in 1.0 files (none)
    uint32_t axis;        // FACTORED, format 1.2: sepal_smp_axis (0 before 1.2); T and S
                          // need SEPAL_SMP_PHI_ABSOLUTE; T_VIEW and S_VIEW (1.3) also
                          // SEPAL_SMP_PARAM_HALF, T_MIRROR and S_MIRROR (1.3)
                          // SEPAL_SMP_PARAM_INCIDENT
    uint32_t reserved;
} sepal_smp_desc;

typedef struct sepal_smp_lobe {
    uint32_t type;  // sepal_smp_lobe_type
    float weight;   // >= 0 (finite); the lobes' weights are not all 0
    float p[6];     // parameters (see the type); unused ones 0
} sepal_smp_lobe;

// ---- reading -----------------------------------------------------------------------------
// A parsed sampler: arrays point into the caller's buffer (no copies, no allocation).
typedef struct sepal_sampler {
    sepal_smp_header header;
    sepal_smp_desc desc;
    uint32_t kind;
    const float* z_edges;
    const float* F;
    const float* u_cdf;
    const float* v_cdf;
    const float* colour_a;  // NULL without colour tables
    const float* colour_b;
    const float* colour_c;
    const sepal_smp_lobe* lobes;
    const float* tables;    // TABULATED: the per-view arrays
} sepal_sampler;

// Validates everything (magic, version, sizes against SEPAL_SMP_MAX_*, checksums, enums,
// finite values, CDFs from 0 to 1, non-decreasing, z edges from 1 down to 0) and fills out.
// Needs a 4-byte aligned buffer on a little-endian host.
sepal_result sepal_sampler_parse(const void* bytes, size_t size, sepal_sampler* out,
                                 sepal_error* err);

// ---- sampling ----------------------------------------------------------------------------
// Per outgoing direction state; fill with sepal_sampler_set_view, reuse for every sample
// with that wo (a pixel's samples share it).
typedef struct sepal_sampler_view {
    const sepal_sampler* sampler;
    float wo[3];
    float cos_phi, sin_phi;  // rotation of the view frame: about n by phi_o (SEPAL_SMP_PHI_VIEW),
                             // about the axis by b (SEPAL_SMP_AXIS_T_VIEW, S_VIEW)
    float mirror;            // the mirror cone's m = -wo.t or -wo.s (AXIS_T_MIRROR, S_MIRROR)
    float defensive;         // effective cosine share (1 when falling back)
    uint32_t count;          // components in cdf
    float cdf[SEPAL_SMP_MAX_TERMS + 1];  // component selection CDF for this view
    float weight[SEPAL_SMP_MAX_TERMS];   // component probabilities (cdf differences)
    float total;             // FACTORED: sum of F_l(wo), the reconstruction's scale
    float colour[3];         // FACTORED: ca_c(wo)
    uint32_t table;          // TABULATED: nearest view
    int fallback;            // 1: wo at or below the horizon or no mass: cosine only
} sepal_sampler_view;

// A NULL sampler or wo gives a cosine-only view (fallback 1); a NULL view is ignored. The
// functions below return -1 (sample), 0 (pdf, eval) for NULL arguments.
void sepal_sampler_set_view(const sepal_sampler* s, const float wo[3], sepal_sampler_view* v);
// Draws wi from u in [0,1)^2 (u[0] selects the component and is rescaled within it, so
// stratified and low-discrepancy points keep their structure). Returns 1 with wi above the
// horizon, 0 with wi at or below it (wi and *pdf still filled: part of the density, adds
// nothing to an estimate), -1 when no direction came out (a degenerate draw; *pdf = 0).
int sepal_sampler_sample(const sepal_sampler_view* v, const float u[2], float wi[3], float* pdf);
// The density of sample()'s draws at the unit direction wi, per steradian, whole sphere.
float sepal_sampler_pdf(const sepal_sampler_view* v, const float wi[3]);
// The reconstruction of f(wi, wo) cos(theta_i), RGB. Returns 1, or 0 with rgb = 0 when the
// kind has no reconstruction (see above) or wi is at or below the horizon.
int sepal_sampler_eval(const sepal_sampler_view* v, const float wi[3], float rgb[3]);

// Where each array lives: byte offsets from the start of the file and byte sizes (both 0 for
// arrays the kind or desc does not have; sizes may be NULL), for the writer and the reader
// alike. Returns the file size, or 0 when a count is out of range.
typedef enum sepal_smp_array {
    SEPAL_SMP_ARRAY_Z_EDGES = 0,
    SEPAL_SMP_ARRAY_F = 1,
    SEPAL_SMP_ARRAY_U_CDF = 2,
    SEPAL_SMP_ARRAY_V_CDF = 3,
    SEPAL_SMP_ARRAY_COLOUR_A = 4,
    SEPAL_SMP_ARRAY_COLOUR_B = 5,
    SEPAL_SMP_ARRAY_COLOUR_C = 6,
    SEPAL_SMP_ARRAY_LOBES = 7,
    SEPAL_SMP_ARRAY_TABLES = 8,
    SEPAL_SMP_ARRAY_COUNT = 9
} sepal_smp_array;
uint64_t sepal_sampler_layout(uint32_t kind, const sepal_smp_desc* d,
                              uint64_t offsets[SEPAL_SMP_ARRAY_COUNT],
                              uint64_t sizes[SEPAL_SMP_ARRAY_COUNT]);

#ifdef __cplusplus
}
#endif
