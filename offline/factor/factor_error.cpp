#include "factor/factor_error.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "util/parallel.h"

namespace sepal {

namespace {
constexpr double kTwoPi = 6.283185307179586;
constexpr int64_t kChunk = 2048;

glm::dvec3 hemi(double z, double phi) {
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

bool finite3(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct Sums {
    double lum = 0, rgb = 0, ref = 0;
};

// Sums over pairs [0, count) in fixed chunks, combined in chunk order.
template <class PairFn, class TermFn>
Sums chunked_sums(int64_t count, int threads, PairFn pair, TermFn term) {
    const size_t chunks = size_t((count + kChunk - 1) / kChunk);
    std::vector<Sums> part(chunks);
    parallel_for(chunks, threads, [&](size_t c) {
        const int64_t k0 = int64_t(c) * kChunk, k1 = std::min(count, k0 + kChunk);
        for (int64_t k = k0; k < k1; ++k) {
            glm::dvec3 wi, wo;
            pair(k, &wi, &wo);
            term(k, wi, wo, &part[c]);
        }
    });
    Sums s;
    for (const Sums& p : part) s.lum += p.lum, s.rgb += p.rgb, s.ref += p.ref;
    return s;
}
}  // namespace

void ErrorEvaluator::mc_pair(uint64_t seed, int64_t k, glm::dvec3* wi, glm::dvec3* wo) {
    // Uniform over the hemisphere: cos(theta) uniform in [0, 1), phi uniform.
    const uint64_t b = uint64_t(k) * 4;
    *wi = hemi(counter_uniform(seed, b), kTwoPi * counter_uniform(seed, b + 1));
    *wo = hemi(counter_uniform(seed, b + 2), kTwoPi * counter_uniform(seed, b + 3));
}

void ErrorEvaluator::dense_pair(int d, int64_t k, glm::dvec3* wi, glm::dvec3* wo) {
    const int64_t cells = int64_t(d) * d;
    const int64_t a = k / cells, b = k % cells;
    auto dir = [&](int64_t cell) {
        const int64_t iz = cell / d, ip = cell % d;
        return hemi((double(iz) + 0.5) / d, kTwoPi * (double(ip) + 0.5) / d);
    };
    *wi = dir(a);
    *wo = dir(b);
}

ErrorEvaluator::ErrorEvaluator(const Brdf& brdf, const ErrorOptions& o) : brdf_(brdf), o_(o) {}

bool ErrorEvaluator::init(std::string* err) {
    if (o_.mc_pairs < 1 || o_.mc_pairs > 10000000 || o_.dense < 0 || o_.dense > 64) {
        if (err) *err = "error metric sizes out of range";
        return false;
    }
    mc_f_.assign(size_t(o_.mc_pairs), glm::dvec3(0));
    const int64_t dense_n = int64_t(o_.dense) * o_.dense * o_.dense * o_.dense;
    dense_f_.assign(size_t(dense_n), glm::dvec3(0));
    std::atomic<bool> bad{false};
    const Sums mc = chunked_sums(
        o_.mc_pairs, o_.threads,
        [&](int64_t k, glm::dvec3* wi, glm::dvec3* wo) { mc_pair(o_.seed, k, wi, wo); },
        [&](int64_t k, const glm::dvec3& wi, const glm::dvec3& wo, Sums* s) {
            const glm::dvec3 f = brdf_.eval(wi, wo);
            if (!finite3(f)) bad = true;
            mc_f_[size_t(k)] = f;
            const double y = luminance(f) * wi.z;
            s->ref += y * y;
        });
    const Sums dn = chunked_sums(
        dense_n, o_.threads,
        [&](int64_t k, glm::dvec3* wi, glm::dvec3* wo) { dense_pair(o_.dense, k, wi, wo); },
        [&](int64_t k, const glm::dvec3& wi, const glm::dvec3& wo, Sums* s) {
            const glm::dvec3 f = brdf_.eval(wi, wo);
            if (!finite3(f)) bad = true;
            dense_f_[size_t(k)] = f;
            const double y = luminance(f) * wi.z;
            s->ref += y * y;
        });
    if (bad) {
        // Name the first such pair (in pair order: the same one whatever the threads).
        if (err) {
            glm::dvec3 wi(0), wo(0);
            for (size_t k = 0; k < mc_f_.size(); ++k)
                if (!finite3(mc_f_[k])) {
                    mc_pair(o_.seed, int64_t(k), &wi, &wo);
                    break;
                }
            if (wi == glm::dvec3(0))
                for (size_t k = 0; k < dense_f_.size(); ++k)
                    if (!finite3(dense_f_[k])) {
                        dense_pair(o_.dense, int64_t(k), &wi, &wo);
                        break;
                    }
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "the BRDF returned a non-finite value while measuring the error, at wi = "
                          "(%.6f, %.6f, %.6f), wo = (%.6f, %.6f, %.6f)",
                          wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
            *err = buf;
        }
        return false;
    }
    ref_rms_ = std::sqrt(mc.ref / o_.mc_pairs);
    ref_dense_ = dense_n ? std::sqrt(dn.ref / double(dense_n)) : 0.0;
    ready_ = true;
    return true;
}

ApproxError ErrorEvaluator::measure(const Factored& f) const {
    ApproxError e;
    if (!ready_) return e;
    auto term = [&](const std::vector<glm::dvec3>& ref) {
        return [&f, &ref](int64_t k, const glm::dvec3& wi, const glm::dvec3& wo, Sums* s) {
            const glm::dvec3 d = evaluate_radiance(f, wi, wo) - ref[size_t(k)] * wi.z;
            const double l = luminance(d);
            s->lum += l * l;
            s->rgb += (d.x * d.x + d.y * d.y + d.z * d.z) / 3;
        };
    };
    const Sums mc = chunked_sums(
        o_.mc_pairs, o_.threads,
        [&](int64_t k, glm::dvec3* wi, glm::dvec3* wo) { mc_pair(o_.seed, k, wi, wo); },
        term(mc_f_));
    e.rms = std::sqrt(mc.lum / o_.mc_pairs);
    e.rms_rgb = std::sqrt(mc.rgb / o_.mc_pairs);
    e.relative = ref_rms_ > 0 ? e.rms / ref_rms_ : 0.0;
    const int64_t dense_n = int64_t(dense_f_.size());
    if (dense_n) {
        const Sums dn = chunked_sums(
            dense_n, o_.threads,
            [&](int64_t k, glm::dvec3* wi, glm::dvec3* wo) { dense_pair(o_.dense, k, wi, wo); },
            term(dense_f_));
        e.dense_rms = std::sqrt(dn.lum / double(dense_n));
        e.dense_relative = ref_dense_ > 0 ? e.dense_rms / ref_dense_ : 0.0;
    }
    return e;
}

std::vector<TermError> measure_terms(const ErrorEvaluator& ev, const FactorResult& result) {
    std::vector<TermError> out;
    for (size_t k = 0; k < result.by_terms.size(); ++k) {
        TermError t;
        t.terms = int(k + 1);
        t.e = ev.measure(result.by_terms[k]);
        t.matrix_rms = k < result.matrix_rms.size() ? result.matrix_rms[k] : 0.0;
        out.push_back(t);
    }
    return out;
}

double sample_relative_rms(const Factored& f, const std::vector<BrdfSample>& samples,
                           double min_half_angle_deg, bool rgb) {
    return sample_relative_rms([&f](const glm::dvec3& wi, const glm::dvec3& wo) { return evaluate_radiance(f, wi, wo); },
                               samples, min_half_angle_deg, rgb);
}

double sample_relative_rms(const RadianceFn& radiance, const std::vector<BrdfSample>& samples,
                           double min_half_angle_deg, bool rgb) {
    const double min_cos = std::cos(min_half_angle_deg * 3.14159265358979323846 / 180.0);
    double num = 0, den = 0;
    for (const BrdfSample& s : samples) {
        if (!(s.wi.z > 0) || !(s.wo.z > 0)) continue;
        if (glm::normalize(s.wi + s.wo).z > min_cos) continue;  // inside the peak's cone
        const glm::dvec3 a = radiance(s.wi, s.wo), b = s.value * s.wi.z;
        if (rgb) {
            num += glm::dot(a - b, a - b), den += glm::dot(b, b);
        } else {
            const double d = luminance(a) - luminance(b);
            num += d * d, den += luminance(b) * luminance(b);
        }
    }
    return den > 0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace sepal
