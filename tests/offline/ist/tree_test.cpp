// The second and third levels of inverse shade trees (bases -> 2D factors -> 1D curves),
// the tree format, edits, and the scattered refinement they rest on.
#include <doctest/doctest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "factor/factor.h"
#include "factor/scattered.h"
#include "ist/figures.h"
#include "ist/tree.h"
#include "reference/render_exact.h"
#include "util/io.h"
#include "util/parallel.h"
#include "ist_fixture.h"
#include "spec/spec.h"
#include "test_util.h"

using namespace sepal;

namespace {

// Cosine-weighted RMS of f against g at a set of pairs, relative to g's RMS.
template <class F, class G>
double relative_rms(const std::vector<DirPair>& pairs, F f, G g) {
    double e = 0, r = 0;
    for (const DirPair& p : pairs) {
        const glm::dvec3 a = f(p.wi, p.wo), b = g(p.wi, p.wo);
        e += glm::dot(a - b, a - b) * p.wi.z * p.wi.z;
        r += glm::dot(b, b) * p.wi.z * p.wi.z;
    }
    return std::sqrt(e / r);
}

}  // namespace

TEST_CASE("ist tree: every level stays close to the bases it came from, and the bases to the truth") {
    const sepal_test::IstCase& c = sepal_test::ist_case();
    const ShadeTree& t = sepal_test::ist_case_tree();
    REQUIRE(t.basis_count() == 4);
    REQUIRE(t.level_errors.size() == 4);
    const TermMatch m = match_terms(c.sacls, c.truth.maps);
    std::string err;
    for (int j = 0; j < 4; ++j) {
        CAPTURE(j);
        const LevelErrors& le = t.level_errors[size_t(j)];
        MESSAGE("basis " << j << ": tabular " << le.tabular << " factors " << le.factors << " curves " << le.curves);
        // The curves are fitted to the samples: no worse than the table in between.
        CHECK(le.curves <= std::max(le.tabular, 0.01));
        // Against the true material (scaled as the match found it), at the SVBRDF's pairs.
        std::unique_ptr<Brdf> truth = make_brdf(c.truth.specs[size_t(m.truth_of_term[size_t(j)])], &err);
        REQUIRE(truth);
        const double s = m.scale[size_t(j)];
        const double rel = relative_rms(
            c.svbrdf.pairs, [&](const glm::dvec3& wi, const glm::dvec3& wo) { return s * t.eval_basis(j, wi, wo); },
            [&](const glm::dvec3& wi, const glm::dvec3& wo) { return truth->eval(wi, wo); });
        MESSAGE("  relative RMS against " << c.truth.names[size_t(m.truth_of_term[size_t(j)])] << ": " << rel);
        CHECK(rel < 0.3);
        // Textures rasterized from the curves hold the curves' product at each texel centre.
        const Factored f = t.textures(j);
        CHECK(f.non_negative());
        for (size_t k = 0; k < f.terms.size(); ++k)
            for (int q = 0; q < 4; ++q) {
                const int i = 3 + 3 * q, jj = 2 + 3 * q;
                glm::dvec3 h;
                REQUIRE(map_inverse(t.map, glm::dvec2((i + 0.5) / t.res, (jj + 0.5) / t.res), &h));
                const double th = std::acos(h.z), ph = std::atan2(h.y, h.x) < 0 ? std::atan2(h.y, h.x) + 2 * M_PI : std::atan2(h.y, h.x);
                const TreeTerm& tt = t.bases[size_t(j)].terms[k];
                CHECK(f.terms[k].g.at(i, jj, 1) == doctest::Approx((tt.g_theta.at(th) * tt.g_phi.at(ph)).y).epsilon(1e-5));
                CHECK(f.terms[k].h.at(i, jj, 1) == doctest::Approx((tt.h_theta.at(th) * tt.h_phi.at(ph)).y).epsilon(1e-5));
            }
    }
}

