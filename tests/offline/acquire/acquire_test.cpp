// The virtual acquisition setup: atlas, visibility and shadowing, capture and its noise
// model, SVBRDF renders against the exact backend.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "acquire/capture.h"
#include "acquire/object.h"
#include "acquire/known.h"
#include "reference/render_exact.h"
#include "spec/spec.h"

namespace {

using glm::dvec3;

sepal::AcqObject object(const std::string& name, int res) {
    sepal::AcqObject o;
    std::string err;
    REQUIRE_MESSAGE(sepal::make_object(name, res, &o, &err), err);
    return o;
}

sepal::BlendSvbrdf single(const std::string& spec, int res) {
    sepal::SvbrdfGenOptions g;
    g.materials = {spec};
    sepal::BlendSvbrdf s;
    std::string err;
    REQUIRE_MESSAGE(sepal::make_svbrdf(res, g, &s, &err), err);
    return s;
}

}  // namespace

TEST_CASE("acquire atlas: sphere texels lie on the sphere with orthonormal frames along the normal") {
    const sepal::AcqObject o = object("sphere", 32);
    const sepal::SurfaceAtlas& a = o.atlas;
    CHECK(a.texels.size() >= 32 * 30);  // all but the degenerate pole rows at most
    for (int t : a.texels) {
        const glm::vec3 p = a.position[size_t(t)], n = a.normal[size_t(t)];
        CHECK(glm::length(p) == doctest::Approx(1.0).epsilon(0.01));
        CHECK(glm::dot(n, glm::normalize(p)) > 0.999f);
        CHECK(std::fabs(glm::dot(n, a.tangent[size_t(t)])) < 1e-5f);
        CHECK(std::fabs(glm::dot(a.bitangent[size_t(t)], a.tangent[size_t(t)])) < 1e-5f);
    }
    const sepal::AcqObject torus = object("torus", 32);
    CHECK(torus.atlas.texels.size() == 32 * 32);
    sepal::AcqObject bad;
    std::string err;
    CHECK_FALSE(sepal::make_object("teapot", 32, &bad, &err));
    CHECK(err.find("teapot") != std::string::npos);
    CHECK_FALSE(sepal::make_object("sphere", 4, &bad, &err));
}

TEST_CASE("acquire atlas: neighbours cross the UV square's edges only where the surface continues") {
    std::string err;
    sepal::AcqObject sphere, torus, wave;
    REQUIRE(sepal::make_object("sphere", 16, &sphere, &err));
    REQUIRE(sepal::make_object("torus", 16, &torus, &err));
    REQUIRE(sepal::make_object("wave", 16, &wave, &err));
    const int corner = 0, inner = 5 * 16 + 5;
    CHECK(sphere.atlas.step(inner, 1, -1) == 4 * 16 + 6);
    CHECK(sphere.atlas.step(corner, -1, 0) == 15);  // around the sphere
    CHECK(sphere.atlas.step(corner, 0, -1) == -1);  // past a pole
    CHECK(torus.atlas.step(corner, -1, -1) == 15 * 16 + 15);
    CHECK(wave.atlas.step(corner, -1, 0) == -1);
    CHECK(wave.atlas.step(corner, 0, -1) == -1);
    CHECK(wave.atlas.step(corner, 1, 1) == 17);
}

TEST_CASE("acquire atlas: every texel a render looks up inside the mesh is set, the sphere's poles included") {
    // Renders and photographs take the texel under a pixel's interpolated UV (capture.cpp):
    // points all over every triangle, its corners and edges included, must land on set texels.
    for (const char* name : {"sphere", "torus", "wave"})
        for (int res : {32, 128}) {
            const sepal::AcqObject o = object(name, res);
            int unset = 0, looked = 0;
            for (size_t t = 0; t + 2 < o.indices.size(); t += 3)
                for (int i = 0; i <= 8; ++i)
                    for (int j = 0; i + j <= 8; ++j) {
                        const double w[3] = {i / 8.0, j / 8.0, (8 - i - j) / 8.0};
                        double u = 0, v = 0;
                        for (int k = 0; k < 3; ++k) {
                            u += w[k] * o.vertices[o.indices[t + size_t(k)]].uv[0];
                            v += w[k] * o.vertices[o.indices[t + size_t(k)]].uv[1];
                        }
                        const int x = std::min(res - 1, std::max(0, int(float(u) * res)));
                        const int y = std::min(res - 1, std::max(0, int(float(v) * res)));
                        ++looked;
                        unset += !o.atlas.valid[size_t(y) * size_t(res) + size_t(x)];
                    }
            CAPTURE(name);
            CAPTURE(res);
            CHECK(looked > 1000);
            CHECK(unset == 0);
        }
}

