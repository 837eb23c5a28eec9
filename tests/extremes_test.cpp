// Extremes of the encoder (offline/): grazing and degenerate parameterization frames, very
// sharp lobes, huge and tiny values, an all-zero BRDF, NaN and inf in measured input, 1x1
// and 256x256 factor textures, and the bake report's counts of every clamp and fallback.
// Every output is checked finite and, where an asset is made, valid for the runtime's own
// reader (sepal_asset_parse); every error bound is stated with the reason it holds. The
// second half of the file tests the runtime backends at the extremes.
// Test names contain "extreme": build/bin/sepal-tests -tc='*extreme*'.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "measured/cornell.h"
#include "factor/factor.h"
#include "factor/factor_error.h"
#include "factor/factor_internal.h"
#include "factor/factored.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "measured/merl.h"
#include "factor/param.h"
#include "bake/plan.h"
#include "bake/quantize.h"
#include "sepal/sepal_asset.h"
#include "measured/tabulated.h"
#include "test_brdfs.h"
#include "test_util.h"
#include <cctype>
#include "extremes_runtime_cases.h"
#include "internal.h"
#include <glm/glm.hpp>
#include "reference/render_exact.h"
#include "headless/sepal_headless.h"

using namespace sepal;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Param kAllParams[] = {Param::IncidentView, Param::GsHalf, Param::ViewHalf,
                            Param::Rusinkiewicz, Param::ElevAzim, Param::Axis, Param::GsMirror};
const Method kAllMethods[] = {Method::SVD, Method::ND, Method::NMF, Method::ACLS};

glm::dvec3 dir(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
double deg(double d) { return d * kPi / 180.0; }

std::unique_ptr<Brdf> brdf(const std::string& spec) {
    std::string err;
    std::unique_ptr<Brdf> b = make_brdf(spec, &err);
    INFO(err);
    REQUIRE(b);
    return b;
}

// f times a constant: huge and tiny versions of any BRDF.
class ScaledBrdf : public Brdf {
  public:
    ScaledBrdf(const Brdf& f, double s) : f_(f), s_(s) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override { return s_ * f_.eval(wi, wo); }
    std::string spec() const override { return f_.spec() + " x " + std::to_string(s_); }
    std::string model() const override { return "scaled"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return f_.isotropic(); }

  private:
    const Brdf& f_;
    double s_;
};

// Negative where wi.x > 0.5 (not a physical BRDF): the non-negative fits must clamp it and
// say how often.
class SignedBrdf : public Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (!(wi.z > 0) || !(wo.z > 0)) return glm::dvec3(0);
        return glm::dvec3(wi.x > 0.5 ? -0.1 : 0.2);
    }
    std::string spec() const override { return "test-signed"; }
    std::string model() const override { return "test-signed"; }
    std::string info() const override { return spec(); }
    bool isotropic() const override { return false; }
};

FactorResult factor_ok(const Brdf& b, const FactorOptions& o) {
    FactorResult r;
    std::string err;
    const bool ok = factor_brdf(b, o, &r, &err);
    INFO(err);
    REQUIRE(ok);
    for (const Factored& f : r.by_terms) {
        std::string why;
        CHECK_MESSAGE(validate_factored(f, &why), why);  // sizes, and every value finite
    }
    return r;
}

ErrorOptions quick_metric() {
    ErrorOptions e;
    e.dense = 0;  // the Monte Carlo metric only (the one bake ranks candidates with)
    return e;
}

// Encodes and parses with the runtime's reader; checks every texture's MIP chain.
void check_valid(const AssetData& a) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(encode_asset(a, &bytes, &err), err);
    sepal_asset parsed;
    sepal_error e{};
    REQUIRE_MESSAGE(sepal_asset_parse(bytes.data(), bytes.size(), &parsed, &e) == SEPAL_OK, e.message);
    for (uint32_t i = 0; i < parsed.texture_count; ++i) {
        const sepal_fmt_texture& d = parsed.textures[i].desc;
        uint32_t full = 1;
        for (uint32_t s = d.width; s > 1; s /= 2) ++full;
        CHECK((d.levels == 1 || d.levels == full));
        for (int c = 0; c < 3; ++c) CHECK((std::isfinite(d.scale[c]) && std::isfinite(d.bias[c])));
    }
    for (uint32_t p = 0; p < parsed.plan.pass_count; ++p)
        for (float c : parsed.passes[p].color) CHECK((c >= 0.0f && c <= 1.0f));
}

// A rigorous bound on |relative error after quantization - relative error before|, from
// the asset's own scales: every stored value is off by at most half a code step
// (scale / (2 (2^bits - 1))) plus float rounding of scale q + bias, bilinear lookups keep
// that bound, so a term's product is off by at most eG |H|max + |G|max eH + eG eH and f by
// the sum over terms times the colour ratio. The luminance of the difference is at most
// its largest channel and cos(theta_i) <= 1, so the RMS changes by at most that much
// (triangle inequality); relative errors divide by the reference RMS.
double quantization_bound(const AssetData& a, const Factored& f, double reference_rms) {
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (const AssetTexture& tg : a.textures) {
            if (tg.desc.role != SEPAL_ROLE_G) continue;
            const AssetTexture* th = nullptr;
            for (const AssetTexture& t : a.textures)
                if (t.desc.role == SEPAL_ROLE_H && t.desc.term == tg.desc.term) th = &t;
            REQUIRE(th);
            const int ch = int(tg.desc.channels) == 1 ? 0 : c;
            const double top = double((1u << tg.desc.bits) - 1);
            auto step = [&](const AssetTexture& t) {
                return t.desc.scale[ch] / (2 * top) + 1e-7 * (t.desc.scale[ch] + std::fabs(t.desc.bias[ch]));
            };
            auto largest = [&](const FactorTexture& t) {
                double m = 0;
                for (size_t i = size_t(ch); i < t.data.size(); i += size_t(t.channels)) m = std::max(m, std::fabs(double(t.data[i])));
                return m;
            };
            const FactorTerm& term = f.terms[tg.desc.term];
            const double eg = step(tg), eh = step(*th), gm = largest(term.g), hm = largest(term.h);
            sum += eg * hm + gm * eh + eg * eh;
        }
        worst = std::max(worst, sum * f.ratio[c]);
    }
    return reference_rms > 0 ? worst / reference_rms : 0.0;
}

// make_asset at `bits`, checked valid, and its measured relative error checked against the
// float error with the bound above. Returns the quantized relative error.
double quantize_and_check(const Factored& f, int terms, int bits, const ErrorEvaluator& ev, AssetData* out = nullptr,
                          BakeCounts* counts = nullptr) {
    CAPTURE(bits);
    QuantizeOptions q;
    q.bits = bits;
    AssetData a;
    std::string err;
    REQUIRE_MESSAGE(make_asset(f, terms, q, &a, &err, counts), err);
    check_valid(a);
    const Factored fk = f.prefix(terms);
    const double ef = ev.measure(fk).relative, eq = ev.measure(dequantize(a, fk)).relative;
    REQUIRE(std::isfinite(ef));
    REQUIRE(std::isfinite(eq));
    const double bound = quantization_bound(a, fk, ev.reference_rms());
    CHECK_MESSAGE(std::fabs(eq - ef) <= bound, "float " << ef << " quantized " << eq << " bound " << bound);
    if (out) *out = std::move(a);
    return eq;
}

BakeResult bake_ok(const Brdf& f, const BakeOptions& o) {
    BakeResult r;
    std::string err;
    const bool ok = bake(f, o, &r, &err);
    INFO(err);
    REQUIRE(ok);
    REQUIRE(r.winner >= 0);
    check_valid(r.asset);
    CHECK(r.counts.quantize_clamped == 0);  // quantize.h: 0 by construction
    return r;
}

BakeOptions small_bake(std::vector<Param> params, std::vector<int> res, std::vector<Method> methods,
                       std::vector<int> terms) {
    BakeOptions o;
    o.params = std::move(params);
    o.resolutions = std::move(res);
    o.methods = std::move(methods);
    o.terms = std::move(terms);
    // These cases test the factorization, quantization and plan at their limits: factors
    // of f itself, every candidate judged on the CPU backend (any parameterization), small
    // images. The radiance fit's own extremes are in tests/offline/bake/fidelity_test.cpp.
    o.radiance = false;
    o.target = Target::Cpu;
    o.judge_size = 32;
    return o;
}


bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const Json& member(const Json& v, const std::string& key) {
    INFO(key);
    REQUIRE(v.contains(key));
    return v[key];
}

// A texture-space constant factorization: f = value everywhere above the horizon.
Factored constant_factored(Param p, double value) {
    Factored f;
    f.param = p;
    f.n = 1;
    f.channels = 3;
    FactorTerm t{FactorTexture(1, 3), FactorTexture(1, 3)};
    for (int c = 0; c < 3; ++c) t.g.data[size_t(c)] = t.h.data[size_t(c)] = float(std::sqrt(value));
    f.terms.push_back(t);
    f.method = "constant";
    return f;
}

}  // namespace

