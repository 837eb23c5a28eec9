#include "material_fixtures.h"

#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "bake/plan.h"
#include "spec/spec.h"

namespace material_fx {


// A texture of side n with the full MIP chain, q = fn(u, v) at texel centres.
sepal::AssetTexture make_texture(int n, uint32_t role, uint32_t term, float scale, const TexFn& fn,
                                 float bias, int channels) {
    sepal::AssetTexture t;
    t.desc.width = t.desc.height = uint32_t(n);
    t.desc.channels = uint32_t(channels);
    t.desc.bits = 8;
    t.desc.role = role;
    t.desc.term = term;
    for (int c = 0; c < 4; ++c) t.desc.scale[c] = scale, t.desc.bias[c] = bias;
    uint32_t levels = 0;
    for (int side = n; side >= 1; side /= 2) {
        ++levels;
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i)
                for (int c = 0; c < channels; ++c) {
                    const float q = fn((i + 0.5f) / side, (j + 0.5f) / side, c);
                    t.data.push_back(uint8_t(std::lround(std::fmin(1.0f, std::fmax(0.0f, q)) * 255.0f)));
                }
    }
    t.desc.levels = levels;
    return t;
}

sepal_fmt_pass pass(sepal_pass_op op, sepal_blend blend, uint16_t t0, uint16_t t1, float color) {
    sepal_fmt_pass p{};
    p.op = uint16_t(op);
    p.blend = uint16_t(blend);
    p.tex0 = t0;
    p.tex1 = t1;
    p.color[0] = p.color[1] = p.color[2] = color;
    p.rgb_scale = 1;
    return p;
}

std::vector<uint8_t> encode(const sepal::AssetData& a) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    return bytes;
}

// Renders an asset through the runtime on GL ES 1.1 with a capability mask.
Rendered render(const sepal::AssetData& a, uint32_t mask, const sepal_ports::SceneSetup& s,
                const sepal_ports::Rgba8Image* diffuse, int gles_version, sepal_draw_mode mode) {
    std::vector<uint8_t> bytes, rgba;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    sepal_ports::GlRenderInfo info;
    // Fails on any GL error: sepal_draw checks after every pass.
    sepal_ports::GlRenderOptions opt;
    opt.mask = mask;
    opt.diffuse = diffuse;
    opt.gles_version = gles_version;
    opt.mode = mode;
    REQUIRE_MESSAGE(sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &rgba, &info, &err), err);
    Rendered out;
    out.stats = info.stats;
    out.path = info.path;
    out.image = sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), s.width, s.height));
    return out;
}

// f = G0 H0 + G1 H1 with G1, H1 signed (stored with a bias): the plan needs every kind
// of pass, subtractions included.
sepal::AssetData signed_asset(sepal_param param) {
    sepal::AssetData a = base_asset(param, 2);
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 0, 1.0f, [](float u, float v, int c) {
        const float r2 = (u - 0.5f) * (u - 0.5f) + (v - 0.5f) * (v - 0.5f);
        return std::exp(-r2 * 12.0f) * (0.8f + 0.1f * c);
    }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 0, 0.3f, [](float u, float v, int) { return 0.5f + 0.5f * u * v; }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 1, 0.6f, [](float u, float, int) { return u; }, -0.3f));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 1, 0.1f, [](float, float v, int) { return v; }, -0.02f));
    std::string err;
    REQUIRE_MESSAGE(sepal::build_plan(&a, &err), err);
    return a;
}

// Renders an asset with the CPU backend.
double image_peak(const sepal::Image& im) {
    double peak = 0;
    for (float v : im.data) peak = std::max<double>(peak, v);
    return peak;
}

sepal::Image render_cpu(const sepal::AssetData& a, const sepal_ports::SceneSetup& s,
                        const sepal_ports::Rgba8Image* diffuse) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal::encode_asset(a, &bytes, &err), err);
    sepal::Image img(s.width, s.height, 3);
    REQUIRE_MESSAGE(sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), s, diffuse, &img.data, nullptr, &err),
                    err);
    return img;
}

sepal_ports::SceneSetup test_scene(const char* mesh, int lights) {
    sepal_ports::SceneSetup s;
    s.width = 128;
    s.height = 96;
    s.mesh_name = mesh;
    test_fx::test_lights(&s.scene, lights);
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
    return s;
}

void views_lighting(sepal::BakeOptions* o) {
    o->views = sepal::default_bake_views();
    o->light_range.ratio = 1;
    o->light_range.max_lights = 1;
    o->light_range.irradiance_max = 1e6;
    o->held_out = false;
    o->fit_weight = sepal::BakeOptions::FitWeight::Uniform;
}

sepal::AssetData bake_small(const std::string& spec, sepal::Param param, sepal::Method method, int terms,
                            bool radiance, int res, int judge_size) {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    sepal::BakeOptions o;
    o.params = {param};
    o.resolutions = {res};
    o.methods = {method};
    o.terms = {terms};
    o.radiance = radiance;
    o.judge_size = judge_size;
    views_lighting(&o);
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
    return r.asset;
}

}  // namespace material_fx
