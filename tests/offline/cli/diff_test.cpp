// `sepal diff`: exit codes, report and heat map (in-process and through the binary).
#include <doctest/doctest.h>

#include <cstdio>

#include "cli/cli.h"
#include "sepal/sepal_asset.h"
#include "util/io.h"
#include "util/image.h"
#include "test_util.h"

namespace {
struct Fixture {
    std::string dir = sepal_test::temp_dir();
    std::string a = dir + "/a.png", b = dir + "/b.png", same = dir + "/same.png";
    Fixture() {
        sepal::Image img(16, 16, 3);
        for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 200) / 255.0f;
        REQUIRE(sepal::write_png(a, img, nullptr));
        REQUIRE(sepal::write_png(same, img, nullptr));
        // 4 of 256 pixels differ by 20 levels in one channel.
        for (int k = 0; k < 4; ++k) img.at(k, 3, 1) += 20.0f / 255.0f;
        REQUIRE(sepal::write_png(b, img, nullptr));
    }
    // Runs `sepal diff` in-process; returns the exit code and captures stdout.
    int diff(std::vector<std::string> args, std::string* out = nullptr) {
        return sepal_test::run_cmd("diff", args, out);
    }
};
}  // namespace

TEST_CASE_FIXTURE(Fixture, "sepal diff passes identical images and reports them") {
    std::string out;
    CHECK(diff({a, same, "--max-diff", "0"}, &out) == 0);
    CHECK(out.find("psnr       inf") != std::string::npos);
    CHECK(out.find("PASS") != std::string::npos);
}

TEST_CASE_FIXTURE(Fixture, "sepal diff fails beyond tolerance and passes within it") {
    std::string out;
    CHECK(diff({a, b, "--max-diff", "10"}, &out) == 1);
    CHECK(out.find("FAIL") != std::string::npos);
    CHECK(out.find("max diff   20.00") != std::string::npos);
    CHECK(out.find(" dB (of this image pair; the bake's figures pool several views)") != std::string::npos);
    CHECK(diff({a, b, "--max-diff", "20"}) == 0);
    CHECK(diff({a, b, "--max-diff", "10", "--max-share", "0.02"}) == 0);  // 4/256 = 1.6%
    CHECK(diff({a, b, "--max-diff", "10", "--max-share", "0.01"}) == 1);
    CHECK(diff({a, b, "--min-psnr", "30"}) == 0);
    CHECK(diff({a, b, "--min-psnr", "60"}, &out) == 1);
    CHECK(out.find("PSNR") != std::string::npos);
    CHECK(diff({a, b}) == 0);  // no tolerance given: report only
}

TEST_CASE_FIXTURE(Fixture, "sepal diff exits 2 on unreadable input or bad usage") {
    std::string out;
    CHECK(diff({a, dir + "/nope.png"}, &out) == 2);
    CHECK(out.find("nope.png") != std::string::npos);
    CHECK(diff({a}) == 2);
    CHECK(diff({a, b, "--max-diff"}) == 2);
    CHECK(diff({a, b, "--max-diff", "abc"}) == 2);
    CHECK(diff({a, b, "--max-share", "2"}) == 2);
    CHECK(diff({a, b, "--frobnicate", "1"}) == 2);
}

TEST_CASE_FIXTURE(Fixture, "sepal diff writes a heat map") {
    const std::string heat = dir + "/heat.png";
    CHECK(diff({a, b, "--heatmap", heat}) == 0);
    sepal::Image h;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_image(heat, &h, &err), err);
    CHECK(h.width == 16);
    CHECK(h.at(0, 3, 0) == 1.0f);  // the differing pixels are bright
    CHECK(h.at(8, 8, 0) == 0.0f);
}