// ---- 1. parameterizations -------------------------------------------------------------
TEST_CASE("extremes: parameterizations stay finite and inside [0,1] at grazing, h ~ t and h ~ n") {
    // Direction pairs at the extremes, all strictly above the horizon.
    std::vector<std::pair<glm::dvec3, glm::dvec3>> pairs;
    const double g = deg(89.9);
    const double az[] = {0, deg(37), deg(90), deg(180), deg(270), deg(359.9)};
    for (double a : az) {
        for (double b : az) pairs.push_back({dir(g, a), dir(g, b)});  // both grazing
        pairs.push_back({dir(g, a), dir(0, 0)});
        pairs.push_back({dir(0, 0), dir(g, a)});
    }
    // h nearly +-t or +-s: wi = wo grazing, down to 1e-9 rad above the horizon.
    for (double e : {deg(0.1), 1e-6, 1e-9})
        for (double a : {0.0, kPi / 2, kPi, 1.5 * kPi}) pairs.push_back({dir(kPi / 2 - e, a), dir(kPi / 2 - e, a)});
    // h = n: mirror pairs at every elevation, and wi = wo = n.
    for (double t : {1e-9, 0.3, g})
        for (double a : az) {
            const glm::dvec3 wi = dir(t, a);
            pairs.push_back({wi, glm::dvec3(-wi.x, -wi.y, wi.z)});
        }
    pairs.push_back({glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 1)});
    pairs.push_back({glm::dvec3(-0.0, -0.0, 1), glm::dvec3(-0.0, 0.0, 1)});

    for (Param p : kAllParams)
        for (HemiMap m : {HemiMap::XY, HemiMap::Parabolic}) {
            CAPTURE(std::string(param_name(p)));
            CAPTURE(std::string(map_name(m)));
            for (const auto& pr : pairs) {
                CAPTURE(pr.first);
                CAPTURE(pr.second);
                TexCoords tc;
                REQUIRE(param_forward(p, m, pr.first, pr.second, &tc));
                for (double u : {tc.x.x, tc.x.y, tc.y.x, tc.y.y}) CHECK((std::isfinite(u) && u >= 0.0 && u <= 1.0));
                // Back again where the maps resolve the points (a direction within about
                // 1e-8 of the horizon lands on the rim of the XY map in double precision).
                glm::dvec3 px, py, wi, wo;
                if (std::min(pr.first.z, pr.second.z) < 1e-6) continue;
                // gs-mirror's eye behind r's horizon reads H's rim (param.h): no way back.
                const glm::dvec3 r(-pr.first.x, -pr.first.y, pr.first.z);
                if (p == Param::GsMirror && glm::dot(pr.second, r) < 1e-6) continue;
                if (!factor_point(p, m, 0, tc.x, &px) || !factor_point(p, m, 1, tc.y, &py)) continue;
                REQUIRE(combine_points(p, px, py, &wi, &wo));
                // The round trip loses about 1e-16 / z near the rim, and acos(z) (elev-azim's
                // theta, rusinkiewicz's theta_h) about sqrt(1e-16) = 1.5e-8 rad next to the
                // pole: 1e-7 is above both, and far below a texel (1/256).
                CHECK(glm::length(wi - pr.first) < 1e-7);
                CHECK(glm::length(wo - pr.second) < 1e-7);
            }
            // Back-facing, on the horizon, and non-finite: refused, coordinates untouched.
            const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
            const std::pair<glm::dvec3, glm::dvec3> refused[] = {
                {dir(deg(90.1), 0.3), dir(0.2, 0)},  {dir(0.2, 0), dir(deg(179), 1)}, {glm::dvec3(1, 0, 0), dir(0.2, 0)},
                {glm::dvec3(1, 0, -1e-300), dir(0.2, 0)}, {glm::dvec3(nan, 0, 0.5), dir(0.2, 0)},
                {dir(0.2, 0), glm::dvec3(0, inf, 0.5)},  {glm::dvec3(0, 0, nan), dir(0.2, 0)}};
            for (const auto& pr : refused) {
                TexCoords tc;
                tc.x = tc.y = glm::dvec2(-7);
                CHECK_FALSE(param_forward(p, m, pr.first, pr.second, &tc));
                CHECK(tc.x == glm::dvec2(-7));
                CHECK(tc.y == glm::dvec2(-7));
            }
        }
}

TEST_CASE("extremes: gs-half keeps full precision as h nears t; its fallback is fixed and documented") {
    // h = (cos e, 0, sin e), wi and wo = h cos d +- s sin d: in the frame of eq. 6,
    // t' = (sin e, 0, -cos e) and s' = s, so wi = (0, sin d, cos d) there and its H
    // coordinate is exactly (1/2, (1 + sin d)/2) for every e. Computing t - (h.t) h as
    // written loses 1 - cos^2 e entirely below e ~ 1e-8 and moves u by about e; 1e-12
    // tells the two apart at e = 1e-9.
    const double d = 0.4;
    for (double e : {deg(0.1), 1e-6, 1e-9, 2e-12}) {
        CAPTURE(e);
        const glm::dvec3 h(std::cos(e), 0, std::sin(e)), s(0, 1, 0);
        const glm::dvec3 wi = h * std::cos(d) + s * std::sin(d), wo = h * std::cos(d) - s * std::sin(d);
        TexCoords tc;
        REQUIRE(param_forward(Param::GsHalf, HemiMap::XY, wi, wo, &tc));
        CHECK(std::fabs(tc.y.x - 0.5) < 1e-12);
        CHECK(std::fabs(tc.y.y - 0.5 * (1 + std::sin(d))) < 1e-12);
        CHECK_FALSE(frame_fallback(Param::GsHalf, glm::normalize(wi + wo)));
    }
    // Within 1e-12 of h = t (only on the horizon) the frame is taken from s, as the runtime
    // does: t' = s, s' = h x s, so the same wi reads (sin d, 0) there.
    const double e = 1e-13;
    const glm::dvec3 h(std::cos(e), 0, std::sin(e));
    CHECK(frame_fallback(Param::GsHalf, h));
    glm::dvec3 tp, sp;
    CHECK_FALSE(gs_half_frame(h, &tp, &sp));
    CHECK(glm::length(tp - glm::dvec3(0, 1, 0)) < 1e-15);
    CHECK(std::fabs(glm::dot(sp, h)) < 1e-15);
    CHECK(std::fabs(glm::length(sp) - 1) < 1e-15);
    // No other parameterization has a frame to fall back from at the tangent.
    for (Param p : {Param::IncidentView, Param::ViewHalf, Param::ElevAzim}) CHECK_FALSE(frame_fallback(p, h));
}

TEST_CASE("extremes: rusinkiewicz at h = n and elev-azim at the pole do not depend on rounding noise") {
    // A mirror pair has h = n exactly; a rounding-sized perturbation of wo gives h.x, h.y
    // of about 1e-17 whose atan2 is any angle at all, so d (and H's coordinate) would turn
    // by up to pi. With the fallback phi_h = 0 below sin(theta_h) = 1e-12 every variant
    // reads the same coordinates (to rounding: 1e-12).
    const glm::dvec3 wi = dir(0.7, 0.3);
    const glm::dvec3 wo(-wi.x, -wi.y, wi.z);
    TexCoords base;
    REQUIRE(param_forward(Param::Rusinkiewicz, HemiMap::XY, wi, wo, &base));
    CHECK(frame_fallback(Param::Rusinkiewicz, glm::normalize(wi + wo)));
    for (double nx : {-3e-17, -1e-17, 0.0, 1e-17, 3e-17})
        for (double ny : {-2e-17, 0.0, 2e-17}) {
            CAPTURE(nx);
            CAPTURE(ny);
            TexCoords tc;
            REQUIRE(param_forward(Param::Rusinkiewicz, HemiMap::XY, wi, wo + glm::dvec3(nx, ny, 0), &tc));
            CHECK(glm::length(tc.x - base.x) < 1e-12);
            CHECK(glm::length(tc.y - base.y) < 1e-12);
        }
    // Just outside the threshold the azimuth is real again: no fallback.
    CHECK_FALSE(frame_fallback(Param::Rusinkiewicz, glm::normalize(glm::dvec3(1e-9, 0, 1))));
    // elev-azim: a direction at the pole has azimuth 0 whatever the noise (u = 0).
    for (double nx : {-1e-17, 0.0, 1e-17}) {
        TexCoords tc;
        REQUIRE(param_forward(Param::ElevAzim, HemiMap::XY, glm::dvec3(nx, -nx, 1), dir(0.5, 1.0), &tc));
        CHECK(tc.y.x == 0.0);
        CHECK(tc.x.x == 0.0);  // theta_i = 0
    }
}

TEST_CASE("extremes: a degenerate frame in sampling is counted (rusinkiewicz at 1x1 samples h = n)") {
    std::unique_ptr<Brdf> lambert = brdf("lambert");
    FactorOptions o;
    o.param = Param::Rusinkiewicz;
    o.res = 1;
    o.terms = 1;
    // One texel each side, its centre (0.5, 0.5) is the pole: one pair, through the fallback.
    CHECK(factor_ok(*lambert, o).frame_fallbacks == 1);
    o.supersample = 3;  // 3 x 3 sub-samples a side: only the middle G one is the pole
    const FactorResult r3 = factor_ok(*lambert, o);
    detail::PairSampler s3(*lambert, o);
    CHECK(r3.frame_fallbacks == s3.frame_fallback_pairs());
    CHECK(r3.frame_fallbacks > 0);
    CHECK(r3.frame_fallbacks <= 9);  // at most every one of the 9 H sub-samples
    o.supersample = 1;
    for (int res : {2, 16}) {  // no texel centre is the pole at even sides
        o.res = res;
        CHECK(factor_ok(*lambert, o).frame_fallbacks == 0);
    }
    o.param = Param::GsHalf;
    o.res = 1;
    CHECK(factor_ok(*lambert, o).frame_fallbacks == 0);  // h = n is no trouble for eq. 6
    // The bake reports the winner's count.
    BakeOptions b = small_bake({Param::Rusinkiewicz}, {1}, {Method::WSVD}, {1});
    const BakeResult r = bake_ok(*lambert, b);
    CHECK(r.counts.frame_fallbacks == 1);
    bool noted = false;
    for (const std::string& n : r.notes) noted = noted || contains(n, "degenerate-frame fallback");
    CHECK(noted);
}

// ---- 2. very sharp lobes ----------------------------------------------------------------
TEST_CASE("extremes: very sharp lobes (phong exponent 1e4, ward alpha 1e-3) factor and quantize finitely") {
    struct Lobe {
        const char* spec;
        double diffuse;  // rho_d / pi
    };
    for (const Lobe& l : {Lobe{"phong:n=10000", 0.3 / kPi}, Lobe{"ward-duer:ax=0.001,ay=0.001", 0.1 / kPi}}) {
        CAPTURE(std::string(l.spec));
        std::unique_ptr<Brdf> f = brdf(l.spec);
        ErrorEvaluator ev(*f, quick_metric());
        std::string err;
        REQUIRE_MESSAGE(ev.init(&err), err);
        // Half-angle parameterizations: cos^1e4 falls to 1/e within 0.014 rad of the mirror
        // direction, Ward's lobe within 1e-3, and no 16x16 texel centre comes closer than
        // 0.06 to h = n: the factors can only carry the diffuse part. So the error is at
        // least that of the exact diffuse part alone (phong: 0.998, its lobe dominates the
        // Monte Carlo RMS; ward: 4e-8, its lobe is too narrow for 8000 pairs to meet) and
        // at most 0.04 above it: weighted fits pull a constant toward 0 below the horizon
        // (weight 0.01), which costs 1% at 1 term and up to 3.7% at 2 here (README: Lambert
        // 0.9% at 32x32). Quantization within the rigorous bound above.
        const double diffuse_only = ev.measure(constant_factored(Param::GsHalf, l.diffuse)).relative;
        for (Param p : {Param::GsHalf, Param::ViewHalf})
            for (Method m : kAllMethods) {
                CAPTURE(std::string(param_name(p)));
                CAPTURE(std::string(method_name(m)));
                FactorOptions o;
                o.param = p;
                o.res = 16;
                o.terms = 2;
                o.method = m;
                o.svd_weighted = true;
                const FactorResult r = factor_ok(*f, o);
                for (int k = 1; k <= 2; ++k) {
                    const double ef = ev.measure(r.by_terms[size_t(k - 1)]).relative;
                    CHECK(ef <= diffuse_only + 0.04);
                    CHECK(ef >= diffuse_only * (1 - 1e-3) - 1e-6);
                    for (int bits : {8, 16}) quantize_and_check(r.by_terms[size_t(k - 1)], k, bits, ev);
                }
            }
        // Incident/view: the texel grid is symmetric, so the mirror direction of every G
        // texel centre is an H texel centre and the matrix holds the peak itself: phong's
        // rho_s (n + 2) / (2 pi) = 796/sr, Ward's 0.5 / (pi ax ay 4 cos^2) beyond 1e5/sr at
        // grazing. Factors stay finite; Ward's needs more than the plan's 16 doublings and
        // is refused with the advice to cap it; capped, it bakes.
        FactorOptions o;
        o.param = Param::IncidentView;
        o.res = 16;
        o.terms = 1;
        o.method = Method::NMF;
        detail::PairSampler sampler(*f, o);
        double peak = 0;
        std::vector<float> rgb(size_t(sampler.cols()) * 3);
        std::vector<uint16_t> count(size_t(sampler.cols()));
        for (int row = 0; row < sampler.rows(); ++row) {
            REQUIRE(sampler.sample_row(row, rgb.data(), count.data(), &err));
            for (float v : rgb) peak = std::max(peak, double(v));
        }
        CHECK(peak >= (l.spec[0] == 'p' ? 790.0 : 1e5));
        const FactorResult r = factor_ok(*f, o);
        QuantizeOptions q;
        AssetData a;
        const bool planned = make_asset(r.factored, 1, q, &a, &err);
        if (l.spec[0] == 'p') {
            // A rank-1 fit spreads the mirror diagonal over whole rows and columns: its
            // coefficient stays far below the peak and fits the plan.
            REQUIRE_MESSAGE(planned, err);
            check_valid(a);
            CHECK(a.plan.doublings <= 16u);
            CHECK(std::isfinite(ev.measure(dequantize(a, r.factored)).relative));
        } else {
            CHECK_FALSE(planned);
            CHECK_MESSAGE(contains(err, "doublings"), err);
            CHECK_MESSAGE(contains(err, "--cap"), err);
            BakeOptions b = small_bake({Param::IncidentView}, {16}, {Method::NMF}, {1});
            b.cap = 100;
            const BakeResult br = bake_ok(*f, b);
            CHECK(br.counts.capped > 0);
            CHECK(br.counts.capped < br.counts.evaluations / 100);  // only the peak's samples
            CHECK(std::isfinite(br.candidates[size_t(br.winner)].error_quantized));
        }
    }
}

