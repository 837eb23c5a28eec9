// A material judged by its picture: an approximation of a BRDF (a reconstruction from a few
// measurements, a fitted model) and the BRDF itself drawn by the exact renderer in the same
// views, with the figures a person comparing the two images would use.
//
// Usage:
//   std::vector<sepal::BakeView> views;
//   if (!sepal::picture_views(&views, &err)) ...      // the default scene, then the held-out conditions
//   sepal::PictureComparison c;
//   if (!sepal::compare_pictures(truth, approx, views, 256, &c, &err)) ...
//   c.views[0].psnr, c.views[0].delta_e;              // the default scene
//   c.held_out_psnr;                                  // pooled over the held-out conditions
//
// The views: the default scene (`sepal render`'s sphere, camera and light), then the held-out
// conditions of the default light range (bake/light_range.h: a dim light, another direction and
// brightness, the torus, two lights; lights behind the object among them), the conditions the
// fidelity bench reports. Both BRDFs are drawn with the exact renderer at one sample per pixel
// (the same rasterization for both, so edges cancel) and shown clamped to [0, 1].
// Per view: PSNR and the largest channel difference in 8-bit levels, the share of pixels more
// than 16 levels off, and the mean CIEDE2000 colour difference over the lit pixels (those where
// the truth shows more than 2 levels in some channel: the object, not the background, which
// would dilute it), reading display values as sRGB (brdf/cie.h). Cost: two exact renders per
// view; deterministic.
#pragma once
#include <string>
#include <vector>

#include "bake/image_score.h"
#include "brdf/brdf.h"
#include "util/image.h"

namespace sepal {

struct PictureFigures {
    std::string view;
    double psnr = 0;
    double max_diff = 0;      // 8-bit levels
    double share_over16 = 0;  // of all pixels
    double delta_e = 0;       // mean CIEDE2000 over lit pixels
};

struct PictureComparison {
    std::vector<PictureFigures> views;
    double held_out_psnr = 0;     // pooled over views[1..] (0 when there are none)
    double held_out_delta_e = 0;  // mean over views[1..]
    double worst_psnr = 0;        // over every view
    Image truth, approx;          // the first view's images, clamped
};

// The default scene, then held_out_conditions(LightRange{}).
bool picture_views(std::vector<BakeView>* views, std::string* err);

bool compare_pictures(const Brdf& truth, const Brdf& approx, const std::vector<BakeView>& views, int size,
                      PictureComparison* out, std::string* err);

// Mean CIEDE2000 between two images of the same size over the pixels where `truth` has some
// channel above lit_threshold (display units); 0 when none is.
double mean_delta_e(const Image& truth, const Image& test, double lit_threshold = 2.0 / 255.0);

}  // namespace sepal
