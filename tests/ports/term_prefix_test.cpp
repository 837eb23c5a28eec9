// ports/common/term_prefix: the first k terms of an asset, on the plan paths (filtered
// passes) and on the CPU (material.terms), must draw the same k-term sum.
#include <doctest/doctest.h>

#include <algorithm>
#include <memory>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "common/render_gl.h"
#include "common/scene_draw.h"
#include "common/term_prefix.h"
#include "util/image.h"

TEST_CASE("term prefix: a signed 3-term plan cut to k terms draws the CPU's k-term sum") {
    std::string err;
    auto brdf = sepal::make_brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", &err);
    REQUIRE(brdf);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.methods = {sepal::Method::WSVD};  // signed factors: texture and constant passes too
    o.terms = {3};
    o.cap = 2.0;
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*brdf, o, &r, &err), err);
    std::vector<uint8_t> bytes;
    REQUIRE(sepal::encode_asset(r.asset, &bytes, &err));
    auto full = std::make_unique<sepal_asset>();
    auto cut = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), full.get(), &e) == SEPAL_OK);
    int constants = 0;
    for (uint32_t p = 0; p < full->plan.pass_count; ++p) constants += full->passes[p].op == SEPAL_OP_CONSTANT;
    CHECK(constants > 0);  // the case the value matching exists for

    sepal_ports::SceneSetup setup;
    setup.width = setup.height = 128;
    REQUIRE(sepal_ports::load_scene_mesh(&setup, &err));
    std::vector<sepal::Image> gl_images;
    for (int k = 1; k <= 3; ++k) {
        CAPTURE(k);
        const sepal_ports::TermPrefix t = sepal_ports::term_prefix(*full, k, cut.get());
        CHECK(t.terms == k);
        CHECK(t.unattributed == 0);
        CHECK(t.texture_bytes > 0);
        for (uint32_t p = 0; p < cut->plan.pass_count; ++p)
            for (uint16_t tex : {cut->passes[p].tex0, cut->passes[p].tex1})
                if (tex != SEPAL_FMT_NO_TEXTURE) CHECK(int(cut->textures[tex].desc.term) < k);
        // The CPU backend sums the first material.terms terms.
        sepal_ports::CpuFrame frame;
        const sepal_cpu_desc d = sepal_ports::scene_cpu_desc(cut.get(), setup, &frame, nullptr);
        REQUIRE(sepal_draw_cpu(&d, &e) == SEPAL_OK);
        sepal::Image cpu(128, 128, 3);
        cpu.data = frame.rgb;
        for (float& v : cpu.data) v = std::min(1.0f, std::max(0.0f, v));
        // The plan path: a headless GL ES 2 frame of the cut plan (the helper draws encoded
        // assets: the cut one goes back through the writer).
        sepal::AssetData a = r.asset;
        a.material.terms = cut->material.terms;
        a.passes.assign(cut->passes, cut->passes + cut->plan.pass_count);
        a.textures.erase(std::remove_if(a.textures.begin(), a.textures.end(),
                                        [k](const sepal::AssetTexture& tx) { return int(tx.desc.term) >= k; }),
                         a.textures.end());
        // Texture indices shift when later terms' textures go; the bake orders them by term.
        std::vector<uint8_t> cut_bytes;
        REQUIRE_MESSAGE(sepal::encode_asset(a, &cut_bytes, &err), err);
        std::vector<uint8_t> rgba;
        sepal_ports::GlRenderOptions opt;
        opt.gles_version = 2;
        opt.float_target = true;  // the plan's own sum, without the 8-bit framebuffer's cost
        sepal_ports::GlRenderInfo info;
        REQUIRE_MESSAGE(sepal_ports::render_asset_headless(cut_bytes.data(), cut_bytes.size(), setup, opt, &rgba, &info, &err),
                        err);
        sepal::Image gl(128, 128, 3);
        gl.data = info.float_rgb;
        for (float& v : gl.data) v = std::min(1.0f, std::max(0.0f, v));
        const sepal::ImageDiff diff = sepal::diff_images(cpu, gl, 8.0);
        CAPTURE(diff.psnr);
        CHECK(diff.psnr > 35.0);  // the half-float test's bar for the full plan (golden_materials_test)
        gl_images.push_back(gl);
    }
    // The prefixes differ: each term adds something visible.
    CHECK(sepal::diff_images(gl_images[0], gl_images[2], 0).psnr < 40.0);
}