// ---- 3. huge and tiny values ------------------------------------------------------------
TEST_CASE("extremes: constant BRDFs of 1e4 and 1e-8 bake exactly, with the doublings they need") {
    std::unique_ptr<Brdf> lambert = brdf("lambert:rho=1");  // f = 1/pi
    for (double value : {1e4, 1e-8}) {
        CAPTURE(value);
        const ScaledBrdf f(*lambert, value * kPi);
        for (int res : {1, 16}) {
            CAPTURE(res);
            BakeOptions o = small_bake({Param::GsHalf, Param::IncidentView}, {res}, {Method::WSVD, Method::NMF}, {1});
            o.max_error = 1e-6;
            const BakeResult r = bake_ok(f, o);
            // A constant is rank 1 and a constant texture channel is stored exactly (code
            // 255 = its scale), so only float rounding remains: 1e-6 is 10x above it.
            const BakeCandidate& w = r.candidates[size_t(r.winner)];
            CHECK(w.error_float <= 1e-6);
            CHECK(w.error_quantized <= 1e-6);
            // One product pass whose colour times 2^doublings is f: 1e4 needs 14 doublings
            // (2^13 < 1e4 <= 2^14); 1e-8 needs none, its colour is 1e-8 itself.
            REQUIRE(r.asset.passes.size() == 1u);
            CHECK(int(r.asset.plan.doublings) == (value > 1 ? 14 : 0));
            const double drawn = std::ldexp(double(r.asset.passes[0].color[0]), int(r.asset.plan.doublings));
            CHECK(drawn == doctest::Approx(value).epsilon(1e-6));
            CHECK(r.counts.zero_scale_channels == 0);
            CHECK_FALSE(r.counts.all_zero);
        }
    }
}

TEST_CASE("extremes: peaks of 1e4 and values of 1e-8 cost exactly what f costs (power-of-two scales)") {
    // f x 2^14 (blinn n=20 peaks at 0.65/sr: 1.07e4/sr) and f x 2^-26 (1e-8/sr and below)
    // are f with the exponent moved: every step of sampling, factoring (the SVDs, the
    // weighted fits' relative thresholds), quantizing and planning is exact under a power
    // of two, so the relative errors must equal f's to rounding (1e-9) and the codes of
    // every texture must be the same bytes. Any absolute epsilon in the pipeline breaks it.
    std::unique_ptr<Brdf> blinn = brdf("blinn:n=20");
    BakeOptions o = small_bake({Param::GsHalf}, {16}, {Method::WSVD, Method::NMF}, {1, 2});
    // Every candidate's asset is compared, not only the winner's: the winner is chosen by its
    // image, and f x 2^14 is white on screen wherever f x 1 is not.
    o.keep_assets = true;
    const BakeResult base = bake_ok(*blinn, o);
    for (int e : {14, -26}) {
        CAPTURE(e);
        const ScaledBrdf f(*blinn, std::ldexp(1.0, e));
        const BakeResult r = bake_ok(f, o);
        REQUIRE(r.candidates.size() == base.candidates.size());
        for (size_t i = 0; i < r.candidates.size(); ++i) {
            CAPTURE(r.candidates[i].label());
            REQUIRE(r.candidates[i].ok);
            CHECK(r.candidates[i].error_float == doctest::Approx(base.candidates[i].error_float).epsilon(1e-9));
            CHECK(r.candidates[i].error_quantized == doctest::Approx(base.candidates[i].error_quantized).epsilon(1e-9));
            CHECK(r.candidates[i].passes == base.candidates[i].passes);
            const AssetData& a = r.candidates[i].asset;
            const AssetData& b = base.candidates[i].asset;
            REQUIRE(a.textures.size() == b.textures.size());
            for (size_t t = 0; t < a.textures.size(); ++t) CHECK(a.textures[t].data == b.textures[t].data);
        }
        // What the plan draws, colour x 2^doublings, is f's times 2^e (to float rounding), for
        // the same candidate as the base's winner.
        const AssetData& same = r.candidates[size_t(base.winner)].asset;
        REQUIRE(same.passes.size() == base.asset.passes.size());
        for (size_t p = 0; p < same.passes.size(); ++p)
            for (int c = 0; c < 3; ++c) {
                const double drawn = std::ldexp(double(same.passes[p].color[c]), int(same.plan.doublings));
                const double ref = std::ldexp(double(base.asset.passes[p].color[c]), int(base.asset.plan.doublings) + e);
                CHECK(drawn == doctest::Approx(ref).epsilon(1e-6));
            }
        CHECK(r.counts.quantize_clamped == 0);
    }
    // 2^17 (peaks of 8.5e4/sr, diffuse 1.25e4/sr) is beyond the plan's 16 doublings:
    // refused, naming --cap; capped at 2e4, it bakes and the lobe's clamps are counted.
    const ScaledBrdf beyond(*blinn, std::ldexp(1.0, 17));
    BakeResult r;
    std::string err;
    CHECK_FALSE(bake(beyond, o, &r, &err));
    CHECK_MESSAGE(contains(err, "doublings"), err);
    CHECK_MESSAGE(contains(err, "--cap"), err);
    BakeOptions capped = o;
    capped.cap = 2e4;
    const BakeResult rc = bake_ok(beyond, capped);
    CHECK(rc.counts.capped > 0);
    CHECK(rc.counts.capped < rc.counts.evaluations);
    CHECK(rc.asset.plan.doublings <= 16u);
}

// ---- 4. an all-zero BRDF ----------------------------------------------------------------
TEST_CASE("extremes: an all-zero BRDF bakes to a valid asset that renders black, and says so") {
    std::unique_ptr<Brdf> black = brdf("lambert:rho=0");
    // Every method at 1x1 and 16x16, 1 and 2 terms (2 at 1x1 is refused for rank alone).
    const BakeOptions o = small_bake({Param::GsHalf, Param::IncidentView}, {1, 16},
                                     {Method::WSVD, Method::ND, Method::NMF, Method::ACLS}, {1, 2});
    const BakeResult r = bake_ok(*black, o);
    for (const BakeCandidate& c : r.candidates) {
        CAPTURE(c.label());
        if (c.res == 1 && c.terms == 2) {
            CHECK_FALSE(c.ok);
            CHECK_MESSAGE(contains(c.note, "exceeds the rank"), c.note);
            continue;
        }
        REQUIRE_MESSAGE(c.ok, c.note);
        // The reference RMS is 0, so relative errors are 0 by definition; the absolute RMS
        // of the (zero) quantized factors must be exactly 0 too.
        CHECK(c.error_float == 0.0);
        CHECK(c.error_quantized == 0.0);
        CHECK(c.rms_quantized == 0.0);
        CHECK(c.passes == 1);
    }
    // The plan draws one constant pass of colour 0: black, in one pass per light.
    REQUIRE(r.asset.passes.size() == 1u);
    CHECK(r.asset.passes[0].op == SEPAL_OP_CONSTANT);
    CHECK(r.asset.passes[0].blend == SEPAL_BLEND_ADD);
    for (float c : r.asset.passes[0].color) CHECK(c == 0.0f);
    CHECK(r.asset.plan.doublings == 0u);
    CHECK(plan_all_zero(r.asset));
    CHECK(r.counts.all_zero);
    CHECK(r.counts.zero_textures == 2 * int(r.asset.material.terms));
    CHECK(r.counts.zero_scale_channels == 2 * int(r.asset.material.terms * r.asset.material.channels));
    bool noted = false;
    for (const std::string& n : r.notes) noted = noted || contains(n, "all-zero BRDF");
    CHECK(noted);
    // The smallest candidate wins the tie at error 0: 1x1, one term.
    CHECK(r.candidates[size_t(r.winner)].res == 1);
    // A plan outside bake still refuses all zeros unless asked (plan.h).
    AssetData a = r.asset;
    std::string err;
    CHECK_FALSE(build_plan(&a, &err));
    CHECK(contains(err, "all-zero"));

    // The command line: exit 0, the note on stdout and in the report, and the CPU backend
    // draws it black (a Lambert asset in the same scene is not, so the check means something).
    const std::string dir = sepal_test::temp_dir(), sepal = sepal_test::bin("sepal");
    std::string out;
    REQUIRE(sepal_test::run(sepal + " bake lambert:rho=0 --param gs-half --res 1,16 --terms 1 -o " + dir +
                                "/black.sepal --report " + dir + "/black.json",
                            &out) == 0);
    CHECK_MESSAGE(contains(out, "note: all-zero BRDF"), out);
    CHECK_MESSAGE(contains(out, "; all zero"), out);
    Json report;
    REQUIRE_MESSAGE(read_json_file(dir + "/black.json", &report, &err), err);
    CHECK(member(member(report, "counts"), "all_zero") == true);
    CHECK(member(member(report, "counts"), "zero_textures") == 2);
    REQUIRE(member(report, "notes").size() >= 1u);
    REQUIRE(sepal_test::run(sepal + " bake lambert --param gs-half --res 1 --terms 1 -o " + dir + "/grey.sepal", &out) == 0);
    for (const char* name : {"black", "grey"}) {
        CAPTURE(std::string(name));
        const std::string base = dir + "/" + name;
        REQUIRE(sepal_test::run(sepal + " render " + base + ".sepal --backend cpu --size 48x48 --background 0,0,0 -o " +
                                    base + ".png --float " + base + ".pfm",
                                &out) == 0);
        Image img;
        REQUIRE_MESSAGE(read_image(base + ".pfm", &img, &err), err);
        float lo = 1e30f, hi = -1e30f;
        for (float v : img.data) lo = std::min(lo, v), hi = std::max(hi, v);
        CHECK(lo >= 0.0f);
        if (name[0] == 'b') CHECK(hi == 0.0f);
        else CHECK(hi > 0.05f);
    }
}

