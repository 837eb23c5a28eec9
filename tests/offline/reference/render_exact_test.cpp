// The exact backend: per-pixel frames and radiance against analytic values on a sphere.
#include <doctest/doctest.h>

#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "reference/render_exact.h"
#include "common/scene_flags.h"
#include "test_util.h"

namespace {

// f = rho / pi: radiance = rho / pi * cos(theta_i) * E for a directional light.
class Lambert : public sepal::Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (wi.z <= 0 || wo.z <= 0) return glm::dvec3(0.0);
        return glm::dvec3(0.8, 0.5, 0.2) / M_PI;
    }
    std::string spec() const override { return "test-lambert"; }
    std::string model() const override { return "test-lambert"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return true; }
};

// Returns the local view direction, remapped to [0,1], divided by cos(theta_i) so the
// rendered radiance (with a unit directional light) shows the frame itself.
class FrameProbe : public sepal::Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        if (wi.z <= 0 || wo.z <= 0) return glm::dvec3(0.0);
        return (wo * 0.5 + 0.5) / wi.z;
    }
    std::string spec() const override { return "test-probe"; }
    std::string model() const override { return "test-probe"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return false; }
};

// The analytic sphere point seen through pixel (x, y), if any.
bool sphere_hit(const sepal_scene& s, int W, int H, int x, int y, glm::dvec3* p) {
    float view[16], proj[16];
    sepal_scene_matrices(&s, W, H, view, proj, nullptr);
    const glm::dmat4 inv = glm::inverse(glm::dmat4(glm::make_mat4(proj) * glm::make_mat4(view)));
    const double nx = (x + 0.5) / W * 2 - 1, ny = 1 - (y + 0.5) / H * 2;
    glm::dvec4 a = inv * glm::dvec4(nx, ny, -1, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
    const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::normalize(glm::dvec3(b) / b.w - o);
    const double bq = glm::dot(o, d), c = glm::dot(o, o) - 1.0, disc = bq * bq - c;
    if (disc < 0) return false;
    *p = o + d * (-bq - std::sqrt(disc));
    return true;
}

}  // namespace

TEST_CASE("exact render: Lambert sphere matches the analytic radiance") {
    sepal_ports::SceneSetup s;
    s.width = 96;
    s.height = 80;
    s.scene.lights[0].type = SEPAL_LIGHT_DIRECTIONAL;
    const glm::dvec3 L = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    s.scene.lights[0].position[0] = float(L.x);
    s.scene.lights[0].position[1] = float(L.y);
    s.scene.lights[0].position[2] = float(L.z);
    s.scene.lights[0].intensity[0] = s.scene.lights[0].intensity[1] = s.scene.lights[0].intensity[2] = 2.0f;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
    sepal::Image img;
    sepal::ExactStats stats;
    REQUIRE_MESSAGE(sepal::render_exact(Lambert(), s.scene, s.mesh, s.width, s.height, &img, &stats, &err), err);
    CHECK(stats.covered_pixels > s.width * s.height / 5);
    int compared = 0;
    double worst = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            glm::dvec3 p;
            if (!sphere_hit(s.scene, s.width, s.height, x, y, &p)) continue;
            // Skip the silhouette band, where the tessellated and the true sphere differ.
            const glm::dvec3 to_eye = glm::normalize(glm::dvec3(0, -3.2, 1.4) - p);
            if (glm::dot(to_eye, p) < 0.3) continue;
            const double expect = 0.8 / M_PI * std::max(0.0, glm::dot(p, L)) * 2.0;
            worst = std::max(worst, std::fabs(img.at(x, y, 0) - expect));
            ++compared;
        }
    CHECK(compared > 1000);
    // 64 x 32 tessellation: interpolated normals are within ~0.3 degrees of the sphere's.
    CHECK(worst < 0.01);
}

