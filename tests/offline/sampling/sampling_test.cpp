// The sampling subsystem's building blocks: KL-NMF, the factored fit's report and bounds,
// sample sequences, environments (constant, sky, .hdr), the Monte Carlo renderer's
// determinism and the variance reduction it exists to show.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <glm/geometric.hpp>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_util.h"
#include "sampling/alternatives.h"
#include "sampling/environment.h"
#include "sampling/factored_fit.h"
#include "sampling/mc_render.h"
#include "sampling/metrics.h"
#include "offline/sampling/sphere_scene.h"
#include "sampling/nmf_kl.h"
#include "sampling/sequence.h"
#include "test_util.h"
#include "util/parallel.h"

using namespace sepal;

namespace {

using sepal_test::SphereScene;

Sampler build(const SamplerData& d) {
    Sampler s;
    std::string err;
    REQUIRE_MESSAGE(s.build(d, &err), err);
    return s;
}

double trial_variance(const Brdf& f, const Sampler& s, const Environment& env, int spp, int trials) {
    static SphereScene sc;
    std::vector<Image> images;
    std::vector<uint8_t> mask;
    for (int t = 0; t < trials; ++t) {
        McOptions o;
        o.spp = spp;
        o.seed = 100 + uint64_t(t);
        McResult r;
        std::string err;
        REQUIRE_MESSAGE(render_mc(f, s.get(), env, sc.scene, sc.mesh, 32, 32, o, &r, &err), err);
        images.push_back(r.image);
        mask = r.shaded;
    }
    return image_variance(images, mask);
}

}  // namespace

TEST_CASE("nmf_kl: recovers an exact non-negative rank-2 matrix; the KL divergence falls to ~0") {
    Eigen::MatrixXd W(30, 2), H(2, 20);
    SplitMix64 r(3);
    for (int i = 0; i < W.size(); ++i) W.data()[i] = r.uniform();
    for (int i = 0; i < H.size(); ++i) H.data()[i] = r.uniform() * 5;
    const Eigen::MatrixXd Y = W * H;
    NmfKl out;
    NmfKlOptions o;
    o.max_iterations = 5000;
    o.tolerance = 1e-12;
    nmf_kl(Y, 2, o, &out);
    CHECK(out.relative < 1e-5);
    CHECK((out.W * out.H - Y).cwiseAbs().maxCoeff() < 1e-2 * Y.maxCoeff());
    CHECK(out.W.minCoeff() >= 0);
    CHECK(out.H.minCoeff() >= 0);
    for (int a = 0; a < 2; ++a) CHECK(out.W.col(a).sum() == doctest::Approx(1.0));
    NmfKl again;
    nmf_kl(Y, 2, o, &again);
    CHECK(again.W == out.W);  // deterministic
    CHECK(kl_divergence(Y, Y) == doctest::Approx(0.0));
}

TEST_CASE("nmf_kl: the threaded fused updates give the one-thread factors and the divergence's value") {
    // 403 x 301 (past the one-thread size, partial chunks on both sides), sparse noise.
    Eigen::MatrixXd Y(403, 301);
    SplitMix64 r(11);
    for (int i = 0; i < Y.size(); ++i) Y.data()[i] = r.uniform() < 0.1 ? 0.0 : r.uniform();
    NmfKlOptions o;
    o.max_iterations = 40;
    o.threads = 1;
    NmfKl one, two;
    nmf_kl(Y, 3, o, &one);
    o.threads = 2;
    nmf_kl(Y, 3, o, &two);
    CHECK(one.W == two.W);
    CHECK(one.H == two.H);
    CHECK(one.divergence == two.divergence);
    // The fused divergence is the reference formula's, to summation order.
    CHECK(one.divergence == doctest::Approx(kl_divergence(Y, one.W * one.H)).epsilon(1e-10));
    CHECK(one.iterations == 40);
    // An iteration is a function of (W, H) alone: the 41st from the 40th's factors, by the
    // paper's equations 14-16 as Eigen products, is the fused code's 41st.
    o.max_iterations = 41;
    NmfKl next;
    nmf_kl(Y, 3, o, &next);
    Eigen::MatrixXd W = one.W, H = one.H;
    const double floor = 1e-14 * Y.sum() / double(Y.size());
    const Eigen::VectorXd wsum = W.colwise().sum().transpose();
    Eigen::MatrixXd R = Y.array() / (W * H).array().max(floor);
    const Eigen::MatrixXd num = W.transpose() * R;
    for (int a = 0; a < 3; ++a) H.row(a) = H.row(a).array() * num.row(a).array() / wsum(a);
    const Eigen::VectorXd hsum = H.rowwise().sum();
    R = Y.array() / (W * H).array().max(floor);
    const Eigen::MatrixXd numw = R * H.transpose();
    for (int a = 0; a < 3; ++a) W.col(a) = W.col(a).array() * numw.col(a).array() / hsum(a);
    for (int a = 0; a < 3; ++a) {
        const double sum = W.col(a).sum();
        W.col(a) /= sum;
        H.row(a) *= sum;
    }
    CHECK((W - next.W).cwiseAbs().maxCoeff() <= 1e-12 * W.cwiseAbs().maxCoeff());
    CHECK((H - next.H).cwiseAbs().maxCoeff() <= 1e-12 * H.cwiseAbs().maxCoeff());
    // An empty matrix: no factors to fit, no crash.
    NmfKl empty;
    nmf_kl(Eigen::MatrixXd(0, 5), 2, o, &empty);
    CHECK(empty.iterations == 0);
}

