// Synthetic materials and rendering helpers shared by the runtime material tests.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "asset_fixtures.h"
#include "brdf/brdf.h"
#include "util/image.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "sepal/sepal_material.h"

namespace material_fx {

using TexFn = std::function<float(float u, float v, int channel)>;

// A texture of side n with the full MIP chain, q = fn(u, v) at texel centres.
sepal::AssetTexture make_texture(int n, uint32_t role, uint32_t term, float scale, const TexFn& fn,
                                 float bias = 0.0f, int channels = 3);
sepal_fmt_pass pass(sepal_pass_op op, sepal_blend blend, uint16_t t0, uint16_t t1, float color);
// The asset's bytes (REQUIREs that the writer, and so the reader, accepts it).
std::vector<uint8_t> encode(const sepal::AssetData& a);
using test_fx::base_asset;
using test_fx::ConstantBrdf;

struct Rendered {
    sepal::Image image;
    sepal_draw_stats stats{};
    std::string path;
};
// Renders an asset through the runtime, headless (REQUIREs success: any GL error fails).
Rendered render(const sepal::AssetData& a, uint32_t mask, const sepal_ports::SceneSetup& s,
                const sepal_ports::Rgba8Image* diffuse = nullptr, int gles_version = 1,
                sepal_draw_mode mode = SEPAL_MODE_MULTIPASS);
// f = G0 H0 + G1 H1 with G1, H1 signed (stored with a bias): every kind of pass.
sepal::AssetData signed_asset(sepal_param param = SEPAL_PARAM_GS_HALF);
// Renders an asset with the CPU backend.
sepal::Image render_cpu(const sepal::AssetData& a, const sepal_ports::SceneSetup& s,
                        const sepal_ports::Rgba8Image* diffuse = nullptr);
// 128x96, the named mesh, `lights` lights alternating point and directional.
sepal_ports::SceneSetup test_scene(const char* mesh, int lights);
// The largest channel value of an image (a test that the picture is lit at all).
double image_peak(const sepal::Image& im);

// A small bake of `spec` for runtime tests: one parameterization, method, factor resolution
// and term count, judged at judge_size; radiance: the format-2 fit (else factors of f).
// The bake's lighting before the light range: ranked on the default scene and its grazing
// twin, the white level 1.25 / their smallest lit irradiance (the declared range is made
// brighter than both so that they decide it), no held-out judging, the uniform fit (the
// display weight needs the range's brightest light). The goldens and the
// emulator's tolerances were set on such assets; the range is tested on its own
// (tests/offline/bake/light_range_test.cpp).
void views_lighting(sepal::BakeOptions* o);
sepal::AssetData bake_small(const std::string& spec, sepal::Param param, sepal::Method method, int terms,
                            bool radiance, int res, int judge_size);


}  // namespace material_fx
