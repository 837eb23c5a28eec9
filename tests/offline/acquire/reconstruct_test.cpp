// Reconstruction: clusters and their Lafortune fits recover the basis materials of a known
// SVBRDF, and the per-texel weights reproduce it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "acquire/planner.h"
#include "acquire/reconstruct.h"
#include "util/image.h"

namespace {

struct Setup {
    sepal::AcqObject obj;
    sepal::BlendSvbrdf truth;
    std::vector<sepal::Capture> caps;
};

// Two Lafortune materials in crisp regions on a sphere, seen from 40 random views.
Setup setup(double noise, double softness = 0.002, int views = 40) {
    Setup s;
    std::string err;
    REQUIRE(sepal::make_object("sphere", 32, &s.obj, &err));
    sepal::SvbrdfGenOptions g;
    g.materials = {"lafortune:rho_d=0.5/0.1/0.05,lobe=-0.95/-0.95/1.02/12",
                   "lafortune:rho_d=0.1/0.2/0.5,lobe=-1/-1/0.99/40"};
    g.softness = softness;
    REQUIRE(sepal::make_svbrdf(32, g, &s.truth, &err));
    sepal::RigOptions rig;
    rig.noise_read *= noise;
    rig.noise_shot *= noise;
    for (int k = 0; k < views; ++k) {
        sepal::Capture c;
        sepal::capture_atlas(s.obj, s.truth, sepal::random_view(rig, 5, k), rig, uint64_t(k), &c);
        s.caps.push_back(std::move(c));
    }
    return s;
}

}  // namespace

TEST_CASE("reconstruct: two Lafortune materials come back as the basis, and the texels' weights pick them") {
    const Setup s = setup(1.0);
    sepal::ReconstructOptions o;
    o.clusters = 2;
    sepal::Reconstruction r;
    std::string err;
    REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r, &err), err);
    REQUIRE(r.basis.size() == 2);
    // Match each truth material to the basis with the closer diffuse colour.
    const double want_rho[2] = {0.5, 0.1}, want_n[2] = {12, 40};
    for (int m = 0; m < 2; ++m) {
        int best = 0;
        for (int k = 1; k < 2; ++k)
            if (std::fabs(r.basis[size_t(k)].model.rho_d.x - want_rho[m]) <
                std::fabs(r.basis[size_t(best)].model.rho_d.x - want_rho[m]))
                best = k;
        const sepal::LafortuneFit& f = r.basis[size_t(best)];
        INFO("material " << m << ": " << f.model.spec());
        CHECK(f.model.rho_d.x == doctest::Approx(want_rho[m]).epsilon(0.05));
        CHECK(f.model.lobes[0].n == doctest::Approx(want_n[m]).epsilon(0.1));
        CHECK(f.rank == 6);
    }
    // The reconstructed SVBRDF against the truth over every sample's directions.
    double num = 0, den = 0;
    for (const sepal::Capture& c : s.caps)
        for (size_t i = 0; i < c.size(); ++i) {
            const glm::dvec3 a = r.svbrdf.eval(c.texel[i], glm::dvec3(c.wi[i]), glm::dvec3(c.wo[i]));
            const glm::dvec3 b = s.truth.eval(c.texel[i], glm::dvec3(c.wi[i]), glm::dvec3(c.wo[i]));
            num += glm::dot(a - b, a - b);
            den += glm::dot(b, b);
        }
    CHECK(std::sqrt(num / den) < 0.03);
    // Every valid texel has weights, measured or filled from a neighbour.
    for (int t : s.obj.atlas.texels) {
        float sum = 0;
        for (int k = 0; k < 2; ++k) sum += r.svbrdf.maps.texel(t)[k];
        CHECK(sum > 0.5f);
        CHECK(r.cluster[size_t(t)] >= 0);
    }
    // Per-texel fits where a texel has enough samples: their intervals are finite.
    const std::vector<sepal::TexelFit> tf = sepal::fit_texels(s.obj, s.caps, r, 5, 0);
    int fitted = 0, finite = 0;
    for (int t : s.obj.atlas.texels) {
        fitted += tf[size_t(t)].fitted;
        finite += tf[size_t(t)].fitted && std::isfinite(tf[size_t(t)].ci95[0]);
    }
    CHECK(fitted > 100);
    CHECK(finite == fitted);
}