// ---- 5. NaN and inf in measured input -----------------------------------------------------
TEST_CASE("extremes: NaN and inf in a MERL file are counted as missing, in info, bake stdout and the report") {
    // A synthetic MERL file (every value valid above the horizon, -1 below, as MERL), then
    // 3 NaN, 2 inf and 2 -inf in cells well above the horizon, one channel each.
    std::unique_ptr<Brdf> source = brdf("blinn:n=20");
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(encode_merl(*source, &bytes, &err), err);
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(write_file_atomic(dir + "/clean.binary", bytes.data(), bytes.size(), &err));
    const Tabulated layout = Tabulated::merl();
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const double bad[7] = {nan, nan, nan, inf, inf, -inf, -inf};
    for (int k = 0; k < 7; ++k) {
        const size_t cell = layout.index(10 + 5 * k, 20, 30 + k), plane = size_t(k % 3) * kMerlCells;
        const size_t at = 12 + 8 * (plane + cell);
        std::memcpy(&bytes[at], &bad[k], 8);  // little-endian host, as the format
    }
    REQUIRE(write_file_atomic(dir + "/corrupt.binary", bytes.data(), bytes.size(), &err));
    std::unique_ptr<Brdf> clean = brdf(dir + "/clean.binary"), corrupt = brdf(dir + "/corrupt.binary");
    const InputCounts c0 = clean->input_counts(), c1 = corrupt->input_counts();
    CHECK(c0.nonfinite == 0);
    CHECK(c1.nonfinite == 7);
    CHECK(c1.values == int64_t(3 * kMerlCells));
    CHECK(c1.negative == c0.negative);  // the -1 markers below the horizon, untouched
    CHECK(c1.missing == c0.missing + 7);
    CHECK(c1.filled == c0.filled + 7);
    // Bakes of both: 7 of 1.46 million cells get push-pull values from their neighbours; the
    // 16x16 factors read a handful of them at most, so the errors agree to 1e-3.
    const BakeOptions o = small_bake({Param::GsHalf}, {16}, {Method::NMF}, {1});
    const BakeResult r0 = bake_ok(*clean, o), r1 = bake_ok(*corrupt, o);
    CHECK(r1.counts.input.nonfinite == 7);
    CHECK(std::fabs(r1.candidates[0].error_quantized - r0.candidates[0].error_quantized) < 1e-3);
    bool noted = false;
    for (const std::string& n : r1.notes) noted = noted || contains(n, "7 NaN or inf");
    CHECK(noted);

    const std::string sepal = sepal_test::bin("sepal");
    std::string out;
    REQUIRE(sepal_test::run(sepal + " info " + dir + "/corrupt.binary", &out) == 0);
    CHECK_MESSAGE(contains(out, "3 NaN, 4 inf"), out);
    REQUIRE(sepal_test::run(sepal + " bake " + dir + "/corrupt.binary --param gs-half --res 16 --method nmf --terms 1 -o " +
                                dir + "/m.sepal --report " + dir + "/m.json",
                            &out) == 0);
    CHECK_MESSAGE(contains(out, "input: 4374000 values; 7 NaN or inf"), out);
    Json report;
    REQUIRE_MESSAGE(read_json_file(dir + "/m.json", &report, &err), err);
    const Json& input = member(member(report, "counts"), "input");
    CHECK(member(input, "nonfinite") == 7);
    CHECK(member(input, "missing") == c1.missing);
}

