// A material judged by its picture (bake/picture.h).
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "bake/picture.h"
#include "brdf/cie.h"
#include "spec/spec.h"

TEST_CASE("picture: the views are the default scene, then the held-out conditions") {
    std::vector<sepal::BakeView> views;
    std::string err;
    REQUIRE_MESSAGE(sepal::picture_views(&views, &err), err);
    REQUIRE(views.size() == 5);
    CHECK(views[0].name == "default");
    for (size_t i = 1; i < views.size(); ++i) CHECK(views[i].name.rfind("held-out", 0) == 0);
}

TEST_CASE("picture: a BRDF against itself is exact; a recoloured one shows its colour difference") {
    std::vector<sepal::BakeView> views;
    std::string err;
    REQUIRE(sepal::picture_views(&views, &err));
    auto grey = sepal::make_brdf("lambert:rho=0.5", &err);
    auto warm = sepal::make_brdf("lambert:rho=0.5/0.4/0.3", &err);
    REQUIRE(grey);
    REQUIRE(warm);
    sepal::PictureComparison same, other;
    REQUIRE_MESSAGE(sepal::compare_pictures(*grey, *grey, views, 48, &same, &err), err);
    REQUIRE(same.views.size() == views.size());
    for (const sepal::PictureFigures& f : same.views) {
        CHECK(std::isinf(f.psnr));
        CHECK(f.max_diff == 0.0);
        CHECK(f.delta_e == 0.0);
    }
    CHECK(std::isinf(same.held_out_psnr));
    REQUIRE(sepal::compare_pictures(*grey, *warm, views, 48, &other, &err));
    CHECK(other.truth.width == 48);
    for (const sepal::PictureFigures& f : other.views) {
        CAPTURE(f.view);
        CHECK(std::isfinite(f.psnr));
        CHECK(f.psnr >= other.worst_psnr);
        CHECK(f.max_diff > 0.0);
        CHECK(f.delta_e > 0.5);  // grey against a warm tint: visible even under the dim light
    }
    CHECK(other.held_out_psnr > other.worst_psnr - 1e-9);
}

TEST_CASE("picture: mean Delta E counts the lit pixels only") {
    sepal::Image a, b;
    for (sepal::Image* im : {&a, &b}) {
        im->width = 4;
        im->height = 1;
        im->channels = 3;
        im->data.assign(12, 0.0f);
    }
    // truth: black, grey, grey, black; test: white where the truth is black (background).
    const float grey[3] = {0.5f, 0.5f, 0.5f}, tint[3] = {0.5f, 0.4f, 0.3f};
    for (int c = 0; c < 3; ++c) {
        a.data[3 + c] = a.data[6 + c] = grey[c];
        b.data[3 + c] = b.data[6 + c] = tint[c];
        b.data[c] = b.data[9 + c] = 1.0f;
    }
    const double expect = sepal::ciede2000(sepal::srgb_display_to_lab({0.5, 0.5, 0.5}),
                                           sepal::srgb_display_to_lab({0.5, 0.4, 0.3}));
    CHECK(expect > 5.0);
    CHECK(sepal::mean_delta_e(a, b) == doctest::Approx(expect));
    sepal::Image black = a;
    black.data.assign(12, 0.0f);
    CHECK(sepal::mean_delta_e(black, b) == 0.0);  // nothing lit
}
