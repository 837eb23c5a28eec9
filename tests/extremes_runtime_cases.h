// The runtime's extreme cases, shared by tests/extremes_test.cpp (the checks) and
// tests/bench/extremes.cpp (the contact sheet): scenes with chosen per-vertex
// frames (grazing, below the horizon, h near t, h = n), a mesh with broken vertices,
// assets with extreme content, and rendering on every backend and fallback mask.
// No doctest here: the contact sheet links this file too. Failures come back as
// ok = false with the reason.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bake/asset_file.h"
#include "asset_fixtures.h"
#include "brdf/brdf.h"
#include "util/image.h"
#include "common/scene_flags.h"
#include "sepal/sepal_material.h"

namespace extremes {

using test_fx::ConstantBrdf;

// ---- backends --------------------------------------------------------------------------
struct Backend {
    std::string name;        // e.g. "gles1", "gles1 -subtract", "cpu"
    bool cpu = false;
    int gles = 1;
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    uint32_t mask = 0;       // SEPAL_MASK_* bits forcing the fallback paths
    bool float_target = false;  // GL ES 2 into a half-float target (read back as floats)
    bool per_vertex() const { return !cpu && mode != SEPAL_MODE_FUSED_PIXEL; }
};
// Every backend, and the masks that force the GL ES 1.1 / GL ES 2 fallbacks: gles1
// (two units, blend subtract), gles1 without blend subtract (inversion), gles1 with one
// texture unit (copy texture), both, gles1 with fbo+npot hidden, gles2 multipass with
// and without blend subtract, gles2 multipass into a half-float target, gles2-fused,
// gles2-fused-pixel, cpu.
std::vector<Backend> all_backends();

struct Frame {
    bool ok = false;
    std::string err;        // why not ok (a refusal names the reason)
    sepal::Image image;     // RGB: GL as read back (0..1); float target and CPU: linear radiance
    sepal_draw_stats stats{};
    bool finite = false;    // every value finite (trivially true for 8-bit GL read-backs)
    std::string path;       // the GL path taken, as the port describes it
};
Frame render(const Backend& b, const std::vector<uint8_t>& asset_bytes, const sepal_ports::SceneSetup& s);

// Display values: a copy clamped to [0, 1] (what an 8-bit framebuffer shows); NaN -> 0.
sepal::Image display(const sepal::Image& linear);
bool all_finite(const sepal::Image& img);

// ---- scenes ----------------------------------------------------------------------------
// Points mesh at the setup's own vectors again (after a copy of a SceneSetup).
void rebind(sepal_ports::SceneSetup* s);

// A camera-facing quad (a cells x cells grid, geometric normal towards the camera) whose
// per-vertex frames are chosen so that, at every vertex, the light and the eye are at the
// requested angles from the shading normal:
//   kAtEye: a point light at the eye, theta_i = theta_o = theta (wi = wo, retro-
//     reflection) with the view along the tangent's azimuth: h is theta from n and
//     90 - theta from t (89.9 and 89.99 degrees: h close to t, gs-half's singularity;
//     0 degrees: h = n, rusinkiewicz's pole).
//   kDirectional: a directional light perpendicular to the view; n solved per vertex so
//     that theta_i and theta_o are exact (grazing 89.9/89.9; light below the horizon
//     90.1; view below the horizon, a frame whose normal faces away from the eye, 120).
//   kMirror: a directional light at 2 theta from the view, n = normalize(wi + wo) per
//     vertex: h = n exactly (rusinkiewicz's pole); theta_i = theta_o = theta at the
//     centre, within about 3 degrees of it elsewhere (the eye's direction varies by up to
//     6 degrees across the quad, and one light cannot keep a mirror angle fixed).
// The quad spans 0.6 x 0.6 at 4 units, seen with a 10-degree field of view.
// Light intensity: the requested irradiance at the centre when the light is above the
// horizon, so grazing images are not black just because cos(theta_i) is 0.0017.
enum class QuadLight { kAtEye, kDirectional, kMirror };
struct QuadConfig {
    QuadLight light = QuadLight::kDirectional;
    double theta_i = 45, theta_o = 45;  // degrees from the shading normal
    double irradiance = 1;              // at the centre, when the light is above the horizon
};
sepal_ports::SceneSetup quad_scene(const QuadConfig& q, int width = 96, int height = 96, int cells = 24);

// The sphere of the material tests (64x32), 128x96, `lights` lights alternating point
// and directional (material_fixtures' test_scene, without doctest).
sepal_ports::SceneSetup sphere_scene(int lights, int width = 128, int height = 96);

// The sphere with broken vertices and extra zero-area triangles, and what the runtime
// must report for it. `clean` is the same mesh as the runtime is documented to treat it:
// triangles touching a bad vertex removed, unusable tangents replaced by the fallback
// (runtime/src/common.cpp), zero-area triangles dropped (they cover nothing anyway).
struct BrokenMesh {
    sepal_ports::SceneSetup broken, clean;
    int fallback_tangents = 0;  // zero (4), parallel to n (4), NaN xyz (3), NaN or inf w (2)
    int bad_vertices = 0;       // NaN normal, zero normal, NaN position, inf position
    int skipped_triangles = 0;  // triangles touching those (counted here independently)
    int zero_area_triangles = 0;  // appended: repeated corners and collinear ones
};
BrokenMesh broken_sphere(int lights);

// ---- assets ----------------------------------------------------------------------------
// A smooth specular-like lobe around h = n (G) times a gentle H, non-negative, one term,
// side x side textures with full MIP chains: any side 1..1024 that is a power of two.
// For rusinkiewicz, H is symmetric about the pole, as an isotropic BRDF's is.
sepal::AssetData lobe_asset(sepal_param param, int side, int bits = 8);
// f = value everywhere above the horizon: G = H = const (side x side; 1 gives 1x1).
sepal::AssetData constant_asset(sepal_param param, int side, double value);
// f = 0.3 everywhere plus a narrow spike up to 1e4 per steradian around h = n (16-bit
// textures; the plan needs 14 doublings).
sepal::AssetData huge_peak_asset();
// f ~ 1e-8 per steradian (the lobe asset scaled down).
sepal::AssetData tiny_asset();
// Every texel 0: f = 0 (hand-built: the encoder refuses an all-zero plan today).
sepal::AssetData zero_asset();
// A signed 2-term asset (every kind of plan pass: subtractions, constants).
sepal::AssetData signed_asset(sepal_param param);
// Bakes a spec (one term, NMF, the given parameterization and side) through the offline
// library; false with the encoder's reason when it refuses.
bool bake_asset(const std::string& spec, sepal_param param, int res, sepal::AssetData* out, std::string* err);
bool encode(const sepal::AssetData& a, std::vector<uint8_t>* bytes, std::string* err);


}  // namespace extremes