TEST_CASE("factored fit: a Blinn lobe is exactly separable; bytes, bounds, options and the Table 1 MAE") {
    std::string err;
    auto blinn = make_brdf("blinn:rho_d=0,rho_s=1,n=50", &err);
    FactoredOptions o;
    o.J = 1, o.K = 1, o.param = SampleParam::Half;
    SamplerData d;
    FactoredReport rep;
    REQUIRE_MESSAGE(fit_factored(*blinn, o, &d, &rep, &err), err);
    CHECK(rep.phi_frame == "view");  // isotropic: phi measured from phi_o
    CHECK(rep.n_phi_o == 1);
    // One term: only the horizon cut (wi below the horizon) is not separable.
    CHECK(rep.kl_total < 0.05);
    CHECK(rep.sampler_bytes < 64 * 1024);
    // Anisotropic: the paper's absolute phi.
    auto ward = make_brdf("ward:rho_d=0.1,rho_s=1.2,ax=0.2,ay=0.02", &err);
    o.J = 2, o.K = 4, o.n_theta_p = 100, o.n_phi_p = 100;  // the paper's Table 1 row
    o.axis = SampleAxis::Normal;
    o.supersample = 1, o.iterations = 50, o.colour = true;
    REQUIRE_MESSAGE(fit_factored(*ward, o, &d, &rep, &err), err);
    CHECK(rep.phi_frame == "absolute");
    CHECK(rep.sampler_bytes < 64 * 1024);
    // Bad options are refused with the option named.
    o.J = 0;
    CHECK_FALSE(fit_factored(*ward, o, &d, &rep, &err));
    CHECK(err.find("terms") != std::string::npos);
    o.J = 2, o.n_theta_p = 5000;
    CHECK_FALSE(fit_factored(*ward, o, &d, &rep, &err));
    CHECK(err.find("bins") != std::string::npos);
    // The Table 1 measure on Cook-Torrance at the paper's resolution, 4 x 1 terms: the
    // paper's 0.192; ours (half angle, view frame, Jacobian) measured 0.22 (the MAE of a
    // piecewise-constant fit is bounded by its 32 theta bins).
    auto ct = make_brdf("cook-torrance", &err);
    FactoredOptions p;
    p.J = 4, p.K = 1, p.param = SampleParam::Half;
    REQUIRE(fit_factored(*ct, p, &d, &rep, &err));
    const Sampler s = build(d);
    const double mae = normalized_mae(*ct, [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
        sepal_sampler_view v;
        sepal_sampler_set_view(&s.get(), w, &v);
        return factored_lum(v, wi);
    }, 1 << 15, 7);
    CHECK(mae > 0.1);
    CHECK(mae < 0.3);
}