TEST_CASE("reconstruct: refuses captures without samples and bad options") {
    Setup s = setup(1.0);
    sepal::Reconstruction r;
    std::string err;
    sepal::ReconstructOptions o;
    o.clusters = 0;
    CHECK_FALSE(sepal::reconstruct(s.obj, s.caps, o, &r, &err));
    CHECK_FALSE(sepal::reconstruct(s.obj, {}, sepal::ReconstructOptions(), &r, &err));
    CHECK(err.find("no texel") != std::string::npos);
}

// The default SVBRDF (two MERL materials among four) on a small sphere from 12 random views.
struct DefaultScene {
    sepal::AcqObject obj;
    sepal::BlendSvbrdf truth;
    std::vector<sepal::Capture> caps;
    sepal::RigOptions rig;
};

void default_scene(uint64_t seed, DefaultScene* s) {
    std::string err;
    REQUIRE(sepal::make_object("sphere", 32, &s->obj, &err));
    REQUIRE_MESSAGE(sepal::make_svbrdf(32, sepal::SvbrdfGenOptions(), &s->truth, &err), err);
    for (int k = 0; k < 12; ++k) {
        sepal::Capture c;
        sepal::capture_atlas(s->obj, s->truth, sepal::random_view(s->rig, seed, k), s->rig, uint64_t(k), &c);
        s->caps.push_back(std::move(c));
    }
}

// Mean PSNR of the reconstruction against the truth, rendered exactly (64 x 64, clipped to
// 0..1) from seven views unlike the captures.
double held_out_psnr(const DefaultScene& s, const sepal::Reconstruction& r) {
    const sepal::ViewPair views[] = {
        sepal::view_from_angles(35, 30, 75, 50),   sepal::view_from_angles(155, -35, 120, -10),
        sepal::view_from_angles(275, 10, 305, 35), sepal::view_from_angles(95, 65, 40, 40),
        sepal::view_from_angles(215, 25, 180, 50), sepal::view_from_angles(330, -60, 10, -30),
        sepal::view_from_angles(200, -20, 240, 10)};
    auto clip = [](sepal::Image* img) {
        for (float& v : img->data) v = std::min(1.0f, std::max(0.0f, v));
    };
    double psnr = 0;
    std::string err;
    for (const sepal::ViewPair& v : views) {
        const sepal_scene scene = sepal::scene_for_view(s.obj, v, s.rig);
        sepal::Image want, got;
        REQUIRE(sepal::render_svbrdf(s.obj, s.truth, scene, 64, 64, sepal::RenderSvbrdfOptions(), &want, &err));
        REQUIRE(sepal::render_svbrdf(s.obj, r.svbrdf, scene, 64, 64, sepal::RenderSvbrdfOptions(), &got, &err));
        clip(&want);
        clip(&got);
        psnr += sepal::diff_images(want, got, 0).psnr / 7;
    }
    return psnr;
}

// The scene's captures reconstructed with a default option off ([0]) and on ([1]) into r;
// their held_out_psnr into psnr.
void psnr_off_on(const DefaultScene& s, bool sepal::ReconstructOptions::*option, sepal::Reconstruction r[2],
                 double psnr[2]) {
    for (int on = 0; on < 2; ++on) {
        sepal::ReconstructOptions o;
        o.*option = on == 1;
        std::string err;
        REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r[on], &err), err);
        psnr[on] = held_out_psnr(s, r[on]);
    }
}

TEST_CASE("reconstruct: chosen fits are plausible where the iterated ones create energy; the renders gain") {
    // Seed 10: the iterated fits of two of the six clusters put lobes where no sample was;
    // choose_fit replaces them, and the held-out views render 4 dB closer. Not every capture
    // set has something to replace; where nothing is, the choice moves the renders little.
    DefaultScene s;
    default_scene(10, &s);
    double psnr[2] = {0, 0};
    int implausible[2] = {0, 0};
    sepal::Reconstruction r[2];
    psnr_off_on(s, &sepal::ReconstructOptions::choose_fit, r, psnr);
    for (int choose = 0; choose < 2; ++choose)
        for (const sepal::LafortuneFit& f : r[choose].basis) implausible[choose] += !sepal::lafortune_plausible(f.model);
    MESSAGE("iterated fits: " << implausible[0] << " implausible, " << psnr[0] << " dB; chosen: " << implausible[1]
                              << ", " << psnr[1] << " dB");
    CHECK(implausible[0] > 0);  // the case this test is for
    CHECK(implausible[1] == 0);
    CHECK(psnr[1] > psnr[0] + 2);
}

