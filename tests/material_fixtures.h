// Synthetic materials and rendering helpers shared by the runtime material tests.
#pragma once
#include <functional>
#include <string>

#include "asset_file.h"
#include "brdf.h"
#include "image.h"
#include "render_gl.h"
#include "scene_flags.h"
#include "sepal_material.h"

namespace material_fx {

using TexFn = std::function<float(float u, float v, int channel)>;

// A texture of side n with the full MIP chain, q = fn(u, v) at texel centres.
sepal::AssetTexture make_texture(int n, uint32_t role, uint32_t term, float scale, const TexFn& fn,
                                 float bias = 0.0f, int channels = 3);
srt_fmt_pass pass(srt_pass_op op, srt_blend blend, uint16_t t0, uint16_t t1, float color);
sepal::AssetData base_asset(srt_param param, uint32_t terms);

struct Rendered {
    sepal::Image image;
    srt_draw_stats stats{};
    std::string path;
};
// Renders an asset through the runtime, headless (REQUIREs success: any GL error fails).
Rendered render(const sepal::AssetData& a, uint32_t mask, const sepal_ports::SceneSetup& s,
                const sepal_ports::Rgba8Image* diffuse = nullptr, int gles_version = 1,
                srt_draw_mode mode = SRT_MODE_MULTIPASS);
// f = G0 H0 + G1 H1 with G1, H1 signed (stored with a bias): every kind of pass.
sepal::AssetData signed_asset(srt_param param = SRT_PARAM_GS_HALF);
// Renders an asset with the CPU backend.
sepal::Image render_cpu(const sepal::AssetData& a, const sepal_ports::SceneSetup& s,
                        const sepal_ports::Rgba8Image* diffuse = nullptr);
// 128x96, the named mesh, `lights` lights alternating point and directional.
sepal_ports::SceneSetup test_scene(const char* mesh, int lights);

// f = constant, for comparisons with the exact backend.
class ConstantBrdf : public sepal::Brdf {
  public:
    explicit ConstantBrdf(double v) : v_(v) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return wi.z > 0 && wo.z > 0 ? glm::dvec3(v_) : glm::dvec3(0.0);
    }
    std::string spec() const override { return "constant"; }
    std::string model() const override { return "constant"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return true; }

  private:
    double v_;
};

}  // namespace material_fx