TEST_CASE("factored fit: param auto picks half for glossy and incident for diffuse-like BRDFs") {
    std::string err;
    FactoredOptions o;
    o.J = 2, o.K = 1, o.n_theta_o = 8, o.n_theta_p = 16, o.n_phi_p = 8;
    SamplerData d;
    FactoredReport rep;
    REQUIRE(fit_factored(*make_brdf("cook-torrance", &err), o, &d, &rep, &err));
    CHECK(rep.param == "half");
    REQUIRE(fit_factored(*make_brdf("hapke-lommel", &err), o, &d, &rep, &err));
    CHECK(rep.param == "incident");
    // A Lambert BRDF is all Lambert part: no term left, cosine sampling (exact for it).
    REQUIRE(fit_factored(*make_brdf("lambert", &err), o, &d, &rep, &err));
    CHECK(d.desc.diffuse[1] == doctest::Approx(0.5 / kPi).epsilon(1e-3));
    bool noted = false;
    for (const std::string& n : rep.notes) noted = noted || n.find("Lambert part") != std::string::npos;
    CHECK(noted);
}

TEST_CASE("sequences: stratified points fill every stratum; all points lie in [0,1); deterministic") {
    std::vector<float> u, again;
    for (SampleSequence s : {SampleSequence::Random, SampleSequence::Stratified, SampleSequence::Sobol})
        for (int spp : {1, 7, 16, 100}) {
            pixel_points(s, spp, 9, 1234, &u);
            pixel_points(s, spp, 9, 1234, &again);
            CHECK(u == again);
            REQUIRE(u.size() == size_t(spp) * 2);
            for (float x : u) CHECK((x >= 0.0f && x < 1.0f));
            if (s == SampleSequence::Random) continue;
            // Stratified (k x k or N-rooks) and (0,2)-nets for powers of 2: one point per
            // 1/spp stratum of each axis.
            if (s == SampleSequence::Sobol && (spp & (spp - 1))) continue;
            for (int axis = 0; axis < 2; ++axis) {
                const int k = s == SampleSequence::Stratified && spp == 100 ? 10 : (spp == 16 && s == SampleSequence::Stratified ? 4 : spp);
                std::vector<int> count(static_cast<size_t>(k), 0);
                for (int i = 0; i < spp; ++i) ++count[size_t(u[2 * size_t(i) + size_t(axis)] * k)];
                for (int c : count) CHECK(c == spp / k);
            }
        }
    pixel_points(SampleSequence::Sobol, 16, 9, 1235, &again);
    pixel_points(SampleSequence::Sobol, 16, 9, 1234, &u);
    CHECK(u != again);  // a different shift per pixel
}

TEST_CASE("environments: constant, sky, a Radiance .hdr file; bad specs and files refused") {
    std::string err;
    auto c = make_environment("constant:0.5,1,2", &err);
    REQUIRE(c);
    glm::dvec3 v;
    CHECK(c->constant(&v));
    CHECK(v == glm::dvec3(0.5, 1, 2));
    auto sky = make_environment("sky:elevation=90,radius=5,sun=100", &err);
    REQUIRE_MESSAGE(sky, err);
    CHECK(sky->radiance(glm::dvec3(0, 0, 1)).x == doctest::Approx(100));  // the sun at the zenith
    CHECK(sky->radiance(glm::dvec3(1, 0, 0)).x < 2);
    CHECK(sky->radiance(glm::dvec3(0, 0, -1)).x < 0.5);  // ground
    CHECK_FALSE(make_environment("sky:sun=-1", &err));
    CHECK_FALSE(make_environment("constant:nan", &err));
    CHECK_FALSE(make_environment("teapot", &err));
    // A 4 x 2 flat RGBE file: the top row is the zenith, u = 0.5 + atan2(y, x) / (2 pi).
    const std::string dir = sepal_test::temp_dir();
    {
        std::ofstream f(dir + "/env.hdr", std::ios::binary);
        f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 4; ++x) {
                const unsigned char px[4] = {(unsigned char)(64 + 32 * x), (unsigned char)(128 * y), 0, 129};  // 2^(129-136)*...
                f.write(reinterpret_cast<const char*>(px), 4);
            }
    }
    auto hdr = make_environment(dir + "/env.hdr", &err);
    REQUIRE_MESSAGE(hdr, err);
    const glm::dvec3 up = hdr->radiance(glm::normalize(glm::dvec3(-1, -0.01, 0.2)));  // column 0, top row
    const glm::dvec3 down = hdr->radiance(glm::normalize(glm::dvec3(1, 0.01, -0.5)));  // column 2, bottom row
    CHECK(up.x > 0);
    CHECK(up.y == 0);
    CHECK(down.y > 0);
    CHECK(down.x > up.x);
    {
        std::ofstream f(dir + "/bad.hdr", std::ios::binary);
        f << "not an hdr";
    }
    CHECK_FALSE(make_environment(dir + "/bad.hdr", &err));
    CHECK(err.find("bad.hdr") != std::string::npos);
}

