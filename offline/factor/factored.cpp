#include "factor/factored.h"

#include <cmath>

#include "sepal/sepal_asset.h"

namespace sepal {

const char* colour_name(ColourMode c) { return c == ColourMode::PerChannel ? "rgb" : "luminance"; }

bool parse_colour(const std::string& name, ColourMode* c) {
    if (name == "rgb") *c = ColourMode::PerChannel;
    else if (name == "luminance") *c = ColourMode::Luminance;
    else return false;
    return true;
}

bool Factored::non_negative() const {
    for (const FactorTerm& t : terms)
        for (const FactorTexture* tex : {&t.g, &t.h})
            for (float v : tex->data)
                if (v < 0) return false;
    return true;
}

Factored Factored::prefix(int k) const {
    Factored out = *this;
    if (k >= 0 && k < int(out.terms.size())) out.terms.resize(size_t(k));
    return out;
}

bool validate_factored(const Factored& f, std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = why;
        return false;
    };
    if (f.n < 1 || f.n > 4096) return fail("factor texture side out of range");
    const int want = f.colour == ColourMode::PerChannel ? 3 : 1;
    if (f.channels != want) return fail("channel count does not match the colour mode");
    if (!std::isfinite(f.ratio.x) || !std::isfinite(f.ratio.y) || !std::isfinite(f.ratio.z))
        return fail("non-finite colour ratio");
    for (const FactorTerm& t : f.terms)
        for (const FactorTexture* tex : {&t.g, &t.h}) {
            // G is f.n texels per side; H may differ (FactorOptions::res_h), alike across terms.
            const int n = tex == &t.g ? f.n : f.terms[0].h.n;
            if (n < 1 || n > 4096 || tex->n != n || tex->channels != f.channels ||
                tex->data.size() != size_t(n) * n * f.channels)
                return fail("factor texture size does not match");
            for (float v : tex->data)
                if (!std::isfinite(v)) return fail("non-finite factor value");
        }
    return true;
}

BilinearTaps bilinear_taps(int n, const glm::dvec2& uv, bool wrap) {
    const double sx = uv.x * n - 0.5, sy = uv.y * n - 0.5;
    const double fx0 = std::floor(sx), fy0 = std::floor(sy);
    const double ax = sx - fx0, ay = sy - fy0;
    int i0 = int(fx0), j0 = int(fy0), i1 = i0 + 1, j1 = j0 + 1;
    auto fix = [&](int& k) {
        if (wrap) {
            k %= n;
            if (k < 0) k += n;
        } else {
            k = k < 0 ? 0 : (k >= n ? n - 1 : k);
        }
    };
    fix(i0), fix(i1), fix(j0), fix(j1);
    return BilinearTaps{{j0 * n + i0, j0 * n + i1, j1 * n + i0, j1 * n + i1},
                        {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay}};
}

void bilinear_lookup(const FactorTexture& t, const glm::dvec2& uv, bool wrap, double* out) {
    const BilinearTaps b = bilinear_taps(t.n, uv, wrap);
    for (int c = 0; c < t.channels; ++c) {
        const float* d = t.data.data();
        out[c] = b.weight[0] * d[size_t(b.index[0]) * t.channels + c] + b.weight[1] * d[size_t(b.index[1]) * t.channels + c] +
                 b.weight[2] * d[size_t(b.index[2]) * t.channels + c] + b.weight[3] * d[size_t(b.index[3]) * t.channels + c];
    }
}

namespace {
// Sums the first k_count terms; when prefixes is given, stores every partial sum too.
glm::dvec3 sum_terms(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo,
                     int k_count, glm::dvec3* prefixes) {
    TexCoords tc;
    if (!param_forward(f.param, f.map, wi, wo, &tc)) {
        if (prefixes)
            for (int k = 0; k < k_count; ++k) prefixes[k] = glm::dvec3(0);
        return glm::dvec3(0);
    }
    const bool wrap_g = factor_wraps(f.param, 0), wrap_h = factor_wraps(f.param, 1);
    // Reciprocal form: G is read a second time at the swapped pair's G coordinate.
    TexCoords swapped;
    const bool reciprocal = f.form == Form::Reciprocal;
    if (reciprocal) param_forward(f.param, f.map, wo, wi, &swapped);
    glm::dvec3 sum(0);
    for (int k = 0; k < k_count; ++k) {
        double g[3], h[3], g2[3] = {1, 1, 1};
        bilinear_lookup(f.terms[size_t(k)].g, tc.x, wrap_g, g);
        bilinear_lookup(f.terms[size_t(k)].h, tc.y, wrap_h, h);
        if (reciprocal) bilinear_lookup(f.terms[size_t(k)].g, swapped.x, wrap_g, g2);
        if (f.channels == 3) sum += glm::dvec3(g[0] * h[0] * g2[0], g[1] * h[1] * g2[1], g[2] * h[2] * g2[2]);
        else sum += glm::dvec3(g[0] * h[0] * g2[0]);
        if (prefixes) prefixes[k] = sum * f.ratio;
    }
    return sum * f.ratio;
}
}  // namespace

void evaluate_prefixes(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo,
                       glm::dvec3* out) {
    sum_terms(f, wi, wo, f.term_count(), out);
}

glm::dvec3 evaluate(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo, int terms) {
    const int k_count = terms < 0 || terms > f.term_count() ? f.term_count() : terms;
    return sum_terms(f, wi, wo, k_count, nullptr);
}

glm::dvec3 evaluate_radiance(const Factored& f, const glm::dvec3& wi, const glm::dvec3& wo, int terms) {
    if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
    const glm::dvec3 sum = evaluate(f, wi, wo, terms);
    if (!f.radiance) return sum * wi.z;
    const double window = double(sepal_horizon_window(float(f.horizon), float(wi.z)));
    glm::dvec3 d = f.diffuse;
    if (f.diffuse_side >= 2)
        for (int c = 0; c < 3; ++c)
            d[c] *= double(sepal_diffuse_profile(f.diffuse_profile.data(), uint32_t(f.diffuse_side), SEPAL_FMT_DIFFUSE_RGB_F32, float(wi.z),
                                                 float(wo.z), c));
    return sum * window + d * wi.z;
}

}  // namespace sepal