TEST_CASE("acquire visibility: a convex sphere hides exactly its back; the torus also hides and shadows itself") {
    const sepal::AcqObject s = object("sphere", 64);
    const dvec3 eye(0.3, -4, 0.8);
    sepal::PointView v;
    sepal::view_from_point(s, eye, 0, &v);
    int wrong = 0, seen = 0;
    for (int t : s.atlas.texels) {
        const dvec3 p(s.atlas.position[size_t(t)]);
        // Front-facing w.r.t. the point, away from the grazing band where the faceted
        // mesh and the smooth normal disagree.
        const double c = glm::dot(dvec3(s.atlas.normal[size_t(t)]), glm::normalize(eye - p));
        if (std::fabs(c) < 0.05) continue;
        wrong += (c > 0) != bool(v.ok[size_t(t)]);
        seen += v.ok[size_t(t)];
    }
    CHECK(seen > 1000);
    CHECK(wrong == 0);

    // The torus seen from the side: the inner side of the far half faces the viewer but is
    // hidden by the near half. Reference: march the ray to the eye through the torus's
    // signed distance (radii 0.7 and 0.3), exact up to the step.
    const sepal::AcqObject tor = object("torus", 64);
    const dvec3 eye2(0, -4, 0.3);
    sepal::view_from_point(tor, eye2, 0, &v);
    auto sdf = [](const dvec3& p) { return glm::length(glm::dvec2(glm::length(glm::dvec2(p.x, p.y)) - 0.7, p.z)) - 0.3; };
    int facing = 0, hidden = 0, disagree = 0;
    for (int t : tor.atlas.texels) {
        const dvec3 p(tor.atlas.position[size_t(t)]);
        const dvec3 d = glm::normalize(eye2 - p);
        if (glm::dot(dvec3(tor.atlas.normal[size_t(t)]), d) < 0.2) continue;
        ++facing;
        bool blocked = false;
        for (double s = 0.03; s < 2.5 && !blocked; s += 0.005) blocked = sdf(p + s * d) < -0.01;
        hidden += blocked;
        disagree += blocked == bool(v.ok[size_t(t)]);
    }
    INFO(facing << " facing texels, " << hidden << " hidden, " << disagree << " disagree");
    CHECK(hidden > facing / 5);
    CHECK(disagree <= facing / 50);  // texels along the occluding edge (depth-map pixels, facets)
}