TEST_CASE("MC renderer: deterministic for a seed whatever the thread count; the estimator is normalized") {
    std::string err;
    auto ct = make_brdf("cook-torrance", &err);
    FactoredOptions fo;
    fo.J = 2, fo.K = 2, fo.param = SampleParam::Half;
    SamplerData d;
    REQUIRE(fit_factored(*ct, fo, &d, nullptr, &err));
    const Sampler s = build(d);
    auto env = make_environment("sky", &err);
    SphereScene sc;
    McOptions o;
    o.spp = 9;
    o.seed = 5;
    o.threads = 1;
    McResult a, b, c;
    REQUIRE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &a, &err));
    o.threads = 2;
    REQUIRE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &b, &err));
    CHECK(a.image.data == b.image.data);
    // A light sampler built by the caller (McOptions::light) renders the same image; one of
    // another environment does not (so the option is really used).
    EnvironmentSampler own, other;
    REQUIRE(own.build(*env, kMcLightWidth, kMcLightHeight, &err));
    o.light = &own;
    REQUIRE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &b, &err));
    CHECK(a.image.data == b.image.data);
    auto sun = make_environment("sky:elevation=80,azimuth=90", &err);
    REQUIRE_MESSAGE(sun, err);
    REQUIRE(other.build(*sun, kMcLightWidth, kMcLightHeight, &err));
    o.light = &other;
    REQUIRE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &b, &err));
    CHECK(a.image.data != b.image.data);
    o.light = nullptr;
    o.seed = 6;
    REQUIRE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &c, &err));
    CHECK(a.image.data != c.image.data);
    CHECK(a.shaded_pixels > 300);
    CHECK(a.failed == 0);
    o.spp = 0;
    CHECK_FALSE(render_mc(*ct, s.get(), *env, sc.scene, sc.mesh, 40, 30, o, &c, &err));
    // The estimator's normalization: Lambert under a constant environment, cosine sampling,
    // is a zero-variance estimator of rho (L = 1): every shaded pixel is exactly rho.
    auto lambert = make_brdf("lambert:rho=0.25/0.5/0.75", &err);
    auto one = make_environment("constant", &err);
    const Sampler cs = build(make_cosine_sampler());
    o.spp = 3;
    REQUIRE(render_mc(*lambert, cs.get(), *one, sc.scene, sc.mesh, 16, 16, o, &c, &err));
    int checked = 0;
    for (size_t p = 0; p < c.shaded.size(); ++p) {
        if (!c.shaded[p]) continue;
        ++checked;
        for (int ch = 0; ch < 3; ++ch) CHECK(c.image.data[p * 3 + size_t(ch)] == doctest::Approx(0.25 * (ch + 1)).epsilon(1e-5));
    }
    CHECK(checked > 100);
}

TEST_CASE("variance: factored beats cosine sampling by >= 10x on the paper's Cook-Torrance (constant light)") {
    std::string err;
    auto ct = make_brdf("cook-torrance", &err);
    FactoredOptions fo;
    SamplerData d;
    REQUIRE(fit_factored(*ct, fo, &d, nullptr, &err));
    const Sampler fs = build(d), cs = build(make_cosine_sampler());
    auto env = make_environment("constant", &err);
    const double vf = trial_variance(*ct, fs, *env, 16, 3), vc = trial_variance(*ct, cs, *env, 16, 3);
    INFO("variance factored " << vf << ", cosine " << vc);
    CHECK(vc > 10 * vf);
}