TEST_CASE_FIXTURE(Fixture, "the sepal binary gives the same exit codes") {
    const std::string sepal = sepal_test::bin("sepal");
    CHECK(sepal_test::run(sepal + " diff " + a + " " + same + " --max-diff 0") == 0);
    CHECK(sepal_test::run(sepal + " diff " + a + " " + b + " --max-diff 1") == 1);
    std::string out;
    CHECK(sepal_test::run(sepal + " diff " + a + " " + dir + "/missing.png", &out) == 2);
    CHECK(out.find("missing.png") != std::string::npos);
    CHECK(sepal_test::run(sepal + " no-such-command") == 2);
    CHECK(sepal_test::run(sepal + " help") == 0);
}

TEST_CASE("golden harness: passes, fails with files named, updates") {
    const std::string dir = sepal_test::temp_dir();
    sepal::Image img(8, 8, 3);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 7) / 7.0f;
    sepal::Tolerance tol;
    tol.max_diff = 2;
    tol.min_psnr = 40;
    // Missing golden: fails and says how to create it.
    std::string msg = sepal_test::check_golden_in(dir, "selftest", img, tol, true, false);
    CHECK(msg.find("make update-goldens") != std::string::npos);
    // Update switch writes it; then the same image passes.
    CHECK(sepal_test::check_golden_in(dir, "selftest", img, tol, true, true).empty());
    CHECK(sepal_test::check_golden_in(dir, "selftest", img, tol, true, false).empty());
    // A real difference fails and leaves actual, expected and heat map behind.
    sepal::Image other = img;
    other.at(4, 4, 0) = 1.0f - other.at(4, 4, 0);
    msg = sepal_test::check_golden_in(dir, "selftest", other, tol, true, false);
    REQUIRE_FALSE(msg.empty());
    for (const char* suffix : {".actual.png", ".expected.png", ".heatmap.png"}) {
        const std::string path = sepal_test::output_dir() + "/selftest" + suffix;
        CHECK(msg.find(path) != std::string::npos);
        sepal::Image tmp;
        CHECK(sepal::read_image(path, &tmp, nullptr));
    }
}

namespace {

// A PNG whose header claims side x side (8-bit grey) with one tiny IDAT: what a
// decompression bomb looks like before decoding. Only the chunk CRCs are right.
std::string claimed_png(uint32_t side) {
    std::string png = "\x89PNG\r\n\x1a\n";
    auto chunk = [&](const char* type, const std::string& data) {
        std::string c(type, 4);
        c += data;
        auto be = [](uint32_t v) {
            return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
        };
        png += be(uint32_t(data.size())) + c + be(sepal_crc32(0, c.data(), c.size()));
    };
    std::string ihdr;
    for (int k = 0; k < 2; ++k) ihdr += std::string{char(side >> 24), char(side >> 16), char(side >> 8), char(side)};
    ihdr += std::string("\x08\x00\x00\x00\x00", 5);
    chunk("IHDR", ihdr);
    chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8));
    chunk("IEND", "");
    return png;
}

}  // namespace

TEST_CASE_FIXTURE(Fixture, "sepal diff: a pixel budget per image, stated in --help, refused before decoding") {
    const std::string bomb = dir + "/bomb.png";
    const std::string bytes = claimed_png(8192);
    std::string err, out;
    REQUIRE(sepal::write_file_atomic(bomb, bytes.data(), bytes.size(), &err));
    CHECK(diff({bomb, bomb}, &out) == 2);
    CHECK_MESSAGE(out.find("8192x8192 = 67108864 pixels is over the pixel budget of 16777216") != std::string::npos,
                  out);
    CHECK(out.find("--max-pixels") != std::string::npos);
    // Raised, the budget lets the header through: the (corrupt) data is what fails then.
    CHECK(diff({bomb, bomb, "--max-pixels", "67108864"}, &out) == 2);
    CHECK(out.find("pixel budget") == std::string::npos);
    CHECK(sepal::image_pixel_budget() == sepal::kDefaultImagePixels);  // for this command only
    CHECK(sepal_test::run_cmd("diff", {"--help"}, &out) == 0);
    CHECK(out.find("--max-pixels") != std::string::npos);
    CHECK(out.find("16777216") != std::string::npos);
}