TEST_CASE("reconstruct: the weights' ridge is chosen by held-out views: little where texels blend and samples are clean") {
    // Soft regions: most texels blend the two materials, so the pull towards one cluster is
    // wrong wherever the samples can say so; with 100 times the noise they cannot.
    double chosen[2] = {0, 0};
    const double noise[2] = {0.2, 20.0};
    for (int i = 0; i < 2; ++i) {
        const Setup s = setup(noise[i], 0.1);
        sepal::ReconstructOptions o;
        o.clusters = 2;
        sepal::Reconstruction r;
        std::string err;
        REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r, &err), err);
        chosen[i] = r.ridge_share;
        o.choose_ridge = false;
        o.ridge_share = 0.05;
        REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r, &err), err);
        CHECK(r.ridge_share == 0.05);  // as given when not chosen
    }
    MESSAGE("chosen ridge share: noise x0.2 " << chosen[0] << ", x20 " << chosen[1]);
    CHECK(chosen[1] > chosen[0]);
}

TEST_CASE("reconstruct: the same captures give the same reconstruction with 1 and 2 threads") {
    const Setup s = setup(1.0, 0.1);
    sepal::Reconstruction r[2];
    std::string err;
    for (int i = 0; i < 2; ++i) {
        sepal::ReconstructOptions o;
        o.clusters = 3;
        o.threads = i + 1;
        REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r[i], &err), err);
    }
    CHECK(r[0].cluster == r[1].cluster);
    CHECK(r[0].svbrdf.maps.w == r[1].svbrdf.maps.w);
    CHECK(r[0].svbrdf.specs == r[1].svbrdf.specs);
    CHECK(r[0].ridge_share == r[1].ridge_share);
    CHECK(r[0].spatial_share == r[1].spatial_share);
    CHECK(r[0].lobes_dropped == r[1].lobes_dropped);
}


TEST_CASE("reconstruct: weights pulled towards their neighbours are closer to the truth's where samples are few or noisy") {
    // Two materials blending over soft regions; the reconstruction's two basis materials stand
    // for them, so its weights can be compared with the truth's texel by texel.
    struct Case {
        double noise;
        int views;
    };
    const Case cases[] = {{5.0, 20}, {1.0, 40}};
    for (const Case& c : cases) {
        const Setup s = setup(c.noise, 0.1, c.views);
        double error[2] = {0, 0}, share = 0;
        for (int spatial = 0; spatial < 2; ++spatial) {
            sepal::ReconstructOptions o;
            o.clusters = 2;
            o.spatial = spatial == 1;
            sepal::Reconstruction r;
            std::string err;
            REQUIRE_MESSAGE(sepal::reconstruct(s.obj, s.caps, o, &r, &err), err);
            REQUIRE(r.basis.size() == 2);
            if (spatial) share = r.spatial_share;
            CHECK((spatial ? r.spatial_share > 0 : r.spatial_share == 0));
            const int red = r.basis[0].model.rho_d.x > r.basis[1].model.rho_d.x ? 0 : 1;
            double sum = 0;
            int n = 0;
            for (int t : s.obj.atlas.texels) {
                if (r.samples[size_t(t)] == 0) continue;
                const double d0 = double(r.svbrdf.maps.texel(t)[red]) - double(s.truth.maps.texel(t)[0]);
                const double d1 = double(r.svbrdf.maps.texel(t)[1 - red]) - double(s.truth.maps.texel(t)[1]);
                sum += d0 * d0 + d1 * d1;
                ++n;
            }
            error[spatial] = std::sqrt(sum / (2.0 * n));
        }
        MESSAGE("noise x" << c.noise << ", " << c.views << " views: weights' RMS error " << error[0]
                          << " pulled to the cluster, " << error[1] << " to the neighbours (share " << share << ")");
        if (c.noise > 1) {
            CHECK(error[1] < 0.8 * error[0]);  // 0.105 -> 0.071
        } else {
            // Clean and dense: the held-out folds choose a light pull, and it costs nothing.
            CHECK(share <= 0.01);
            CHECK(error[1] <= 1.01 * error[0]);
        }
    }
    // Its cost where material boundaries are a texel or two wide (the default SVBRDF on a
    // 32x32 atlas): the pull blurs them. docs/acquisition.md quotes this case; the bound keeps
    // the loss from growing unnoticed.
    DefaultScene d;
    default_scene(4, &d);
    double psnr[2] = {0, 0};
    sepal::Reconstruction r[2];
    psnr_off_on(d, &sepal::ReconstructOptions::spatial, r, psnr);
    MESSAGE("32x32 atlas, 12 random views: " << psnr[0] << " dB pulled to the cluster, " << psnr[1]
                                             << " dB to the neighbours");
    CHECK(psnr[1] > psnr[0] - 1.0);
}