TEST_CASE("environment sampler: pdf() is the density sample() draws; the sun gets its share") {
    std::string err;
    auto sky = make_environment("sky", &err);
    REQUIRE(sky);
    EnvironmentSampler es;
    REQUIRE_MESSAGE(es.build(*sky, 512, 256, &err), err);
    // E[g / pdf] = integral of g over the sphere: g = 1 gives 4 pi, g = the luminance the
    // sky's power; each sample's pdf is pdf(dir); the sun's samples match its power share.
    const int n = 200000;
    double inv = 0, sun_hits = 0, power = 0;
    const glm::dvec3 sun = dir_from_degrees(90.0 - 35.0, -60.0);
    const double cos_r = std::cos(deg2rad(4.0));
    for (int i = 0; i < n; ++i) {
        double p = 0;
        const glm::dvec3 d = es.sample(counter_uniform(7, uint64_t(2 * i)), counter_uniform(7, uint64_t(2 * i + 1)), &p);
        REQUIRE(p > 0);
        if (i % 97 == 0) {
            CHECK(std::fabs(glm::length(d) - 1) < 1e-9);
            CHECK(es.pdf(d) == doctest::Approx(p).epsilon(1e-9));
        }
        inv += 1 / p;
        const glm::dvec3 L = sky->radiance(d);
        power += (0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z) / p;
        sun_hits += glm::dot(d, sun) >= cos_r;
    }
    CHECK(inv / n == doctest::Approx(4 * kPi).epsilon(0.01));
    // The sun disk's share of the luminance power (100 x its solid angle against the rest).
    const double sun_power = 100 * (0.2126 + 0.7152 * 0.95 + 0.0722 * 0.85) * 2 * kPi * (1 - cos_r);
    CHECK(sun_hits / n == doctest::Approx(sun_power / (power / n)).epsilon(0.05));
    EnvironmentSampler bad;
    auto black = make_environment("constant:0", &err);
    CHECK_FALSE(bad.build(*black, 64, 32, &err));
    CHECK(err.find("black") != std::string::npos);
    CHECK_FALSE(bad.build(*sky, 2, 1, &err));
}

TEST_CASE("MC renderer: MIS with light samples is unbiased and cuts the variance under the sun") {
    std::string err;
    auto paint = make_brdf("cook-torrance:d=0.7,Rd=0.8/0.15/0.1,s=0.3,F0=0.04,m=0.2", &err);
    REQUIRE_MESSAGE(paint, err);
    SamplerData d;
    REQUIRE(fit_factored(*paint, FactoredOptions(), &d, nullptr, &err));
    const Sampler fs = build(d), cs = build(make_cosine_sampler());
    auto sky = make_environment("sky", &err);
    static SphereScene sc;
    auto render = [&](const Sampler& s, Mis mis, int spp, uint64_t seed) {
        McOptions o;
        o.spp = spp, o.seed = seed, o.mis = mis;
        McResult r;
        REQUIRE_MESSAGE(render_mc(*paint, s.get(), *sky, sc.scene, sc.mesh, 24, 24, o, &r, &err), err);
        CHECK(r.mis == (mis != Mis::Off));
        return r;
    };
    // The sphere's mean radiance: MIS and plain BRDF sampling agree within their noise.
    auto mean = [](const McResult& r) {
        double s = 0;
        int n = 0;
        for (size_t p = 0; p < r.shaded.size(); ++p)
            if (r.shaded[p]) s += r.image.data[p * 3] + r.image.data[p * 3 + 1] + r.image.data[p * 3 + 2], ++n;
        return s / n;
    };
    const McResult on = render(fs, Mis::On, 256, 1), off = render(cs, Mis::Off, 1024, 2);
    CHECK(on.light_samples == on.samples);
    CHECK(mean(on) == doctest::Approx(mean(off)).epsilon(0.02));
    // Auto: on under the sky, off under a constant environment (nothing to follow).
    McOptions o;
    McResult r;
    auto one = make_environment("constant", &err);
    REQUIRE(render_mc(*paint, fs.get(), *one, sc.scene, sc.mesh, 8, 8, o, &r, &err));
    CHECK_FALSE(r.mis);
    // Variance under the sun: with light samples, factored beats cosine (both with MIS) and
    // beats itself without them.
    auto variance = [&](const Sampler& s, Mis mis) {
        std::vector<Image> imgs;
        std::vector<uint8_t> mask;
        for (int t = 0; t < 3; ++t) {
            const McResult x = render(s, mis, 16, 10 + uint64_t(t));
            imgs.push_back(x.image);
            mask = x.shaded;
        }
        return image_variance(imgs, mask);
    };
    const double f_mis = variance(fs, Mis::On), c_mis = variance(cs, Mis::On), f_off = variance(fs, Mis::Off);
    INFO("variance: factored + MIS " << f_mis << ", cosine + MIS " << c_mis << ", factored alone " << f_off);
    CHECK(f_mis < c_mis);
    CHECK(f_mis * 3 < f_off);
}
