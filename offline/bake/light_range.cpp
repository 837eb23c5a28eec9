#include "bake/light_range.h"

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "brdf/brdf_util.h"

namespace sepal {
namespace {

// The default scene's light: position, and its squared distance to the origin.
constexpr double kDefaultLight[3] = {2.0, -2.5, 3.0};
constexpr double kDistance2 = 2.0 * 2.0 + 2.5 * 2.5 + 3.0 * 3.0;
constexpr double kDefaultIntensity = 60.0;
// The grazing view's light: from the side and behind.
constexpr double kGrazingLight[3] = {3.83, 1.91, 0.96};
// Directions farther than about 155 degrees from the eye light only a sliver the camera
// cannot resolve.
constexpr double kBehind = -0.9;
// The held-out stream: another seed, never the training one.
constexpr uint64_t kHeldOutSalt = 0x9e1d07ull;

sepal_light point_light(const glm::dvec3& dir, double irradiance) {
    sepal_light l = {};
    l.type = SEPAL_LIGHT_POINT;
    const glm::dvec3 p = glm::normalize(dir) * std::sqrt(kDistance2);
    for (int k = 0; k < 3; ++k) {
        l.position[k] = float(p[k]);
        l.intensity[k] = float(irradiance * kDistance2);
    }
    return l;
}

// Draws directions in the cone about +z, uniform in solid angle, all but those close to
// straight behind the object as the default camera sees it (kBehind).
class Draws {
  public:
    Draws(const LightRange& r, uint64_t seed) : r_(r), rng_(seed) {
        sepal_scene s;
        sepal_scene_default(&s);
        eye_ = glm::normalize(glm::dvec3(s.camera.eye[0], s.camera.eye[1], s.camera.eye[2]));
    }
    glm::dvec3 direction() {
        const double lo = std::cos(r_.cone_degrees * M_PI / 180.0);
        for (int tries = 0;; ++tries) {
            const double z = rng_.uniform(std::max(lo, 0.0), 1.0), phi = rng_.uniform(0.0, 2.0 * M_PI);
            const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
            const glm::dvec3 d(s * std::cos(phi), s * std::sin(phi), z);
            if (glm::dot(d, eye_) > kBehind || tries >= 64) return d;
        }
    }
    // A direction behind the object (its highlight on the visible rim), in the cone; any
    // drawn direction when the cone holds none.
    glm::dvec3 behind() {
        for (int tries = 0; tries < 64; ++tries) {
            const glm::dvec3 d = direction();
            if (glm::dot(d, eye_) < 0.0) return d;
        }
        return direction();
    }
    // Log-uniform between the range's ends.
    double irradiance() {
        const double lo = range_irradiance_min(r_), hi = range_irradiance_max(r_);
        return lo * std::pow(hi / lo, rng_.uniform());
    }

