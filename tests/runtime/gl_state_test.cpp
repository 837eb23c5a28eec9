// A frame does not depend on the GL state its caller left (ports hand in the context, and an
// application draws its own things between frames): masks, scissor and dither left in any
// state give the same image as a fresh context.
#include <doctest/doctest.h>

#include <GLES2/gl2.h>

#include <functional>
#include <memory>
#include <vector>

#include "common/scene_draw.h"
#include "common/scene_flags.h"
#include "headless/sepal_headless.h"
#include "material_fixtures.h"
#include "sepal/sepal_material.h"

namespace {

std::vector<uint8_t> read_rgba(int w, int h) {
    std::vector<uint8_t> px(size_t(w) * size_t(h) * 4);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    return px;
}

}  // namespace

TEST_CASE("a frame clears and draws the same whatever state the caller left (GL ES 1.1 and 2)") {
    const std::vector<uint8_t> bytes = material_fx::encode(
        material_fx::bake_small("blinn:n=40", sepal::Param::GsHalf, sepal::Method::ACLS, 2, false, 16, 16));
    for (int version : {1, 2})
        for (sepal_draw_mode mode : {SEPAL_MODE_MULTIPASS, SEPAL_MODE_FUSED_VERTEX, SEPAL_MODE_FUSED_PIXEL}) {
            if (version == 1 && mode != SEPAL_MODE_MULTIPASS) continue;
            CAPTURE(version);
            CAPTURE(int(mode));
            sepal_headless_desc hd = {};
            hd.width = hd.height = 64;
            hd.gles_version = version;
            char msg[512];
            sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
            REQUIRE_MESSAGE(ctx, msg);
            auto asset = std::make_unique<sepal_asset>();
            auto mat = std::make_unique<sepal_material>();
            struct Destroy {  // also when a REQUIRE below ends the case (declared after the
                              // material's storage, so it runs first)
                sepal_headless_context* ctx;
                sepal_material* mat = nullptr;
                ~Destroy() {
                    if (mat) sepal_material_destroy(mat);
                    sepal_headless_destroy(ctx);
                }
            } destroy{ctx};
            sepal_caps caps;
            sepal_error e = {};
            REQUIRE(sepal_query_caps(version, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK);
            REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
            REQUIRE_MESSAGE(sepal_material_create(&caps, asset.get(), 64, 64, mat.get(), &e) == SEPAL_OK, e.message);
            destroy.mat = mat.get();
            sepal_ports::SceneSetup s;
            s.width = s.height = 64;
            std::string err;
            REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
            std::vector<float> scratch;
            const sepal_draw_desc d = sepal_ports::scene_draw_desc(mat.get(), s, mode, &scratch);
            sepal_draw_stats stats = {};
            // Two frames that differ (the light moves), so a frame that kept the last one's
            // colour or depth shows. The reference: the second drawn after the first as usual.
            const sepal_light light = s.scene.lights[0];
            auto draw = [&](bool moved) {
                s.scene.lights[0] = light;
                if (moved) s.scene.lights[0].position[0] = -s.scene.lights[0].position[0] - 1.0f;
                REQUIRE_MESSAGE(sepal_draw(&d, &stats, &e) == SEPAL_OK, e.message);
            };
            draw(false);
            const std::vector<uint8_t> first = read_rgba(64, 64);
            draw(true);
            const std::vector<uint8_t> fresh = read_rgba(64, 64);
            size_t lit = 0, moved = 0;
            for (size_t i = 0; i < fresh.size(); i += 4) lit += fresh[i] + fresh[i + 1] + fresh[i + 2] > 0;
            for (size_t i = 0; i < fresh.size(); ++i) moved += fresh[i] != first[i];
            CHECK(lit > 500);     // the sphere is there
            CHECK(moved > 1000);  // and the light's move shows
            draw(false);
            // What an application might leave: masks off, a scissor box, dithering, a clear colour, a
            // stencil test, a polygon offset, the other front face.
            glDepthMask(GL_FALSE);
            glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
            glEnable(GL_SCISSOR_TEST);
            glScissor(10, 10, 5, 5);
            glEnable(GL_DITHER);
            glClearColor(0.5f, 0.25f, 0.75f, 1.0f);
            glEnable(GL_STENCIL_TEST);
            glStencilFunc(GL_NEVER, 0, 0xff);  // would drop every fragment
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(0.0f, -1000.0f);
            glFrontFace(GL_CW);  // would cull the front faces
            draw(true);
            const std::vector<uint8_t> again = read_rgba(64, 64);
            size_t differ = 0;
            for (size_t i = 0; i < fresh.size(); ++i) differ += fresh[i] != again[i];
            CHECK_MESSAGE(differ == 0, differ << " of " << fresh.size() << " bytes differ from the frame drawn after ours");
        }
}
