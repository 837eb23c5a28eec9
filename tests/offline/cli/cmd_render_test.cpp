// sepal render --framebuffer: the GL backends draw into an RGB565 pbuffer, the models round
// to its bits, and a value that is neither 565 nor 8888 is refused saying what is accepted.
#include <doctest/doctest.h>

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

// Every channel value one a 5- or 6-bit channel reads back as (bit replication).
bool all_565(const sepal::Image& img) {
    for (size_t i = 0; i < img.data.size(); ++i) {
        const int v = int(img.data[i] * 255.0f + 0.5f), n = i % 3 == 1 ? 6 : 5, code = v >> (8 - n);
        if (v != ((code << (8 - n)) | (code >> (2 * n - 8)))) return false;
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
    CHECK(run({"--scene", dir + "/s.json", "--framebuffer", "565", "-o", dir + "/x.png"}, &out) == 2);
    CHECK(contains(out, "--scene takes no --env, --diffuse, --float-target or --framebuffer"));
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/x.png") == 0);
}