  private:
    const LightRange& r_;
    Rng rng_;
    glm::dvec3 eye_;
};

glm::dvec3 vec(const double p[3]) { return glm::dvec3(p[0], p[1], p[2]); }

}  // namespace

double default_irradiance() { return kDefaultIntensity / kDistance2; }
double range_irradiance_max(const LightRange& r) { return r.irradiance_max > 0 ? r.irradiance_max : default_irradiance(); }
double range_irradiance_min(const LightRange& r) { return range_irradiance_max(r) / std::max(1.0, r.ratio); }

bool validate_light_range(const LightRange& r, std::string* err) {
    auto fail = [&](const std::string& m) {
        if (err) *err = "light range: " + m;
        return false;
    };
    if (!(r.ratio >= 1.0 && r.ratio <= 1e6)) return fail("the ratio must be 1..1e6 (brightest : dimmest)");
    if (!(r.irradiance_max >= 0 && r.irradiance_max <= 1e6)) return fail("the brightest irradiance must be 0..1e6");
    if (!(r.cone_degrees > 0 && r.cone_degrees <= 180)) return fail("the cone must be in (0, 180] degrees");
    if (r.max_lights < 1 || r.max_lights > SEPAL_MAX_LIGHTS)
        return fail("lights at once must be 1.." + std::to_string(SEPAL_MAX_LIGHTS));
    if (r.meshes.empty() || r.meshes.size() > 3) return fail("meshes: 1..3 of sphere, torus, wave");
    for (const std::string& m : r.meshes)
        if (m != "sphere" && m != "torus" && m != "wave") return fail("mesh '" + m + "': sphere, torus or wave");
    return true;
}

std::string describe_light_range(const LightRange& r) {
    std::string meshes;
    for (const std::string& m : r.meshes) meshes += (meshes.empty() ? "" : ",") + m;
    char buf[200];
    std::snprintf(buf, sizeof buf, "%g:1, irradiance %.3g..%.3g at the object, cone %g deg, up to %d light%s, %s",
                  r.ratio, range_irradiance_min(r), range_irradiance_max(r), r.cone_degrees, r.max_lights,
                  r.max_lights == 1 ? "" : "s", meshes.c_str());
    return buf;
}

std::string LightCondition::flags() const {
    std::string s = "--mesh " + mesh;
    for (const sepal_light& l : lights) {
        char buf[160];
        if (l.intensity[0] == l.intensity[1] && l.intensity[1] == l.intensity[2])
            std::snprintf(buf, sizeof buf, " --light point:%.4g,%.4g,%.4g:%.4g", l.position[0], l.position[1],
                          l.position[2], l.intensity[0]);
        else
            std::snprintf(buf, sizeof buf, " --light point:%.4g,%.4g,%.4g:%.4g,%.4g,%.4g", l.position[0], l.position[1],
                          l.position[2], l.intensity[0], l.intensity[1], l.intensity[2]);
        s += buf;
    }
    return s;
}

std::vector<LightCondition> training_conditions(const LightRange& r) {
    Draws draw(r, r.seed);
    const double hi = range_irradiance_max(r), lo = range_irradiance_min(r);
    std::vector<LightCondition> out;
    out.push_back({"default", "sphere", {point_light(vec(kDefaultLight), hi)}});
    out.push_back({"grazing dim", "sphere", {point_light(vec(kGrazingLight), lo)}});
    out.push_back({"dim", "sphere", {point_light(draw.direction(), lo)}});
    {
        const glm::dvec3 d = draw.behind();
        out.push_back({"rim", "sphere", {point_light(d, draw.irradiance())}});
    }
    if (r.max_lights >= 2) {
        const glm::dvec3 a = draw.direction(), b = draw.direction();
        const double ea = draw.irradiance(), eb = draw.irradiance();
        out.push_back({"two lights", "sphere", {point_light(a, ea), point_light(b, eb)}});
    }
    for (const std::string& m : r.meshes)
        if (m != "sphere") {
            const glm::dvec3 d = draw.direction();
            out.push_back({m, m, {point_light(d, draw.irradiance())}});
        }
    return out;
}

std::vector<LightCondition> held_out_conditions(const LightRange& r) {
    Draws draw(r, r.seed ^ kHeldOutSalt);
    const double lo = range_irradiance_min(r);
    std::vector<LightCondition> out;
    // Each draw in its own statement: the order of a call's arguments is unspecified.
    auto drawn = [&](const std::string& name, const std::string& mesh) {
        const glm::dvec3 d = draw.direction();
        out.push_back({name, mesh, {point_light(d, draw.irradiance())}});
    };
    out.push_back({"held-out dim", "sphere", {point_light(draw.direction(), lo)}});
    drawn("held-out mid", "sphere");
    drawn("held-out torus", "torus");
    if (r.max_lights >= 2) {
        const glm::dvec3 a = draw.direction(), b = draw.direction();
        const double ea = draw.irradiance(), eb = draw.irradiance();
        out.push_back({"held-out two lights", "sphere", {point_light(a, ea), point_light(b, eb)}});
    }
    for (const std::string& m : r.meshes)
        if (m != "sphere" && m != "torus") drawn("held-out " + m, m);
    return out;
}

bool condition_view(const LightCondition& c, BakeView* out, std::string* err) {
    sepal_scene s;
    sepal_scene_default(&s);
    s.light_count = int(c.lights.size());
    for (size_t l = 0; l < c.lights.size() && l < SEPAL_MAX_LIGHTS; ++l) s.lights[l] = c.lights[l];
    if (c.mesh == "sphere") {
        *out = sphere_view(c.name, s);
        return true;
    }
    BakeView v;
    v.name = c.name;
    v.scene = s;
    const bool torus = c.mesh == "torus";
    v.vertices.resize(torus ? 97 * 49 : 65 * 65);
    v.indices.resize(torus ? 96 * 48 * 6 : 64 * 64 * 6);
    sepal_mesh m = {v.vertices.data(), v.indices.data(), int(v.vertices.size()), int(v.indices.size())};
    sepal_error e = {};
    const sepal_result res = torus ? sepal_mesh_torus(0.72f, 0.3f, 96, 48, &m, &e)
                                   : c.mesh == "wave" ? sepal_mesh_wave(64, &m, &e)
                                                      : SEPAL_ERR_INVALID_ARGUMENT;
    if (res != SEPAL_OK) {
        if (err) *err = "light range: mesh '" + c.mesh + "': " + (c.mesh == "wave" || torus ? e.message : "unknown");
        return false;
    }
    v.vertices.resize(size_t(m.vertex_count));
    v.indices.resize(size_t(m.index_count));
    *out = std::move(v);
    return true;
}

bool condition_views(const std::vector<LightCondition>& cs, std::vector<BakeView>* out, std::string* err) {
    out->clear();
    for (const LightCondition& c : cs) {
        BakeView v;
        if (!condition_view(c, &v, err)) return false;
        out->push_back(std::move(v));
    }
    return true;
}

}  // namespace sepal