TEST_CASE("ist tree: the folder round trip is exact to the printed digits, and curve files are checked") {
    const ShadeTree& t = sepal_test::ist_case_tree();
    const std::string dir = sepal_test::temp_dir() + "/card.tree";
    std::string err;
    REQUIRE_MESSAGE(write_tree(dir, t, &err), err);
    ShadeTree r;
    REQUIRE_MESSAGE(read_tree(dir, &r, &err), err);
    REQUIRE(r.basis_count() == t.basis_count());
    CHECK(r.param == t.param);
    CHECK(r.res == t.res);
    CHECK(r.blend.w == t.blend.w);
    SplitMix64 rng(9);
    for (int i = 0; i < 200; ++i) {
        const double z1 = 0.05 + 0.9 * rng.uniform(), z2 = 0.05 + 0.9 * rng.uniform();
        const double p1 = 6.283 * rng.uniform(), p2 = 6.283 * rng.uniform();
        const glm::dvec3 wi(std::sqrt(1 - z1 * z1) * std::cos(p1), std::sqrt(1 - z1 * z1) * std::sin(p1), z1);
        const glm::dvec3 wo(std::sqrt(1 - z2 * z2) * std::cos(p2), std::sqrt(1 - z2 * z2) * std::sin(p2), z2);
        for (int j = 0; j < t.basis_count(); ++j) {
            const glm::dvec3 a = t.eval_basis(j, wi, wo), b = r.eval_basis(j, wi, wo);
            CHECK(b.y == doctest::Approx(a.y).epsilon(1e-7));
        }
    }
    // Curve files: unsorted, out of range, negative, too short.
    Curve cv;
    auto refused = [&](const std::string& text, bool periodic) {
        const std::string path = sepal_test::temp_dir() + "/c.csv";
        REQUIRE(write_file_atomic(path, text.data(), text.size(), &err));
        CHECK_FALSE(read_curve_csv(path, periodic, &cv, &err));
        CHECK(err.find("c.csv") != std::string::npos);
    };
    refused("0,1,1,1\n10,1,1,1\n5,1,1,1\n", false);
    refused("0,1,1,1\n95,1,1,1\n", false);
    refused("0,1,1,1\n360,1,1,1\n", true);
    refused("0,1,1,1\n10,1,-1,1\n", false);
    refused("0,1,1,1\n", false);
    refused("0,1,1\n10,1,1,1\n", false);
    // A broken tree.json is refused with the file named.
    const std::string json = "{\"format\":\"sepal-ist-tree\",\"version\":1,\"param\":\"bogus\"}";
    REQUIRE(write_file_atomic(dir + "/tree.json", json.data(), json.size(), &err));
    CHECK_FALSE(read_tree(dir, &r, &err));
    CHECK(err.find("tree.json") != std::string::npos);
}

TEST_CASE("ist tree: edits change what renders, and only there") {
    ShadeTree t = sepal_test::ist_case_tree();
    std::string err;
    const glm::dvec3 wi = glm::normalize(glm::dvec3(0.3, 0.1, 0.9)), wo = glm::normalize(glm::dvec3(-0.2, 0.2, 0.9));
    // A curve: double term 0's H theta curve of basis 1 (curve 1.2): that basis's term 0
    // doubles, the others stay.
    Curve c = t.bases[1].terms[0].h_theta;
    const glm::dvec3 before = t.eval_basis(1, wi, wo), other = t.eval_basis(2, wi, wo);
    for (glm::dvec3& v : c.y) v *= 2.0;
    REQUIRE_MESSAGE(t.set_curve(1, 2, c, &err), err);
    const glm::dvec3 after = t.eval_basis(1, wi, wo);
    CHECK(after.y > before.y);
    CHECK(t.eval_basis(2, wi, wo).y == other.y);
    Curve bad = c;
    bad.periodic = true;  // a theta curve must not wrap
    CHECK_FALSE(t.set_curve(1, 2, bad, &err));
    CHECK_FALSE(t.set_curve(7, 0, c, &err));
    // A swap: basis 0 becomes a Lambertian; its evaluation follows the new BRDF.
    TreeOptions o;
    o.res = 16;
    REQUIRE_MESSAGE(t.swap_basis(0, "lambert:rho=0.3/0.6/0.2", o, &err), err);
    CHECK(t.bases[0].source.find("lambert") == 0);
    const glm::dvec3 lam = t.eval_basis(0, wi, wo);
    CHECK(lam.x == doctest::Approx(0.3 / M_PI).epsilon(0.05));
    CHECK(lam.y == doctest::Approx(0.6 / M_PI).epsilon(0.05));
    CHECK_FALSE(t.swap_basis(0, "no-such-model", o, &err));
    // A blend map: all of basis 3 everywhere, resampled from a 4x4 image.
    Image full(4, 4, 1);
    for (float& v : full.data) v = 1.0f;
    REQUIRE(t.set_blend(3, full, &err));
    for (int i = 0; i < t.blend.width * t.blend.height; ++i) CHECK(t.blend.at(i, 3) == 1.0f);
    Image neg(4, 4, 1);
    neg.data[5] = -1;
    CHECK_FALSE(t.set_blend(3, neg, &err));
    // The exact spatial evaluation is blend-weighted bases.
    const TreeSvbrdf ts(t);
    const glm::dvec2 uv(0.3, 0.6);
    glm::dvec3 sum(0);
    for (int j = 0; j < t.basis_count(); ++j) sum += t.blend.sample(j, uv.x, uv.y) * t.eval_basis(j, wi, wo);
    CHECK(ts.eval(uv, wi, wo).y == doctest::Approx(sum.y));
}