TEST_CASE("extremes: NaN and inf in Cornell text are refused with their count; huge values are counted") {
    const std::string head = "# c\n3\n450 550 650\n";
    const std::string good = "0.5 0 0.5 3.1 0.1 0.2 0.3\n0.4 0 0.6 3.0 0.1 0.2 0.3\n";
    CornellData d;
    std::string err;
    // Refused: the format marks missing samples with negative values and has no NaN; the
    // message names the first (file:line) and counts them all.
    CHECK_FALSE(parse_cornell(head + good + "0.5 0 0.5 0 0.1 nan 0.3\n0.5 0 0.5 0 inf 0.2 -inf\n", "c", &d, &err));
    CHECK_MESSAGE(contains(err, "c:6: 'nan' is not a finite number (3 NaN or inf values in the file, the first here)"), err);
    const std::string dir = sepal_test::temp_dir();
    const std::string text = head + good + "0.5 0 0.5 0 0.1 0.2 inf\n";
    REQUIRE(write_file_atomic(dir + "/nan.brdf", text.data(), text.size(), &err));
    CHECK(make_brdf(dir + "/nan.brdf", &err) == nullptr);
    CHECK_MESSAGE(contains(err, dir + "/nan.brdf:6: 'inf' is not a finite number (1 NaN or inf value in the file"), err);
    // A finite value beyond 1e30 (it would not survive the float table): missing, counted.
    const std::string huge = head + good + "0.3 0 0.3 3.1 0.1 1e35 0.3\n0.2 0 1.5707964 0 0.1 0.1 0.1\n";
    REQUIRE_MESSAGE(parse_cornell(huge, "c", &d, &err), err);
    CHECK(d.huge == 1u);
    CHECK(d.missing == 1u);
    CHECK(d.angles_clamped == 1u);  // 1.5707964 is pi/2 + 3e-8: within the slack, clamped
    REQUIRE(write_file_atomic(dir + "/huge.brdf", huge.data(), huge.size(), &err));
    std::unique_ptr<Brdf> f = brdf(dir + "/huge.brdf");
    const InputCounts c = f->input_counts();
    CHECK(c.huge == 1);
    CHECK(c.missing == 1);
    CHECK(c.negative == 0);
    CHECK(c.clamped == 1);
    CHECK(c.values == 4 * 3);
    for (int k = 0; k < 1000; ++k) {  // finite everywhere
        glm::dvec3 wi, wo;
        ErrorEvaluator::mc_pair(7, k, &wi, &wo);
        const glm::dvec3 v = f->eval(wi, wo);
        REQUIRE((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
    }
    const BakeResult r = bake_ok(*f, small_bake({Param::GsHalf}, {16}, {Method::NMF}, {1}));
    CHECK(r.counts.input.huge == 1);
    CHECK(r.counts.input.clamped == 1);
}

TEST_CASE("extremes: tables refuse NaN, inf and beyond-float values as missing, counted") {
    Tabulated t;
    std::string err;
    REQUIRE(t.init(4, 4, 8, ThetaHMapping::kSqrt, &err));
    for (size_t i = 0; i < t.size(); ++i) t.set(i, glm::dvec3(0.2));
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    t.set(3, glm::dvec3(nan, 0.1, 0.1));
    t.set(4, glm::dvec3(0.1, -inf, 0.1));
    t.set(5, glm::dvec3(0.1, 0.1, 1e39));  // finite as a double, inf as a float
    CHECK(t.rejected() == 3u);
    for (size_t i : {size_t(3), size_t(4), size_t(5)}) CHECK(t.state(i) == Tabulated::State::kMissing);
    Tabulated s;
    REQUIRE(s.init(4, 4, 8, ThetaHMapping::kLinear, &err));
    s.splat(to_half_diff(dir(0.3, 0), dir(0.3, kPi)), glm::dvec3(0.5));
    s.splat(to_half_diff(dir(0.3, 0), dir(0.4, kPi)), glm::dvec3(nan));
    s.splat(to_half_diff(dir(0.3, 0), dir(0.5, kPi)), glm::dvec3(0.5), inf);
    CHECK(s.rejected() == 2u);
    s.finish_splats();
    s.fill_missing();
    t.fill_missing();
    // Every lookup is finite, and near the one good sample it reads that sample's value.
    for (int k = 0; k < 1000; ++k) {
        glm::dvec3 wi, wo;
        ErrorEvaluator::mc_pair(11, k, &wi, &wo);
        for (const Tabulated* x : {&t, &s}) {
            const glm::dvec3 v = x->eval(wi, wo);
            REQUIRE((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
        }
    }
    CHECK(s.eval(dir(0.3, 0), dir(0.3, kPi)).x == doctest::Approx(0.5).epsilon(1e-6));
    CHECK(t.eval(dir(0.3, 0), dir(0.3, kPi)).x == doctest::Approx(0.2).epsilon(1e-6));
}

TEST_CASE("extremes: a BRDF returning NaN is refused by the bake, naming where") {
    sepal_test::NanBrdf f;
    BakeResult r;
    std::string err;
    CHECK_FALSE(bake(f, small_bake({Param::GsHalf}, {16}, {Method::WSVD}, {1}), &r, &err));
    // The first place it meets one: the error metric's pairs (before any factoring).
    CHECK_MESSAGE(contains(err, "the BRDF returned a non-finite value"), err);
    CHECK_MESSAGE(contains(err, "at wi = ("), err);
    // The engine alone refuses too, naming its own pair (tests/offline/factor/factor_test.cpp has more).
    FactorResult fr;
    CHECK_FALSE(factor_brdf(f, FactorOptions(), &fr, &err));
    CHECK_MESSAGE(contains(err, "non-finite value at wi = ("), err);
}

// ---- 6. every clamp and fallback counted --------------------------------------------------
TEST_CASE("extremes: the bake counts clamps and fallbacks exactly, the same for any thread count") {
    // The cap: counted per sample of the winner's factorization; equal totals at 1 and 2
    // threads (integer counts do not depend on the order).
    std::unique_ptr<Brdf> ward = brdf("ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15");
    BakeOptions o = small_bake({Param::GsHalf}, {16}, {Method::NMF}, {2});
    o.cap = 2;
    o.threads = 1;
    const BakeResult a = bake_ok(*ward, o);
    o.threads = 2;
    const BakeResult b = bake_ok(*ward, o);
    CHECK(a.counts.capped > 0);
    CHECK(a.counts.capped < a.counts.evaluations);
    const BakeCounts& x = a.counts;
    const BakeCounts& y = b.counts;
    CHECK(x.evaluations == y.evaluations);
    CHECK(x.capped == y.capped);
    CHECK(x.negative_clamped == y.negative_clamped);
    CHECK(x.frame_fallbacks == y.frame_fallbacks);
    CHECK(x.solver_fallbacks == y.solver_fallbacks);
    CHECK(x.zero_textures == y.zero_textures);
    CHECK(x.zero_scale_channels == y.zero_scale_channels);
    // One pass of a 16x16 gs-half matrix: evaluations = its valid sub-sample pairs.
    FactorOptions fo;
    fo.res = 16;
    detail::PairSampler sampler(*ward, fo);
    int64_t pairs = 0;
    std::vector<float> rgb(size_t(sampler.cols()) * 3);
    std::vector<uint16_t> count(size_t(sampler.cols()));
    std::string err;
    int64_t over = 0;
    for (int row = 0; row < sampler.rows(); ++row) {
        REQUIRE(sampler.sample_row(row, rgb.data(), count.data(), &err));
        for (int c = 0; c < sampler.cols(); ++c) {
            pairs += count[size_t(c)];
            if (count[size_t(c)] && (rgb[3 * c] > 2 || rgb[3 * c + 1] > 2 || rgb[3 * c + 2] > 2)) ++over;
        }
    }
    CHECK(x.evaluations == pairs);
    CHECK(x.capped == over);  // supersample 1: one evaluation per entry

    // Negative values (a non-physical BRDF): NMF clamps each negative matrix entry to 0 and
    // counts it, per channel plane: exactly 3 x the entries where f < 0.
    SignedBrdf signed_f;
    int64_t negative = 0;
    detail::PairSampler ss(signed_f, fo);
    for (int row = 0; row < ss.rows(); ++row) {
        REQUIRE(ss.sample_row(row, rgb.data(), count.data(), &err));
        for (int c = 0; c < ss.cols() * 3; ++c) negative += rgb[size_t(c)] < 0 ? 1 : 0;
    }
    REQUIRE(negative > 0);
    BakeOptions rgb_bake = small_bake({Param::GsHalf}, {16}, {Method::NMF}, {1});
    rgb_bake.colour_auto = false;  // grey: auto would factor one luminance plane
    const BakeResult s = bake_ok(signed_f, rgb_bake);
    CHECK(s.counts.negative_clamped == negative);
    bool noted = false;
    for (const std::string& n : s.notes) noted = noted || contains(n, "negative matrix entries clamped");
    CHECK(noted);
    // The signed SVD keeps them (no clamp).
    CHECK(bake_ok(signed_f, small_bake({Param::GsHalf}, {16}, {Method::WSVD}, {1})).counts.negative_clamped == 0);

    // Solver fallbacks: NMF on all zeros drives every factor entry to 0 and then has no
    // data left to scale by; each such update is counted. Lambert has data everywhere.
    std::unique_ptr<Brdf> black = brdf("lambert:rho=0"), grey = brdf("lambert");
    const BakeOptions nmf = small_bake({Param::GsHalf}, {16}, {Method::NMF}, {1});
    CHECK(bake_ok(*black, nmf).counts.solver_fallbacks > 0);
    CHECK(bake_ok(*grey, nmf).counts.solver_fallbacks == 0);
    const BakeResult g = bake_ok(*grey, small_bake({Param::GsHalf}, {16}, {Method::WSVD}, {1}));
    CHECK(g.counts.capped == 0);
    CHECK(g.counts.negative_clamped == 0);
    CHECK(g.counts.frame_fallbacks == 0);
    CHECK(g.counts.zero_textures == 0);
    CHECK(g.counts.input.values == 0);  // analytic: no input to count
}

// ---- 7. 1x1 and 256x256 factor textures -------------------------------------------------
TEST_CASE("extremes: 1x1 factors are constants: Lambert is exact at 1 term for every parameterization and method") {
    std::unique_ptr<Brdf> lambert = brdf("lambert:rho=0.2/0.5/0.8");
    ErrorEvaluator ev(*lambert, quick_metric());
    std::string err;
    REQUIRE_MESSAGE(ev.init(&err), err);
    for (Param p : kAllParams)
        for (HemiMap map : {HemiMap::XY, HemiMap::Parabolic})
            for (Method m : kAllMethods) {
                CAPTURE(std::string(param_name(p)));
                CAPTURE(std::string(map_name(map)));
                CAPTURE(std::string(method_name(m)));
                FactorOptions o;
                o.param = p;
                o.map = map;
                o.res = 1;
                o.terms = 1;
                o.method = m;
                const FactorResult r = factor_ok(*lambert, o);
                CHECK(r.rows == 1);
                CHECK(r.cols == 1);
                // f is one constant per channel and a 1x1 factor pair is one constant: exact
                // but for float storage (6e-8 relative); 1e-6 leaves room.
                CHECK(ev.measure(r.factored).relative <= 1e-6);
                for (int bits : {8, 16}) {
                    AssetData a;
                    // A constant channel quantizes to its scale exactly (code 2^bits - 1).
                    CHECK(quantize_and_check(r.factored, 1, bits, ev, &a) <= 1e-6);
                    for (const AssetTexture& t : a.textures) {
                        CHECK(t.desc.width == 1u);
                        CHECK(t.desc.levels == 1u);  // the full MIP chain of a 1x1 texture
                    }
                }
            }
    // Two terms need a rank 1x1 cannot have: refused, naming the size.
    FactorOptions o;
    o.res = 1;
    o.terms = 2;
    FactorResult r;
    CHECK_FALSE(factor_brdf(*lambert, o, &r, &err));
    CHECK_MESSAGE(contains(err, "1 x 1 sample matrix can have at --res 1 (at most 1)"), err);
    // The bake takes 1 (a power of two) and refuses 0, 3 and 512 with the range.
    const BakeResult b = bake_ok(*lambert, small_bake({Param::GsHalf}, {1, 2}, {Method::WSVD}, {1}));
    CHECK(b.asset.textures[0].desc.width == 1u);
    for (int res : {0, 3, 512}) {
        BakeResult x;
        CHECK_FALSE(bake(*lambert, small_bake({Param::GsHalf}, {res}, {Method::WSVD}, {1}), &x, &err));
        CHECK_MESSAGE(contains(err, "a power of two in 1..256"), err);
    }
    o.res = 257;
    CHECK_FALSE(validate_factor_options(o, &err));
    CHECK(contains(err, "1..256"));
}

TEST_CASE("extremes: 256x256 factors: svd, nmf and acls refuse naming nd; 256 textures quantize with 9 MIP levels") {
    std::unique_ptr<Brdf> blinn = brdf("blinn:n=50");
    FactorOptions o;
    o.res = 256;
    o.terms = 4;
    std::string err;
    for (Method m : {Method::SVD, Method::NMF, Method::ACLS}) {
        o.method = m;
        FactorResult r;
        CHECK_FALSE(factor_brdf(*blinn, o, &r, &err));  // refused before sampling: fast
        CHECK_MESSAGE(contains(err, "use --method nd"), err);
    }
    o.method = Method::ND;
    CHECK(validate_factor_options(o, &err));
    CHECK(estimate_memory_mb(o) < FactorOptions().max_memory_mb);  // nd fits the default limit
    BakeResult br;
    CHECK_FALSE(bake(*blinn, small_bake({Param::GsHalf}, {256}, {Method::WSVD}, {1}), &br, &err));
    CHECK_MESSAGE(contains(err, "every candidate failed"), err);
    CHECK_MESSAGE(contains(err, "use --method nd"), err);

    // 256x256 textures through quantization, the plan and the reader, without the 2.6e9
    // samples of a factorization (that is the skipped test below): blinn depends on h only,
    // so in gs-half G = f(h) at the texel centres and H = 1 is its bilinear limit (README).
    // Its error falls with the texel size squared, 64x from 32 to 256; at least 10x
    // leaves room for the rim, where the XY map compresses theta.
    ErrorEvaluator ev(*blinn, quick_metric());
    REQUIRE_MESSAGE(ev.init(&err), err);
    auto limit = [&](int n) {
        Factored f;
        f.param = Param::GsHalf;
        f.n = n;
        f.channels = 3;
        FactorTerm t{FactorTexture(n, 3), FactorTexture(n, 3)};
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = 2 * (i + 0.5) / n - 1, y = 2 * (j + 0.5) / n - 1, r2 = x * x + y * y;
                const double hz = r2 < 1 ? std::sqrt(1 - r2) : 0.0;  // outside the disk: the rim
                const double v = 0.3 / kPi + 0.5 * (50 + 8) / (8 * kPi) * std::pow(hz, 50);
                for (int c = 0; c < 3; ++c) t.g.at(i, j, c) = float(v), t.h.at(i, j, c) = 1.0f;
            }
        f.terms.push_back(t);
        return f;
    };
    // The formula is blinn's (brdf_models.h): check it against the model at two points.
    CHECK(blinn->eval(dir(0.3, 0), dir(0.3, kPi)).x == doctest::Approx(0.3 / kPi + 0.5 * 58 / (8 * kPi)));
    const double e32 = ev.measure(limit(32)).relative;
    const Factored f256 = limit(256);
    const double e256 = ev.measure(f256).relative;
    CHECK(e256 < e32 / 10);
    for (int bits : {8, 16}) {
        AssetData a;
        const double eq = quantize_and_check(f256, 1, bits, ev, &a);
        CHECK(eq < e32 / (bits == 16 ? 10 : 2));
        for (const AssetTexture& t : a.textures) {
            CHECK(t.desc.width == 256u);
            CHECK(t.desc.levels == 9u);  // 256, 128, ..., 1
        }
    }
}

TEST_CASE("extremes: a 256x256 bake through the streaming nd method" * doctest::skip()) {
    // 51468 x 51468 entries per sampling pass (1.77e9 valid pairs): minutes on two cores, so
    // skipped by default (run with --no-skip). The result is a valid asset whose 9-level
    // textures the reader takes, more accurate than the 32x32 bake of the same BRDF.
    // Measured: 197 s for the bake (the search's factorization and the winner's rebuild) on
    // the shared 2-core machine, 112 MB peak; error 0.0082 against 0.0205 at 32x32.
    std::unique_ptr<Brdf> blinn = brdf("blinn:n=50");
    const BakeResult r32 = bake_ok(*blinn, small_bake({Param::GsHalf}, {32}, {Method::ND}, {1}));
    BakeOptions with_mips = small_bake({Param::GsHalf}, {256}, {Method::ND}, {1});
    with_mips.mips = true;  // the full chain at 256 (9 levels) is part of what is checked
    const BakeResult r = bake_ok(*blinn, with_mips);
    CHECK(r.asset.textures[0].desc.width == 256u);
    CHECK(r.asset.textures[0].desc.levels == 9u);
    const double e = r.candidates[0].error_quantized, e32 = r32.candidates[0].error_quantized;
    MESSAGE("nd 256: error " << e << " (32: " << e32 << "), " << r.seconds << " s, " << r.counts.evaluations << " evaluations");
    CHECK(e < e32);
}

// ==== The runtime at the extremes ==========================================================
// Grazing light and view at 89.9 degrees, light and view below the horizon, h near t (gs-half) and h = n (rusinkiewicz), degenerate tangents, NaN and
// inf in mesh attributes, zero-area triangles, very sharp lobes, huge peaks and tiny
// values, an all-zero material, 1x1 and 256x256 factor textures, lights too bright for
// the exposure. Every backend and fallback mask: output finite, errors inside the bounds
// stated next to each check, every repair, skip and clamp counted in sepal_draw_stats.
// build/bin/sepal-bench-extremes draws the same cases into a contact sheet.
namespace extremes_runtime {
using namespace extremes;

namespace {

std::vector<uint8_t> bytes_of(const sepal::AssetData& a) {
    std::vector<uint8_t> b;
    std::string err;
    REQUIRE_MESSAGE(encode(a, &b, &err), err);
    return b;
}

// In display units (8-bit levels of the clamped image), as a person sees the frame.
sepal::ImageDiff against(const sepal::Image& reference_linear, const sepal::Image& img, double threshold) {
    return sepal::diff_images(display(reference_linear), display(img), threshold);
}

double peak(const sepal::Image& img) {
    double p = 0;
    for (float v : img.data) p = std::max<double>(p, v);
    return p;
}

int covered_pixels(const sepal::Image& img) {
    int n = 0;
    for (size_t i = 0; i < img.data.size(); i += 3) n += img.data[i] != 0 || img.data[i + 1] != 0 || img.data[i + 2] != 0;
    return n;
}

bool refuses_per_pixel(const Backend& b, sepal_param p) {
    return b.per_vertex() && (p == SEPAL_PARAM_RUSINKIEWICZ || p == SEPAL_PARAM_ELEV_AZIM);
}

// build/test-output/extremes_<name>.png, for a person to look at when a check fails.
void save(std::string name, const sepal::Image& img) {
    for (char& ch : name)
        if (!std::isalnum((unsigned char)ch) && ch != '.' && ch != '-') ch = '_';
    sepal::write_png(sepal_test::output_dir() + "/extremes_" + name + ".png", display(img), nullptr);
}

}  // namespace

// The bound of a backend against the CPU backend (the precise reference of the same
// factored material), in 8-bit display levels:
//   multipass (gles1, gles2, every mask): each pass and light rounds once in the 8-bit
//     framebuffer (half a level, a level where the blend unit truncates), and the final
//     doublings multiply that by 2^doublings; plus `geometry` levels for per-vertex factor
//     coordinates interpolated across triangles where the CPU evaluates per pixel;
//   gles2-fused: one rounding, plus `geometry`;
//   gles2-fused-pixel: one rounding, plus GL's 8-bit bilinear weights and MIP selection
//     against the CPU's level 0: 6 levels (measured up to 5.0 near the rusinkiewicz pole).
double level_bound(const Backend& b, const Frame& f, int passes, int lights, double geometry) {
    if (b.mode == SEPAL_MODE_FUSED_PIXEL) return 6.0;
    if (b.mode == SEPAL_MODE_FUSED_VERTEX) return 1.0 + geometry;
    return std::ldexp(1.0, f.stats.doublings) * passes * lights + geometry;
}

TEST_CASE("extreme frames: grazing 89.9 degrees, below the horizon, h near t, h = n, on every backend") {
    struct Case {
        const char* name;
        QuadConfig q;
        sepal_param param;
        bool black;  // light or eye below the horizon everywhere: the image must be 0
    };
    // Irradiance at the centre chosen so the lobe asset (f 0.02..0.6) shows mid-tones.
    const Case cases[] = {
        {"grazing 89.9/89.9", {QuadLight::kDirectional, 89.9, 89.9, 20}, SEPAL_PARAM_GS_HALF, false},
        {"grazing 89.9/89.9 rusinkiewicz", {QuadLight::kDirectional, 89.9, 89.9, 20}, SEPAL_PARAM_RUSINKIEWICZ, false},
        {"retro 89.9 (h 0.1 deg from t)", {QuadLight::kAtEye, 89.9, 89.9, 20}, SEPAL_PARAM_GS_HALF, false},
        {"retro 89.99 (h 0.01 deg from t)", {QuadLight::kAtEye, 89.99, 89.99, 20}, SEPAL_PARAM_GS_HALF, false},
        {"normal incidence (h = n)", {QuadLight::kAtEye, 0, 0, 1.2}, SEPAL_PARAM_RUSINKIEWICZ, false},
        {"normal incidence gs-half", {QuadLight::kAtEye, 0, 0, 1.2}, SEPAL_PARAM_GS_HALF, false},
        {"mirror 86 (h = n)", {QuadLight::kMirror, 86, 86, 1.2}, SEPAL_PARAM_RUSINKIEWICZ, false},
        {"mirror 86 gs-half", {QuadLight::kMirror, 86, 86, 1.2}, SEPAL_PARAM_GS_HALF, false},
        {"light below 90.1", {QuadLight::kDirectional, 90.1, 60, 1}, SEPAL_PARAM_GS_HALF, true},
        {"view below 120 (back-facing frame)", {QuadLight::kDirectional, 45, 120, 1}, SEPAL_PARAM_GS_HALF, true},
    };
    for (const Case& c : cases) {
        const std::string name = c.name;
        CAPTURE(name);
        const sepal_ports::SceneSetup s = quad_scene(c.q);
        const int vertices = s.mesh.vertex_count;
        const std::vector<uint8_t> bytes = bytes_of(lobe_asset(c.param, 32));
        const Frame cpu = render(all_backends().back(), bytes, s);
        REQUIRE_MESSAGE(cpu.ok, cpu.err);
        CHECK(cpu.finite);
        save(name + "_cpu", cpu.image);
        const int pixels = covered_pixels(display(cpu.image));
        CAPTURE(pixels);
        CAPTURE(cpu.stats.below_horizon);
        CAPTURE(cpu.stats.param_fallbacks);
        if (c.black) {
            // The quad covers 82x82 pixels; every one has the light or the eye below.
            CHECK(peak(cpu.image) == 0.0);
            CHECK(cpu.stats.below_horizon == 82 * 82);
        } else {
            CHECK(peak(cpu.image) > 0.1);  // lit: the light's intensity makes up for cos(theta_i)
            CHECK(cpu.stats.below_horizon == 0);
            CHECK(pixels == 82 * 82);
        }
        CHECK(cpu.stats.fallback_tangents == 0);
        CHECK(cpu.stats.pixel_frame_fallbacks == 0);
        // gs-half's frame is undefined within 1e-3 rad of h = t: at 89.99 degrees every
        // pixel takes (and counts) the fallback, at 89.9 none does.
        if (name.find("retro 89.99") == 0) CHECK(cpu.stats.param_fallbacks == 82 * 82);
        if (name.find("retro 89.9 ") == 0) CHECK(cpu.stats.param_fallbacks == 0);
        // Normal incidence: h = n exactly up to float rounding, the rusinkiewicz pole.
        if (name == "normal incidence (h = n)") CHECK(cpu.stats.param_fallbacks > 82 * 82 / 2);
        for (const Backend& b : all_backends()) {
            if (b.cpu) continue;
            CAPTURE(b.name);
            const Frame f = render(b, bytes, s);
            if (refuses_per_pixel(b, c.param)) {
                CHECK_FALSE(f.ok);  // refused with a reason, never drawn wrong
                CHECK(f.err.find("per-pixel") != std::string::npos);
                continue;
            }
            REQUIRE_MESSAGE(f.ok, f.err);
            save(name + "_" + b.name, f.image);
            CAPTURE(f.stats.below_horizon);
            CAPTURE(f.stats.param_fallbacks);
            CAPTURE(f.stats.doublings);
            CHECK(f.stats.fallback_tangents == 0);
            CHECK(f.stats.bad_vertices == 0);
            CHECK(f.stats.exposure_clamped == 0);
            if (c.black) {
                CHECK(peak(f.image) == 0.0);
                CHECK(f.stats.below_horizon == vertices);  // every vertex-light pair, counted
                continue;
            }
            CHECK(f.stats.below_horizon == 0);
            if (name.find("retro 89.99") == 0) CHECK(f.stats.param_fallbacks == vertices);
            if (name.find("retro 89.9 ") == 0) CHECK(f.stats.param_fallbacks == 0);
            // h = n at every vertex (to float rounding): counted per vertex.
            if (c.param == SEPAL_PARAM_RUSINKIEWICZ && name.find("grazing") != 0)
                CHECK(f.stats.param_fallbacks > vertices / 2);
            // 3 levels of geometry: per-vertex coordinates and irradiance on a 24x24 quad
            // whose frames turn by up to 12 degrees (measured: 1.4 levels where 0 doublings).
            const double bound = level_bound(b, f, 1, 1, 3.0);
            const sepal::ImageDiff d = against(cpu.image, f.image, bound);
            CAPTURE(bound);
            CAPTURE(d.psnr);
            CAPTURE(d.max_diff);
            CHECK(d.share_over == 0.0);
            CHECK(d.psnr > 36.0);
        }
    }
}

TEST_CASE("extreme meshes: degenerate tangents, NaN and inf attributes, zero-area triangles") {
    const BrokenMesh m = broken_sphere(2);
    // 4 bad vertices two rings apart, 6 triangles each; 6 + 1 zero-area triangles appended.
    REQUIRE(m.skipped_triangles == 24);
    REQUIRE(m.zero_area_triangles == 7);
    REQUIRE(m.fallback_tangents == 13);
    const std::vector<uint8_t> bytes = bytes_of(signed_asset(SEPAL_PARAM_GS_HALF));  // anisotropic, signed
    for (const Backend& b : all_backends()) {
        CAPTURE(b.name);
        const Frame broken = render(b, bytes, m.broken);
        const Frame clean = render(b, bytes, m.clean);
        REQUIRE_MESSAGE(broken.ok, broken.err);
        REQUIRE_MESSAGE(clean.ok, clean.err);
        save("broken_sphere_" + b.name, broken.image);
        CHECK(broken.finite);
        // Every repair and skip counted, with the numbers the mesh was built with.
        CHECK(broken.stats.fallback_tangents == m.fallback_tangents);
        CHECK(broken.stats.bad_vertices == m.bad_vertices);
        CHECK(broken.stats.skipped_triangles == m.skipped_triangles);
        CHECK(broken.stats.zero_area_triangles == m.zero_area_triangles);
        // The clean twin: tangents already repaired, bad triangles gone (its bad vertices
        // stay in the array, unreferenced, and are still counted as such).
        CHECK(clean.stats.fallback_tangents == 0);
        CHECK(clean.stats.bad_vertices == m.bad_vertices);
        CHECK(clean.stats.skipped_triangles == 0);
        CHECK(clean.stats.zero_area_triangles == 0);
        // Same picture: the runtime does to the broken mesh exactly what it documents. The
        // twin's tangents were repaired in double by the test, the runtime's in float, so
        // coordinates may differ in the last bit: a level on GL, 1e-4 of a level on the CPU.
        const sepal::ImageDiff d = sepal::diff_images(display(clean.image), display(broken.image), b.cpu ? 1e-3 : 1.0);
        CAPTURE(d.max_diff);
        CHECK(d.share_over == 0.0);
        if (b.cpu) {
            CHECK(broken.stats.pixel_frame_fallbacks == 0);
            CHECK(broken.stats.negative_clamped > 0);  // the signed asset dips below 0 somewhere
        }
    }
    // The skipped triangles really are missing: the clean sphere without broken vertices
    // covers more pixels.
    const Frame whole = render(all_backends().back(), bytes, sphere_scene(2));
    const Frame holes = render(all_backends().back(), bytes, m.broken);
    CHECK(covered_pixels(display(whole.image)) > covered_pixels(display(holes.image)));
}

TEST_CASE("extreme meshes: an index past the vertices is refused, not read") {
    sepal_ports::SceneSetup s = sphere_scene(1);
    s.indices[7] = uint16_t(s.mesh.vertex_count + 3);
    const std::vector<uint8_t> bytes = bytes_of(lobe_asset(SEPAL_PARAM_GS_HALF, 16));
    for (const Backend& b : all_backends()) {
        if (b.mask) continue;
        CAPTURE(b.name);
        const Frame f = render(b, bytes, s);
        CHECK_FALSE(f.ok);
        CHECK(f.err.find("index 7") != std::string::npos);
    }
}

TEST_CASE("extreme assets: sharp lobes, huge peaks, tiny values, all zero, 1x1 and 256x256 textures") {
    struct Case {
        std::string name;
        sepal::AssetData asset;
        std::string exact_spec;  // the BRDF for an exact render, if any
        double max_share16;      // share of pixels allowed over 16 levels against the CPU backend
        double min_psnr;         // against the CPU backend, dB
    };
    std::vector<Case> cases;
    std::string err;
    sepal::AssetData baked;
    // Per-vertex coordinates on a 64x32 sphere against per-pixel ones, and GL's MIP
    // selection near silhouettes against the CPU's level 0: a few pixels of the highlight
    // and rim differ by tens of levels (measured up to 0.64% of pixels over 16 levels on
    // the one-unit path with 7 doublings; 35 dB there), the rest within a few.
    REQUIRE_MESSAGE(bake_asset("phong:n=10000", SEPAL_PARAM_GS_HALF, 32, &baked, &err), err);
    cases.push_back({"phong n=1e4", baked, "phong:n=10000", 0.01, 35.0});
    REQUIRE_MESSAGE(bake_asset("ward:ax=0.001,ay=0.001", SEPAL_PARAM_GS_HALF, 32, &baked, &err), err);
    cases.push_back({"ward alpha=1e-3", baked, "ward:ax=0.001,ay=0.001", 0.01, 35.0});
    // The spike's tails are 16-bit texels the GL backends round to 8 bits at upload (and
    // fused-pixel MIP-maps): the white highlight is smaller there, up to 2.1% of the
    // pixels; everything outside it must match.
    cases.push_back({"huge peaks 1e4", huge_peak_asset(), "", 0.03, 20.0});
    cases.push_back({"tiny 1e-8", tiny_asset(), "", 0.0, 100.0});
    cases.push_back({"all zero", zero_asset(), "", 0.0, 100.0});
    cases.push_back({"1x1 textures", constant_asset(SEPAL_PARAM_IV, 1, 0.125), "constant", 0.01, 35.0});
    cases.push_back({"256x256 textures", lobe_asset(SEPAL_PARAM_GS_HALF, 256), "", 0.01, 35.0});
    const sepal_ports::SceneSetup s = sphere_scene(2);
    for (const Case& c : cases) {
        CAPTURE(c.name);
        const std::vector<uint8_t> bytes = bytes_of(c.asset);
        const Frame cpu = render(all_backends().back(), bytes, s);
        REQUIRE_MESSAGE(cpu.ok, cpu.err);
        CHECK(cpu.finite);
        CHECK(cpu.stats.nonfinite_clamped == 0);
        save(c.name + "_cpu", cpu.image);
        if (c.name == "tiny 1e-8") {
            CHECK(peak(cpu.image) > 1e-9);  // kept, not flushed to 0: f ~ 6e-9 per sr
            CHECK(peak(cpu.image) < 1e-7);
        }
        if (c.name == "all zero" || c.name == "tiny 1e-8") CHECK(peak(display(cpu.image)) < 0.5 / 255);
        if (!c.exact_spec.empty()) {
            std::unique_ptr<sepal::Brdf> brdf = c.exact_spec == "constant" ? std::make_unique<ConstantBrdf>(0.125)
                                                                            : sepal::make_brdf(c.exact_spec, &err);
            REQUIRE(brdf);
            sepal::Image exact;
            REQUIRE(sepal::render_exact(*brdf, s.scene, s.mesh, s.width, s.height, &exact, nullptr, &err));
            const sepal::ImageDiff de = against(exact, cpu.image, 8.0);
            CAPTURE(de.psnr);
            CAPTURE(de.share_over);
            if (c.exact_spec == "constant") {
                CHECK(de.max_diff < 0.01);  // 1x1 textures: exact, up to float against double
            } else if (c.name == "ward alpha=1e-3") {
                // Measured 74 dB: no pixel of this scene lands in a 1e-3 lobe, so the exact
                // render shows the diffuse part only, and so does the asset.
                CHECK(de.psnr > 60.0);
            } else {
                // phong n=1e4 at 32x32, one NMF term: the bake reports relative error 1.0;
                // this is the factorization's error, not the runtime's (measured 21.3 dB).
                CHECK(de.psnr > 20.0);
            }
        }
        for (const Backend& b : all_backends()) {
            if (b.cpu) continue;
            CAPTURE(b.name);
            const Frame f = render(b, bytes, s);
            REQUIRE_MESSAGE(f.ok, f.err);
            save(c.name + "_" + b.name, f.image);
            CAPTURE(f.stats.doublings);
            CAPTURE(f.stats.exposure_stages);
            CHECK(f.stats.exposure_clamped == 0);
            CHECK(f.stats.nonfinite_clamped == 0);
            const sepal::ImageDiff d = against(cpu.image, f.image, 16.0);
            CAPTURE(d.psnr);
            CAPTURE(d.max_diff);
            CAPTURE(d.share_over);
            CHECK(d.share_over <= c.max_share16);
            CHECK(d.psnr > c.min_psnr);
            if (c.name == "all zero" || c.name == "tiny 1e-8") CHECK(peak(f.image) == 0.0);  // below half a level
            // The huge peak needs 13 doublings on GL ES 1.1; staged, the 0.3 floor keeps its
            // precision (one stage: 11 dB, 42% of pixels off by more than 8 levels).
            if (c.name == "huge peaks 1e4" && b.gles == 1) CHECK(f.stats.exposure_stages == 2);
        }
    }
}

TEST_CASE("extreme lights: an exposure past 2^-30 and overflowing irradiance are clamped and counted") {
    const std::vector<uint8_t> bytes = bytes_of(lobe_asset(SEPAL_PARAM_GS_HALF, 32));
    // 1e12: the plan paths would need 2^37; they stop at 2^-30 and the lit side is white.
    sepal_ports::SceneSetup bright = sphere_scene(1);
    for (int c = 0; c < 3; ++c) bright.scene.lights[0].intensity[c] = 1e12f;
    // 3e38 (finite) over a light 0.05 from the surface: intensity / d^2 overflows float.
    sepal_ports::SceneSetup overflow = sphere_scene(1);
    const float near[3] = {0.0f, -1.05f, 0.0f};
    std::copy(near, near + 3, overflow.scene.lights[0].position);
    for (int c = 0; c < 3; ++c) overflow.scene.lights[0].intensity[c] = 3e38f;
    for (const Backend& b : all_backends()) {
        CAPTURE(b.name);
        const Frame fb = render(b, bytes, bright);
        REQUIRE_MESSAGE(fb.ok, fb.err);
        CHECK(fb.finite);
        const bool plan = !b.cpu && b.mode == SEPAL_MODE_MULTIPASS;
        CHECK(fb.stats.exposure_clamped == (plan && b.gles == 1 ? 1 : 0));  // GL ES 2 colours are not clamped
        CHECK(peak(display(fb.image)) == 1.0);
        // A half-float target holds up to 65504: 1e12 overflows there, clamped on read-back.
        if (b.float_target) CHECK(fb.stats.nonfinite_clamped > 0);
        const Frame fo = render(b, bytes, overflow);
        REQUIRE_MESSAGE(fo.ok, fo.err);
        CHECK(fo.finite);
        CAPTURE(fo.stats.nonfinite_clamped);
        CHECK(fo.stats.nonfinite_clamped > 0);
        CHECK(peak(display(fo.image)) == 1.0);
    }
}

TEST_CASE("extreme parameterizations: texture coordinates near h = t and h = n against the encoder's double maths") {
    // The encoder's param_forward (offline/factor/param.h, double precision) is the reference.
    auto dir = [](double theta_deg, double phi_deg) {
        const double t = theta_deg * M_PI / 180, p = phi_deg * M_PI / 180;
        return glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    };
    auto check = [](sepal_param p, sepal::Param op, const glm::dvec3& wi, const glm::dvec3& wo, double tol,
                    int fallbacks) {
        const float fi[3] = {float(wi.x), float(wi.y), float(wi.z)}, fo[3] = {float(wo.x), float(wo.y), float(wo.z)};
        float g[2], h[2];
        int taken = 0;
        REQUIRE(srt::param_texcoords(p, SEPAL_MAP_XY, fi, fo, g, h, true, &taken) == 1);
        CHECK(taken == fallbacks);  // counted exactly where documented
        // The reference from the float inputs, so only the runtime's arithmetic is measured.
        sepal::TexCoords ref;
        REQUIRE(sepal::param_forward(op, sepal::HemiMap::XY, glm::dvec3(fi[0], fi[1], fi[2]),
                                     glm::dvec3(fo[0], fo[1], fo[2]), &ref));
        CAPTURE(h[0] - ref.y.x);
        CAPTURE(h[1] - ref.y.y);
        CHECK(std::fabs(g[0] - ref.x.x) < 1e-6);
        CHECK(std::fabs(g[1] - ref.x.y) < 1e-6);
        if (fallbacks == 0) {
            CHECK(std::fabs(h[0] - ref.y.x) < tol);
            CHECK(std::fabs(h[1] - ref.y.y) < tol);
        }
        for (float v : {g[0], g[1], h[0], h[1]}) CHECK(std::isfinite(v));
    };
    // gs-half near its singularity h = t: both directions near grazing, close to t.
    // Float inputs carry 6e-8 rad of rounding, which the frame magnifies by 1/|h - t|:
    // 2e-4 in texture units at 0.1 degrees (one texel of a 32x32 map is 0.03).
    check(SEPAL_PARAM_GS_HALF, sepal::Param::GsHalf, dir(89.9, 0.05), dir(89.9, -0.05), 2e-4, 0);
    check(SEPAL_PARAM_GS_HALF, sepal::Param::GsHalf, dir(89.9, 0.0), dir(89.8, 0.0), 2e-4, 0);
    check(SEPAL_PARAM_GS_HALF, sepal::Param::GsHalf, dir(60, 10), dir(70, 170), 1e-6, 0);
    // Within 1e-3 rad of t the frame is undefined for mediump shaders; the runtime takes
    // Gram-Schmidt on s there, everywhere alike, and counts it.
    check(SEPAL_PARAM_GS_HALF, sepal::Param::GsHalf, dir(89.99, 0.01), dir(89.99, -0.01), 0, 1);
    // gs-mirror's frame about r = (-wi.x, -wi.y, wi.z) is singular at r = t: a light grazing
    // along -t, whatever the eye. Away from it, and 0.1 degrees from it, as gs-half's; within
    // 1e-3 rad, Gram-Schmidt on s, counted.
    check(SEPAL_PARAM_GS_MIRROR, sepal::Param::GsMirror, dir(40, 30), dir(35, 215), 1e-6, 0);
    check(SEPAL_PARAM_GS_MIRROR, sepal::Param::GsMirror, dir(89.9, 180.05), dir(30, 10), 2e-4, 0);
    check(SEPAL_PARAM_GS_MIRROR, sepal::Param::GsMirror, dir(89.99, 180.01), dir(30, 10), 0, 1);
    // An eye behind r's horizon (light and eye on the same side, far from n) reads H's rim,
    // not its fold: wi = wo grazing is wo = -r nearly, which an XY map folds onto the lobe's
    // peak at the centre.
    for (const glm::dvec3& w : {dir(60, 0), dir(89, 40)}) {
        check(SEPAL_PARAM_GS_MIRROR, sepal::Param::GsMirror, w, w, 1e-6, 0);
        const float fw[3] = {float(w.x), float(w.y), float(w.z)};
        float g[2], h[2];
        REQUIRE(srt::param_texcoords(SEPAL_PARAM_GS_MIRROR, SEPAL_MAP_XY, fw, fw, g, h, false, nullptr) == 1);
        const float x = 2 * h[0] - 1, y = 2 * h[1] - 1;
        CHECK(x * x + y * y == doctest::Approx(1.0).epsilon(1e-5));
    }
    // rusinkiewicz near its pole h = n: mirror pairs whose half vector is tilted from n by
    // 1e-2 .. 1e-5 rad towards azimuth 50 degrees. sin(theta_h) comes from h.x, h.y (the
    // old sqrt(1 - h.z^2) gave 0 below 3e-4 rad: an error of the tilt itself, 5e-5 at 1e-4).
    const double phi = 50 * M_PI / 180;
    const glm::dvec3 axis(-std::sin(phi), std::cos(phi), 0);  // tilting about it moves n towards phi
    auto rot = [&](const glm::dvec3& v, double a) {  // Rodrigues
        return v * std::cos(a) + glm::cross(axis, v) * std::sin(a) + axis * glm::dot(axis, v) * (1 - std::cos(a));
    };
    const glm::dvec3 wi0 = dir(40, 30), wo0(-wi0.x, -wi0.y, wi0.z);
    for (double tilt : {1e-2, 1e-4, 1e-5}) {
        CAPTURE(tilt);
        check(SEPAL_PARAM_RUSINKIEWICZ, sepal::Param::Rusinkiewicz, rot(wi0, tilt), rot(wo0, tilt), 3e-6, 0);
    }
    // Within 1e-6 rad of the pole phi_h is taken as 0 (the encoder's atan2(0, 0) convention)
    // and counted; the coordinates stay finite.
    check(SEPAL_PARAM_RUSINKIEWICZ, sepal::Param::Rusinkiewicz, rot(wi0, 1e-7), rot(wo0, 1e-7), 0, 1);
    check(SEPAL_PARAM_RUSINKIEWICZ, sepal::Param::Rusinkiewicz, wi0, wo0, 0, 1);
    // axis near its poles w = +-t (grazing along the tangent): alpha as atan2(w.t, |(w.s,
    // w.n)|), not asin(w.t), whose slope is unbounded there, and the runtime's branch-free
    // atan2 (5e-7 rad, 1.5e-7 in texture units): within 1e-6 of the encoder's double maths
    // down to 1e-3 rad from t.
    for (double off : {1e-1, 1e-2, 1e-3}) {
        CAPTURE(off);
        const double el = 90 - off * 180 / M_PI;  // degrees from n, in the t-n plane
        const glm::dvec3 wi(std::sin(el * M_PI / 180), 1e-4, std::cos(el * M_PI / 180)), wo = dir(30, 200);
        const glm::dvec3 wn = glm::normalize(wi);
        const float fi[3] = {float(wn.x), float(wn.y), float(wn.z)}, fo[3] = {float(wo.x), float(wo.y), float(wo.z)};
        float g[2], h[2];
        int taken = 0;
        REQUIRE(srt::param_texcoords(SEPAL_PARAM_AXIS, SEPAL_MAP_XY, fi, fo, g, h, false, &taken) == 1);
        CHECK(taken == 0);
        sepal::TexCoords ref;
        REQUIRE(sepal::param_forward(sepal::Param::Axis, sepal::HemiMap::XY, glm::dvec3(fi[0], fi[1], fi[2]),
                                     glm::dvec3(fo[0], fo[1], fo[2]), &ref));
        CHECK(std::fabs(g[0] - ref.x.x) < 1e-6);
        CHECK(std::fabs(g[1] - ref.x.y) < 1e-6);
        CHECK(std::fabs(h[0] - ref.y.x) < 1e-6);
        CHECK(std::fabs(h[1] - ref.y.y) < 1e-6);
    }
    // Below the horizon (per vertex, for interpolation only): finite, beta clamped to the
    // texture's edge on the side of its s component; at w = t exactly beta is 0 (the centre).
    const float below[3] = {0.0f, 0.6f, -0.8f}, at_t[3] = {1.0f, 0.0f, 0.0f}, up[3] = {0.0f, 0.0f, 1.0f};
    float g[2], h[2];
    CHECK(srt::param_texcoords(SEPAL_PARAM_AXIS, SEPAL_MAP_XY, below, up, g, h, false, nullptr) == 0);
    CHECK(h[0] == 1.0f);
    CHECK(g[0] == doctest::Approx(0.5));
    CHECK(srt::param_texcoords(SEPAL_PARAM_AXIS, SEPAL_MAP_XY, at_t, up, g, h, false, nullptr) == 0);
    CHECK(g[0] == doctest::Approx(1.0));
    CHECK(h[0] == doctest::Approx(0.5));
    // The runtime's atan2 (srt::atan2_poly, branch-free for the batched set-up) against
    // libm's in every octant and on its axes (signed zeros included: 1e-30 x sin(-pi)
    // underflows to -0), at magnitudes 1e-30 .. 1e30; at the origin 0 rather than pi.
    double worst = 0;
    for (double scale : {1e-30, 1e-3, 1.0, 1e30})
        for (int k = 0; k <= 3600; ++k) {
            const double a = -M_PI + 2 * M_PI * k / 3600;
            const float y = float(scale * std::sin(a)), x = float(scale * std::cos(a));
            worst = std::max(worst, std::fabs(double(srt::atan2_poly(y, x)) - std::atan2(double(y), double(x))));
        }
    CAPTURE(worst);
    CHECK(worst < 6e-7);  // measured 4.7e-7
    CHECK(srt::atan2_poly(0.0f, 0.0f) == 0.0f);
    CHECK(srt::atan2_poly(1.0f, 0.0f) == doctest::Approx(M_PI / 2));
    CHECK(srt::atan2_poly(0.0f, -1.0f) == doctest::Approx(M_PI));
}

TEST_CASE("extreme assets: the reader takes 1x1 factors with one level and 256x256 ones; NaN is refused") {
    for (int side : {1, 256}) {
        CAPTURE(side);
        const sepal::AssetData a = lobe_asset(SEPAL_PARAM_GS_HALF, side);
        REQUIRE(a.textures[0].desc.levels == uint32_t(side == 1 ? 1 : 9));
        std::vector<uint8_t> b = bytes_of(a);
        auto asset = std::make_unique<sepal_asset>();
        sepal_error e{};
        CHECK(sepal_asset_parse(b.data(), b.size(), asset.get(), &e) == SEPAL_OK);
        CHECK(asset->textures[0].desc.width == uint32_t(side));
    }
    // Scales, biases, pass colours and colour ratios are the only floats an asset carries;
    // the encoder's own check (encode_asset parses with the runtime's reader) refuses NaN
    // and inf in each, so no asset can feed one to a backend.
    for (int what = 0; what < 4; ++what) {
        CAPTURE(what);
        sepal::AssetData a = lobe_asset(SEPAL_PARAM_GS_HALF, 4);
        if (what == 0) a.textures[0].desc.scale[1] = NAN;
        if (what == 1) a.textures[1].desc.bias[0] = INFINITY;
        if (what == 2) a.passes[0].color[2] = NAN;
        if (what == 3) a.material.ratio[0] = NAN;
        std::vector<uint8_t> b;
        std::string err;
        CHECK_FALSE(encode(a, &b, &err));
        CHECK(!err.empty());
    }
}
}  // namespace extremes_runtime

TEST_CASE("extremes: the exact renderer on a mesh with NaN and zero attributes is finite and counts them") {
    using namespace extremes;
    BrokenMesh m = broken_sphere(1);
    rebind(&m.broken);
    std::string err;
    std::unique_ptr<sepal::Brdf> brdf = sepal::make_brdf("blinn:n=20", &err);
    REQUIRE_MESSAGE(brdf, err);
    sepal::Image img;
    sepal::ExactStats stats;
    const sepal_ports::SceneSetup& s = m.broken;
    REQUIRE_MESSAGE(sepal::render_exact(*brdf, s.scene, s.mesh, s.width, s.height, &img, &stats, &err), err);
    int64_t nonfinite = 0;
    for (float v : img.data) nonfinite += !std::isfinite(v);
    // Before: 42 NaN values from NaN normals and tangents passing a `< 1e-12` test.
    CHECK(nonfinite == 0);
    CHECK(stats.degenerate_frames > 0);
}

TEST_CASE("extremes: a bake whose best candidate misses half of f says so in a note") {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("phong:n=10000", &err);
    REQUIRE_MESSAGE(f, err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {16};
    o.methods = {sepal::Method::WSVD};
    o.terms = {1};
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
    // The lobe is far narrower than a 16x16 texel: the error is ~1 and the report says it.
    CHECK(r.candidates[size_t(r.winner)].error_quantized >= 0.5);
    bool said = false;
    for (const std::string& n : r.notes) said = said || n.find(">= 0.5") != std::string::npos;
    CHECK(said);
    // An easy BRDF gets no such note.
    f = sepal::make_brdf("lambert", &err);
    REQUIRE(sepal::bake(*f, o, &r, &err));
    for (const std::string& n : r.notes) CHECK(n.find(">= 0.5") == std::string::npos);
}
