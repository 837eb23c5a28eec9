#include "sampling/metrics.h"

#include <cmath>

#include "brdf/brdf_util.h"
#include "sampling/factored_fit.h"
#include "util/parallel.h"

namespace sepal {

double normalized_mae(const Brdf& truth, const ApproxFn& approx, int pairs, uint64_t seed, PairDensity density) {
    double num = 0, den = 0;
    Rng rng(seed);
    auto draw = [&]() {
        if (density == PairDensity::SolidAngle) return rng.hemisphere();
        const double t = rng.uniform() * 0.5 * kPi;
        return dir_from_angles(t, rng.uniform() * 2.0 * kPi);
    };
    for (int n = 0; n < pairs; ++n) {
        const glm::dvec3 wi = draw(), wo = draw();
        const double f = luminance(truth.eval(wi, wo)) * wi.z;
        num += std::fabs(approx(wi, wo) - f);
        den += std::fabs(f);
    }
    return den > 0 ? num / den : 0.0;
}

std::vector<glm::dvec3> judge_views(bool isotropic) {
    std::vector<glm::dvec3> v;
    for (double t : {5.0, 20.0, 35.0, 50.0, 62.0, 72.0, 80.0, 87.0})
        for (double p : isotropic ? std::vector<double>{0.0} : std::vector<double>{0.0, 30.0, 60.0, 90.0})
            v.push_back(dir_from_degrees(t, p));
    return v;
}

double relative_variance(const Brdf& f, const sepal_sampler& s, const std::vector<glm::dvec3>& views,
                         int samples, uint64_t seed) {
    std::vector<double> rel(views.size(), 0.0);
    parallel_for(views.size(), 0, [&](size_t vi) {
        const glm::dvec3& wo = views[vi];
        const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
        sepal_sampler_view v;
        sepal_sampler_set_view(&s, w, &v);
        double m = 0, m2 = 0;
        for (int i = 0; i < samples; ++i) {
            const float u[2] = {float((i + counter_uniform(seed + vi, 2 * uint64_t(i))) / samples),
                                float(counter_uniform(seed + vi, 2 * uint64_t(i) + 1))};
            float wi[3], pdf;
            double x = 0;
            if (sepal_sampler_sample(&v, u, wi, &pdf) == 1)
                x = luminance(f.eval(glm::dvec3(wi[0], wi[1], wi[2]), wo)) * wi[2] / pdf;
            m += x, m2 += x * x;
        }
        m /= samples, m2 /= samples;
        rel[vi] = m > 0 ? std::max(0.0, m2 - m * m) / (m * m) : 0.0;
    });
    double sum = 0;
    for (double r : rel) sum += r;
    return views.empty() ? 0.0 : sum / double(views.size());
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