TEST_CASE("exact render: S x S supersampling is the box average of an S-times finer render; coverage stays") {
    // Pixel (x, y) at S holds the mean over the S x S sub-pixel centres, which are the pixel
    // centres of an image S times larger: where all of them lie on the surface the two agree
    // (to float rasterization); coverage is the pixel centre's, as GL's.
    sepal_ports::SceneSetup s;
    std::string err;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&s, &err), err);
    const int W = 48, H = 40, S = 4;
    sepal::Image point, fine, ss;
    REQUIRE_MESSAGE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, W, H, &point, nullptr, &err), err);
    REQUIRE_MESSAGE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, W * S, H * S, &fine, nullptr, &err), err);
    sepal::ExactStats stats;
    REQUIRE_MESSAGE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, W, H, &ss, &stats, &err, false, S), err);
    sepal::ExactStats stats_point;
    REQUIRE_MESSAGE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, W, H, &point, &stats_point, &err), err);
    CHECK(stats.covered_pixels == stats_point.covered_pixels);
    int interior = 0;
    double worst = 0, moved = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            // Pixels whose S x S samples are all shaded (lit, on the surface) in the fine render.
            bool all = true;
            double mean[3] = {0, 0, 0};
            for (int j = 0; j < S; ++j)
                for (int i = 0; i < S; ++i) {
                    all = all && fine.at(x * S + i, y * S + j, 2) > 0;
                    for (int c = 0; c < 3; ++c) mean[c] += fine.at(x * S + i, y * S + j, c) / (S * S);
                }
            if (!all) continue;
            ++interior;
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::fabs(ss.at(x, y, c) - mean[c]) / mean[c]);
                moved = std::max(moved, std::fabs(ss.at(x, y, c) - point.at(x, y, c)) / mean[c]);
            }
        }
    CAPTURE(worst);
    CAPTURE(moved);
    CHECK(interior > 400);
    // The same sample positions, rasterized at two sizes in float (FrameProbe divides by
    // cos(theta_i), which amplifies it near the terminator): measured 1.1e-3 relative.
    CHECK(worst < 3e-3);
    CHECK(moved > 10 * worst);  // not the centre sample: the frame changes across a pixel
    // Out of range: refused, with the range.
    CHECK_FALSE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, W, H, &ss, nullptr, &err, false, 9));
    CHECK(err.find("1..8") != std::string::npos);
}

TEST_CASE("exact render: the per-pixel frame is the sphere's analytic frame") {
    sepal_ports::SceneSetup s;
    s.width = 64;
    s.height = 64;
    s.scene.lights[0].type = SEPAL_LIGHT_DIRECTIONAL;
    s.scene.lights[0].position[0] = 0;
    s.scene.lights[0].position[1] = -1;  // towards the camera side: lights what we see
    s.scene.lights[0].position[2] = 0.4f;
    s.scene.lights[0].intensity[0] = s.scene.lights[0].intensity[1] = s.scene.lights[0].intensity[2] = 1.0f;
    std::string err;
    REQUIRE(sepal_ports::load_scene_mesh(&s, &err));
    sepal::Image img;
    REQUIRE(sepal::render_exact(FrameProbe(), s.scene, s.mesh, s.width, s.height, &img, nullptr, &err));
    const glm::dvec3 eye(s.scene.camera.eye[0], s.scene.camera.eye[1], s.scene.camera.eye[2]);
    const glm::dvec3 light = glm::normalize(glm::dvec3(0, -1, 0.4));
    double worst = 0;
    int compared = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            glm::dvec3 p;
            if (!sphere_hit(s.scene, s.width, s.height, x, y, &p)) continue;
            const glm::dvec3 n = p, t = glm::normalize(glm::dvec3(-p.y, p.x, 0)), b = glm::cross(n, t);
            const glm::dvec3 w = glm::normalize(eye - p);
            if (glm::dot(w, n) < 0.3 || glm::dot(light, n) < 0.3 || std::fabs(n.z) > 0.95) continue;
            const glm::dvec3 local(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n));
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::fabs(img.at(x, y, c) - (local[c] * 0.5 + 0.5)));
            ++compared;
        }
    CHECK(compared > 300);
    CHECK(worst < 0.02);
}

TEST_CASE("exact render: scene errors are reported") {
    sepal_ports::SceneSetup s;
    std::string err;
    REQUIRE(sepal_ports::load_scene_mesh(&s, &err));
    s.scene.lights[0].intensity[1] = -1;
    sepal::Image img;
    CHECK_FALSE(sepal::render_exact(Lambert(), s.scene, s.mesh, 32, 32, &img, nullptr, &err));
    CHECK(err.find("intensity") != std::string::npos);
    sepal_ports::SceneSetup t;
    t.mesh_name = "/no/such/mesh.obj";
    CHECK_FALSE(sepal_ports::load_scene_mesh(&t, &err));
    CHECK(err.find("mesh.obj") != std::string::npos);
}