TEST_CASE("acquire capture: without noise the samples are the SVBRDF itself; with it, z-scores are standard") {
    const sepal::AcqObject o = object("torus", 48);
    sepal::SvbrdfGenOptions g;
    sepal::BlendSvbrdf truth;
    std::string err;
    REQUIRE(sepal::make_svbrdf(48, g, &truth, &err));
    sepal::RigOptions rig;
    rig.noise_read = rig.noise_shot = 0;
    const sepal::ViewPair v = sepal::view_from_angles(-80, 30, -40, 60);
    sepal::Capture c;
    sepal::capture_atlas(o, truth, v, rig, 1, &c);
    REQUIRE(c.size() > 300);
    const double cos_max = std::cos(rig.max_angle_deg * M_PI / 180);
    for (size_t i = 0; i < c.size(); ++i) {
        const dvec3 f = truth.eval(c.texel[i], dvec3(c.wi[i]), dvec3(c.wo[i]));
        CHECK(glm::length(dvec3(c.value[i]) - f) <= 1e-5 * (1 + glm::length(f)));
        CHECK(c.wi[i].z >= cos_max - 1e-6);
        CHECK(c.wo[i].z >= cos_max - 1e-6);
    }
    // Noise: (measured - true) / std over all samples and channels, std from the rig's
    // model at the true radiance: mean ~0 and variance ~1.
    sepal::RigOptions noisy;
    sepal::Capture n;
    sepal::PointView lv;
    sepal::capture_atlas(o, truth, v, noisy, 2, &n, nullptr, &lv);
    REQUIRE(n.size() == c.size());
    double sum = 0, sum2 = 0;
    int count = 0;
    for (size_t i = 0; i < n.size(); ++i) {
        const size_t t = size_t(n.texel[i]);
        const double E = sepal::light_intensity(o, noisy) * lv.local[t].z / lv.dist2[t];
        const dvec3 f = truth.eval(n.texel[i], dvec3(n.wi[i]), dvec3(n.wo[i]));
        for (int k = 0; k < 3; ++k) {
            const double z = (n.value[i][k] - f[k]) * E / sepal::radiance_std(noisy, f[k] * E);
            sum += z;
            sum2 += z * z;
            ++count;
        }
    }
    const double mean = sum / count, var = sum2 / count - mean * mean;
    INFO(count << " values: mean " << mean << ", variance " << var);
    CHECK(std::fabs(mean) < 4 / std::sqrt(double(count)));
    CHECK(var == doctest::Approx(1.0).epsilon(0.08));
    // The same seed gives the same capture.
    sepal::Capture again;
    sepal::capture_atlas(o, truth, v, noisy, 2, &again);
    CHECK(again.value == n.value);
    // Camera and light too close together: no view.
    sepal::capture_atlas(o, truth, sepal::view_from_angles(0, 0, 3, 0), noisy, 2, &again);
    CHECK(again.size() == 0);
}

TEST_CASE("acquire render: a one-material SVBRDF renders like the exact backend; photographs measure their pixels") {
    const sepal::AcqObject o = object("sphere", 64);
    const std::string spec = "blinn:rho_d=0.4/0.2/0.1,rho_s=0.3,n=40";
    const sepal::BlendSvbrdf sv = single(spec, 64);
    sepal::RigOptions rig;
    const sepal::ViewPair v = sepal::view_from_angles(-90, 20, -50, 40);
    const sepal_scene scene = sepal::scene_for_view(o, v, rig);
    sepal::Image a, b;
    std::string err;
    REQUIRE(sepal::render_svbrdf(o, sv, scene, 96, 96, sepal::RenderSvbrdfOptions(), &a, &err));
    auto brdf = sepal::make_brdf(spec, &err);
    sepal::ExactStats stats;
    REQUIRE(sepal::render_exact(*brdf, scene, o.mesh(), 96, 96, &b, &stats, &err));
    double worst = 0;
    for (size_t i = 0; i < a.data.size(); ++i) worst = std::max(worst, double(std::fabs(a.data[i] - b.data[i])));
    CHECK(worst < 1e-4);

    // A photograph with shadows and noise: every measured pixel's value times its
    // irradiance is the pixel (one light), and the pixels are a subset of the covered ones.
    sepal::RenderSvbrdfOptions po;
    po.shadows = po.noise = true;
    po.rig = &rig;
    po.seed = 9;
    std::vector<sepal::PhotoSample> samples;
    sepal::Image photo;
    REQUIRE(sepal::render_svbrdf(o, sv, scene, 96, 96, po, &photo, &err, &samples));
    REQUIRE(samples.size() > 1000);
    const dvec3 light(scene.lights[0].position[0], scene.lights[0].position[1], scene.lights[0].position[2]);
    int bad = 0;
    for (const sepal::PhotoSample& s : samples) {
        const double L = photo.at(s.x, s.y, 1);
        CHECK(s.weight > 0);
        bad += !(std::isfinite(L) && std::fabs(s.value.y) < 100);
    }
    CHECK(bad == 0);
    (void)light;
}
