#include "port_fixtures.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "common/render_gl.h"
#include "test_util.h"

namespace port_test {

Assets bake_assets(const std::string& dir) {
    std::string err;
    auto brdf = sepal::make_brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", &err);
    REQUIRE_MESSAGE(brdf, err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {32};
    o.methods = {sepal::Method::NMF};
    o.terms = {2};
    o.cap = 2.0;
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*brdf, o, &r, &err), err);
    Assets a{dir + "/intact.sepal", dir + "/masked.sepal"};
    REQUIRE_MESSAGE(sepal::write_asset(a.intact, r.asset, &err), err);
    sepal::AssetData masked = r.asset;
    // NMF: one product pass per term, plus the separated diffuse part's untextured pass.
    REQUIRE(std::count_if(masked.passes.begin(), masked.passes.end(), [](const sepal_fmt_pass& p) {
                return p.op == SEPAL_OP_PRODUCT;
            }) == 2);
    int zeroed = 0;
    for (sepal::AssetTexture& t : masked.textures)
        if (t.desc.term == 1 && t.desc.role == SEPAL_ROLE_H) {
            REQUIRE(t.desc.bias[0] == 0.0f);  // q = 0 then means 0
            std::fill(t.data.begin(), t.data.end(), uint8_t(0));
            ++zeroed;
        }
    REQUIRE(zeroed == 1);
    REQUIRE_MESSAGE(sepal::write_asset(a.masked, masked, &err), err);
    return a;
}

namespace {
sepal::Tolerance tolerance(double max_diff, double max_share, double min_psnr) {
    sepal::Tolerance t;
    t.max_diff = max_diff;
    t.max_share = max_share;
    t.min_psnr = min_psnr;
    return t;
}
}  // namespace

sepal::Tolerance golden_tolerance() { return tolerance(2, 0.005, 45); }
sepal::Tolerance cross_rasterizer_tolerance() { return tolerance(3, 0.01, 40); }
sepal::Tolerance cpu_tolerance() { return tolerance(8, 0.03, 33); }

sepal::Image render_cpu(const std::string& asset, const sepal_ports::SceneSetup& setup) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::read_asset_file(asset, &bytes, &err), err);
    sepal::Image img(setup.width, setup.height, 3);
    REQUIRE_MESSAGE(sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), setup, nullptr, &img.data, nullptr, &err), err);
    for (float& v : img.data) v = std::min(1.0f, std::max(0.0f, v));  // as displayed
    return img;
}

bool parse_command(const std::string& line, Command* c, std::string* err) {
    std::istringstream in(line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(&w[0]);
    const int argc = int(argv.size());
    for (int i = 1; i < argc; ++i) {
        const int used = sepal_ports::parse_scene_flag(argc, argv.data(), i, &c->setup, err);
        if (used < 0) return false;
        if (used > 0) {
            i += used - 1;
            continue;
        }
        const std::string a = words[size_t(i)];
        if ((a == "--backend" || a == "-o") && i + 1 < argc) {
            if (a == "--backend") c->backend = words[size_t(i + 1)];
            ++i;
        } else if (a[0] != '-' && c->asset.empty()) {
            c->asset = a;
        } else if (a != "--headless") {
            *err = "unexpected word '" + a + "' in: " + line;
            return false;
        }
    }
    return sepal_ports::load_scene_mesh(&c->setup, err);
}

sepal::Image render_headless(const std::string& asset, const sepal_ports::SceneSetup& setup, const std::string& backend) {
    std::vector<uint8_t> bytes, rgba;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::read_asset_file(asset, &bytes, &err), err);
    sepal_ports::GlRenderOptions opt;
    REQUIRE(sepal_ports::parse_gl_backend(backend, &opt));
    sepal_ports::GlRenderInfo info;
    REQUIRE_MESSAGE(sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &err), err);
    return sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), setup.width, setup.height));
}

bool have_program(const std::string& name) {
    return sepal_test::run("command -v " + name + " > /dev/null") == 0;
}

}  // namespace port_test
