// sepal render --framebuffer: the GL backends draw into an RGB565 pbuffer (a --scene's too),
// the models round to its bits, and a value that is neither 565 nor 8888 is refused saying
// what is accepted.
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "util/image.h"
#include "test_util.h"

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

int run(const std::vector<std::string>& args, std::string* out) {
    const int code = sepal_test::run_cmd("render", args, out);
    INFO(*out);
    return code;
}

// Every channel value one a 5- or 6-bit channel reads back as: widened by repeating its bits
// (llvmpipe) or by rounding code x 255 / (2^n - 1) (NVIDIA), which differ by a level at most.
bool all_565(const sepal::Image& img) {
    for (size_t i = 0; i < img.data.size(); ++i) {
        const int v = int(img.data[i] * 255.0f + 0.5f), n = i % 3 == 1 ? 6 : 5, top = (1 << n) - 1;
        const int code = (v * top + 127) / 255;
        const int repeated = (code << (8 - n)) | (code >> (2 * n - 8)), rounded = (code * 255 + top / 2) / top;
        if (v != repeated && v != rounded) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("render --framebuffer 565: an RGB565 pbuffer (and its model) writes a PNG; bad values are refused") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(sepal_test::run_cmd("bake", {"blinn", "--param", "gs-half", "--res", "8", "--terms", "1", "--method",
                                         "nmf", "-o", dir + "/b.sepal"},
                                &out) == 0);
    for (const char* backend : {"gles1", "gles2", "gles1-model"}) {
        CAPTURE(backend);
        const std::string png = dir + "/" + backend + ".png";
        REQUIRE(run({dir + "/b.sepal", "--backend", backend, "--size", "48x48", "--framebuffer", "565", "-o", png},
                    &out) == 0);
        CHECK(contains(out, std::string(backend) == "gles1-model" ? "framebuffer 5/6/5 bits per channel, no dithering"
                                                                   : "framebuffer 5/6/5 bits per channel, GL_DITHER on"));
        sepal::Image img;
        REQUIRE(sepal::read_image(png, &img, nullptr));
        CHECK(all_565(img));
        double sum = 0;
        for (float v : img.data) sum += v;
        CHECK(sum > 10);  // the sphere was drawn
    }
    // The default stays 8 bits per channel.
    REQUIRE(run({dir + "/b.sepal", "--backend", "gles1", "--size", "48x48", "-o", dir + "/d.png"}, &out) == 0);
    CHECK(contains(out, "framebuffer 8/8/8 bits per channel"));
    sepal::Image img;
    REQUIRE(sepal::read_image(dir + "/d.png", &img, nullptr));
    CHECK_FALSE(all_565(img));
    // Bad values and backends it does not apply to: exit 2, saying what is accepted, no PNG.
    CHECK(run({dir + "/b.sepal", "--backend", "gles1", "--framebuffer", "555", "-o", dir + "/x.png"}, &out) == 2);
    CHECK(contains(out, "--framebuffer '555': give 8888 (8 bits per channel) or 565"));
    CHECK(run({dir + "/b.sepal", "--backend", "cpu", "--framebuffer", "565", "-o", dir + "/x.png"}, &out) == 2);
    CHECK(contains(out, "--framebuffer applies to the GL backends and their models (not cpu)"));
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/x.png") == 0);
}

TEST_CASE("render --scene --framebuffer 565: the scene's objects in an RGB565 pbuffer, each summed in 8 bits") {
    // Two overlapping spheres of a blinn asset with 2 doublings on GL ES 1.1 under two
    // lights: every pass rounded to 5/6/5 loses several dB against the exact render that
    // one rounding of each object's 8-bit sum keeps (measured on llvmpipe at 96 x 72:
    // GL ES 1.1 summed 43.3 dB, per pass 32.4; GL ES 2 43.6 and 38.2).
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(sepal_test::run_cmd("bake", {"blinn", "--param", "gs-half", "--res", "32", "--terms", "2", "--method",
                                         "nmf", "--fit", "brdf", "-o", dir + "/b.sepal"},
                                &out) == 0);
    {
        std::FILE* f = std::fopen((dir + "/s.json").c_str(), "w");
        REQUIRE(f);
        std::fputs(R"({
  "size": [96, 72],
  "camera": {"eye": [0, -3.2, 1.4], "target": [0, 0, 0]},
  "lights": [{"type": "point", "position": [2, -2.5, 3], "intensity": 40},
             {"type": "directional", "direction": [-1, -0.5, 0.6], "intensity": 1.5}],
  "materials": [{"name": "b", "spec": "blinn", "asset": "b.sepal"}],
  "objects": [{"material": "b", "mesh": "sphere", "translate": [-0.4, 0.3, 0], "scale": 0.8},
              {"material": "b", "mesh": "sphere", "translate": [0.5, -0.3, 0], "scale": 0.6}]
})",
                   f);
        std::fclose(f);
    }
    const std::string scene = dir + "/s.json";
    REQUIRE(run({"--scene", scene, "--backend", "exact", "-o", dir + "/exact.png"}, &out) == 0);
    sepal::Image exact;
    REQUIRE(sepal::read_image(dir + "/exact.png", &exact, nullptr));
    auto psnr = [&](const std::string& backend, const std::vector<std::string>& extra, const std::string& says) {
        std::vector<std::string> args = {"--scene", scene, "--backend", backend, "--framebuffer", "565"};
        args.insert(args.end(), extra.begin(), extra.end());
        args.push_back("-o");
        args.push_back(dir + "/" + backend + ".png");
        REQUIRE(run(args, &out) == 0);
        CHECK(contains(out, says));
        sepal::Image img;
        REQUIRE(sepal::read_image(dir + "/" + backend + ".png", &img, nullptr));
        CHECK(all_565(img));
        return sepal::diff_images(exact, img, 8).psnr;
    };
    for (const std::string backend : {"gles1", "gles2"}) {
        CAPTURE(backend);
        const double summed = psnr(backend, {}, "each object's passes summed in an 8-bit target");
        const double per_pass = psnr(backend, {"--mask", "fbo"}, "every pass rounded to it");
        MESSAGE(backend << " scene on 565 against exact: summed " << summed << " dB, each pass rounded " << per_pass);
        CHECK(summed >= per_pass + (backend == "gles1" ? 4.0 : 1.5));
    }
    // Where it does not apply: exit 2, saying so.
    CHECK(run({"--scene", scene, "--backend", "cpu", "--framebuffer", "565", "-o", dir + "/x.png"}, &out) == 2);
    CHECK(contains(out, "--scene: --framebuffer applies to the GL backends (not cpu)"));
    CHECK(run({"--scene", scene, "--framebuffer", "555", "-o", dir + "/x.png"}, &out) == 2);
    CHECK(contains(out, "--framebuffer '555': give 8888"));
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/x.png") == 0);
}
