// Image I/O and comparison (offline/util/image.h).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "util/image.h"
#include "util/io.h"
#include "test_util.h"

using sepal::Image;

namespace {
Image gradient(int w, int h) {
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.at(x, y, 0) = float(x) / float(w - 1);
            img.at(x, y, 1) = float(y) / float(h - 1);
            img.at(x, y, 2) = 0.25f;
        }
    return img;
}
void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}
}  // namespace

TEST_CASE("png round trip keeps 8-bit values and orientation") {
    const std::string dir = sepal_test::temp_dir();
    Image img = gradient(37, 19);
    for (float& v : img.data) v = std::round(v * 255.0f) / 255.0f;
    std::string err;
    REQUIRE(sepal::write_png(dir + "/g.png", img, &err));
    Image back;
    REQUIRE_MESSAGE(sepal::read_image(dir + "/g.png", &back, &err), err);
    CHECK(back.width == 37);
    CHECK(back.height == 19);
    CHECK(back.channels == 3);
    CHECK(back.data == img.data);
    CHECK(back.at(36, 0, 0) == doctest::Approx(1.0f));  // top-right red
    CHECK(back.at(0, 18, 1) == doctest::Approx(1.0f));  // bottom-left green
}

TEST_CASE("png writer reports clipped values instead of hiding them") {
    const std::string dir = sepal_test::temp_dir();
    Image img(2, 1, 1);
    img.data = {1.5f, -0.25f};
    int64_t clipped = 0;
    REQUIRE(sepal::write_png(dir + "/c.png", img, nullptr, &clipped));
    CHECK(clipped == 2);
}

TEST_CASE("pfm round trip is exact, grey and rgb") {
    const std::string dir = sepal_test::temp_dir();
    Image img = gradient(5, 3);
    img.at(1, 1, 0) = 1234.5f;  // float range, not clipped
    img.at(2, 1, 1) = -3.0e-8f;
    std::string err;
    REQUIRE(sepal::write_pfm(dir + "/g.pfm", img, &err));
    Image back;
    REQUIRE_MESSAGE(sepal::read_image(dir + "/g.pfm", &back, &err), err);
    CHECK(back.channels == 3);
    CHECK(back.data == img.data);

    Image grey(4, 2, 1);
    for (size_t i = 0; i < grey.data.size(); ++i) grey.data[i] = float(i) * 0.5f;
    REQUIRE(sepal::write_pfm(dir + "/grey.pfm", grey, &err));
    REQUIRE(sepal::read_pfm(dir + "/grey.pfm", &back, &err));
    CHECK(back.channels == 1);
    CHECK(back.data == grey.data);
}

TEST_CASE("pfm reader accepts big-endian files") {
    const std::string dir = sepal_test::temp_dir();
    // 1x1 RGB, positive scale = big endian; 1.0f = 3f 80 00 00.
    write_bytes(dir + "/be.pfm", std::string("PF\n1 1\n1.0\n") +
                                     std::string("\x3f\x80\x00\x00\x40\x00\x00\x00\x00\x00\x00\x00", 12));
    Image img;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_pfm(dir + "/be.pfm", &img, &err), err);
    CHECK(img.data == std::vector<float>{1.0f, 2.0f, 0.0f});
}

