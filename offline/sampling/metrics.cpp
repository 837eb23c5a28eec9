#include "sampling/metrics.h"

#include <cmath>

#include "brdf/brdf_util.h"
#include "sampling/factored_fit.h"
#include "util/parallel.h"

namespace sepal {

double normalized_mae(const Brdf& truth, const ApproxFn& approx, int pairs, uint64_t seed) {
    double num = 0, den = 0;
    Rng rng(seed);
    for (int n = 0; n < pairs; ++n) {
        const glm::dvec3 wi = rng.hemisphere(), wo = rng.hemisphere();
        const double f = luminance(truth.eval(wi, wo)) * wi.z;
        num += std::fabs(approx(wi, wo) - f);
        den += std::fabs(f);
    }
    return den > 0 ? num / den : 0.0;
}

double factored_lum(const sepal_sampler_view& v, const glm::dvec3& wi) {
    // The same sampler without its colour tables evaluates to the luminance.
    sepal_sampler grey = *v.sampler;
    grey.colour_a = grey.colour_b = grey.colour_c = nullptr;
    sepal_sampler_view g = v;
    g.sampler = &grey;
    const float w[3] = {float(wi.x), float(wi.y), float(wi.z)};
    float rgb[3];
    return sepal_sampler_eval(&g, w, rgb) ? double(rgb[0]) : 0.0;
}

namespace {
double pixel_value(const Image& img, size_t p) {
    double s = 0;
    for (int c = 0; c < img.channels; ++c) s += img.data[p * img.channels + size_t(c)];
    return s / img.channels;
}
}  // namespace

double image_mse(const Image& a, const Image& b, const std::vector<uint8_t>& mask) {
    const size_t n = size_t(a.width) * a.height;
    double s = 0;
    size_t count = 0;
    for (size_t p = 0; p < n; ++p) {
        if (!mask.empty() && !mask[p]) continue;
        const double d = pixel_value(a, p) - pixel_value(b, p);
        s += d * d;
        ++count;
    }
    return count ? s / double(count) : 0.0;
}

double image_variance(const std::vector<Image>& trials, const std::vector<uint8_t>& mask) {
    if (trials.size() < 2) return 0.0;
    const size_t n = size_t(trials[0].width) * trials[0].height;
    const double t = double(trials.size());
    double s = 0;
    size_t count = 0;
    for (size_t p = 0; p < n; ++p) {
        if (!mask.empty() && !mask[p]) continue;
        double mean = 0, sq = 0;
        for (const Image& img : trials) mean += pixel_value(img, p);
        mean /= t;
        for (const Image& img : trials) {
            const double d = pixel_value(img, p) - mean;
            sq += d * d;
        }
        s += sq / (t - 1.0);
        ++count;
    }
    return count ? s / double(count) : 0.0;
}

}  // namespace sepal