TEST_CASE("ist scattered: refitting factors to samples lowers their error, keeps them non-negative and the held factor") {
    std::string err;
    std::unique_ptr<Brdf> b = make_brdf("cook-torrance:d=0.2,m=0.2", &err);
    REQUIRE(b);
    FactorOptions fo;
    fo.res = 16;
    fo.terms = 2;
    fo.method = Method::ACLS;
    fo.acls_constant = true;
    // A poor start: the factors of a different material.
    std::unique_ptr<Brdf> other = make_brdf("cook-torrance:d=0.6,m=0.35", &err);
    FactorResult r;
    REQUIRE(factor_brdf(*other, fo, &r, &err));
    Factored f = r.factored;
    const std::vector<float> held = f.terms[0].g.data;
    std::vector<ScatteredSample> s;
    for (const DirPair& p : gantry_pairs(6, 30, 12))
        s.push_back(ScatteredSample{p.wi, p.wo, b->eval(p.wi, p.wo), p.wi.z * p.wi.z});
    ScatteredOptions so;
    so.constant_side = 0;
    ScatteredResult sr;
    REQUIRE_MESSAGE(refine_scattered(s, so, &f, &sr, &err), err);
    MESSAGE("weighted RMS " << sr.rms_before << " -> " << sr.rms_after);
    CHECK(sr.rms_after < 0.5 * sr.rms_before);
    CHECK(f.non_negative());
    CHECK(f.terms[0].g.data == held);
    std::vector<ScatteredSample> none;
    CHECK_FALSE(refine_scattered(none, so, &f, &sr, &err));
}

TEST_CASE("scattered: a half-angle factor finer than the other (res_h) is refitted at its own size") {
    // The bake's ladder gives G and H different sides (vh 16/64): the refit once indexed both
    // at G's side and wrote past H's texels (heap corruption, found refitting bake candidates).
    std::string err;
    std::unique_ptr<Brdf> b = make_brdf("cook-torrance:d=0.2,m=0.2", &err);
    REQUIRE(b);
    FactorOptions fo;
    fo.param = Param::ViewHalf;
    fo.res = 8;
    fo.res_h = 32;
    fo.terms = 2;
    fo.method = Method::ACLS;
    std::unique_ptr<Brdf> other = make_brdf("cook-torrance:d=0.6,m=0.35", &err);
    FactorResult r;
    REQUIRE_MESSAGE(factor_brdf(*other, fo, &r, &err), err);
    Factored f = r.factored;
    REQUIRE(f.terms[0].g.n != f.terms[0].h.n);
    const int gn = f.terms[0].g.n, hn = f.terms[0].h.n;
    std::vector<ScatteredSample> s;
    for (const DirPair& p : gantry_pairs(6, 30, 12))
        s.push_back(ScatteredSample{p.wi, p.wo, b->eval(p.wi, p.wo), p.wi.z * p.wi.z});
    ScatteredResult sr;
    REQUIRE_MESSAGE(refine_scattered(s, ScatteredOptions{}, &f, &sr, &err), err);
    CHECK(sr.rms_after < 0.5 * sr.rms_before);
    CHECK(f.terms[0].g.n == gn);
    CHECK(f.terms[0].h.n == hn);
    CHECK(f.terms[1].h.data.size() == size_t(hn) * hn * 3);
    CHECK(f.non_negative());
    // Terms of different sizes: refused, not guessed.
    f.terms[1].h = FactorTexture(hn / 2, 3);
    CHECK_FALSE(refine_scattered(s, ScatteredOptions{}, &f, &sr, &err));
    CHECK(err.find("one size") != std::string::npos);
}