TEST_CASE("corrupt and unreadable images are refused with a reason") {
    const std::string dir = sepal_test::temp_dir();
    struct Case {
        const char* name;
        std::string bytes;
        const char* expect;  // a fragment of the message
    } cases[] = {
        {"empty.png", "", "unknown image format"},
        {"text.png", "hello world", "unknown image format"},
        {"trunc.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), "truncated PNG: the file ends at byte 16"},
        {"short.pfm", std::string("PF\n2 2\n-1.0\n") + std::string(8, '\0'), "need"},
        {"long.pfm", std::string("PF\n1 1\n-1.0\n") + std::string(16, '\0'), "need"},
        {"huge.pfm", "PF\n100000 100000\n-1.0\n", "out of range"},
        {"neg.pfm", "PF\n-3 2\n-1.0\n", "out of range"},
        {"words.pfm", "PF\nab 2\n-1.0\n", "not an integer"},
        {"scale.pfm", "PF\n1 1\nzero\n", "scale"},
        {"header.pfm", "PF\n1", "truncated"},
        {"nan.pfm", std::string("PF\n1 1\n-1.0\n") + std::string("\0\0\xc0\x7f\0\0\0\0\0\0\0\0", 12),
         "NaN or inf"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.name);
        write_bytes(dir + "/" + c.name, c.bytes);
        Image img;
        std::string err;
        CHECK_FALSE(sepal::read_image(dir + "/" + c.name, &img, &err));
        CHECK_MESSAGE(err.find(c.expect) != std::string::npos, err);
        CHECK(err.find(c.name) != std::string::npos);  // the message names the file
    }
    Image img;
    std::string err;
    CHECK_FALSE(sepal::read_image(dir + "/does-not-exist.png", &img, &err));
    CHECK(err.find("No such file") != std::string::npos);
    CHECK_FALSE(sepal::read_image(dir, &img, &err));  // a folder
    CHECK(err.find("not a regular file") != std::string::npos);
}

TEST_CASE("writes are atomic: a failed write leaves no file behind") {
    const std::string dir = sepal_test::temp_dir();
    std::string err;
    CHECK_FALSE(sepal::write_png(dir + "/missing-folder/x.png", gradient(2, 2), &err));
    CHECK_FALSE(err.empty());
    Image bad;  // empty image
    CHECK_FALSE(sepal::write_png(dir + "/bad.png", bad, &err));
    std::FILE* f = std::fopen((dir + "/bad.png").c_str(), "rb");
    CHECK(f == nullptr);
    if (f) std::fclose(f);
}

TEST_CASE("diff statistics") {
    Image a = gradient(10, 10), b = a;
    sepal::ImageDiff d = sepal::diff_images(a, b, 0);
    CHECK(d.comparable);
    CHECK(std::isinf(d.psnr));
    CHECK(d.max_diff == 0);
    CHECK(d.pixels_over == 0);

    b.at(3, 4, 1) += 10.0f / 255.0f;  // one channel of one pixel, 10 levels
    b.at(5, 5, 2) += 2.0f / 255.0f;
    d = sepal::diff_images(a, b, 5);
    CHECK(d.max_diff == doctest::Approx(10.0).epsilon(1e-4));
    CHECK(d.pixels_over == 1);
    CHECK(d.share_over == doctest::Approx(0.01));
    // mse = (100 + 4) / 300 channel values
    CHECK(d.psnr == doctest::Approx(10 * std::log10(255.0 * 255.0 * 300.0 / 104.0)).epsilon(1e-4));

    sepal::Tolerance t;
    t.max_diff = 5;
    std::string why;
    CHECK_FALSE(sepal::tolerance_holds(d, t, &why));
    CHECK(why.find("differ by more than 5") != std::string::npos);
    t.max_share = 0.02;
    CHECK(sepal::tolerance_holds(d, t, &why));
    t.min_psnr = 60;
    CHECK_FALSE(sepal::tolerance_holds(d, t, &why));
    CHECK(why.find("PSNR") != std::string::npos);

    Image c = gradient(10, 11);
    d = sepal::diff_images(a, c, 0);
    CHECK_FALSE(d.comparable);
    CHECK_FALSE(sepal::tolerance_holds(d, sepal::Tolerance{}, &why));
    CHECK(why.find("sizes differ") != std::string::npos);
}

TEST_CASE("grey and rgba compare as rgb; alpha is ignored") {
    Image grey(2, 1, 1), rgba(2, 1, 4);
    grey.data = {0.5f, 1.0f};
    rgba.data = {0.5f, 0.5f, 0.5f, 0.0f, 1.0f, 1.0f, 1.0f, 0.3f};
    CHECK(sepal::diff_images(grey, rgba, 0).max_diff == 0);
}

TEST_CASE("heatmap marks differing pixels") {
    Image a = gradient(4, 4), b = a;
    b.at(2, 1, 0) = 1.0f - b.at(2, 1, 0);
    const Image h = sepal::diff_heatmap(a, b, 100);
    CHECK(h.channels == 3);
    CHECK(h.at(0, 0, 0) == 0.0f);
    CHECK(h.at(2, 1, 0) > 0.5f);
}

TEST_CASE("16-bit png round trip keeps every sample, for 1 to 4 channels") {
    const std::string dir = sepal_test::temp_dir();
    for (int ch = 1; ch <= 4; ++ch) {
        CAPTURE(ch);
        const int w = 5, h = 3;
        std::vector<uint16_t> s(size_t(w) * h * ch);
        for (size_t i = 0; i < s.size(); ++i) s[i] = uint16_t((i * 4099 + 7) & 0xffff);
        std::string err;
        REQUIRE_MESSAGE(sepal::write_png16(dir + "/p.png", w, h, ch, s, &err), err);
        int rw = 0, rh = 0, rc = 0;
        std::vector<uint16_t> back;
        REQUIRE_MESSAGE(sepal::read_png16(dir + "/p.png", &rw, &rh, &rc, &back, &err), err);
        CHECK(rw == w);
        CHECK(rh == h);
        CHECK(rc == ch);
        CHECK(back == s);
    }
    std::string err;
    CHECK_FALSE(sepal::write_png16(dir + "/bad.png", 2, 2, 5, std::vector<uint16_t>(20), &err));
}
