#include "acquire/capture.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "fit/lafortune_fit.h"
#include "reference/surface.h"
#include "util/parallel.h"

namespace sepal {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double counter_gauss(uint64_t seed, uint64_t i) {
    const double u = std::max(counter_uniform(seed, 2 * i), 1e-300), v = counter_uniform(seed, 2 * i + 1);
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * kPi * v);
}

glm::dvec3 direction_from_angles(double az, double el) {
    const double a = az * kPi / 180, e = el * kPi / 180;
    return glm::dvec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

ViewPair view_from_angles(double ca, double ce, double la, double le) {
    return {direction_from_angles(ca, ce), direction_from_angles(la, le)};
}

double separation_deg(const ViewPair& v) {
    const double c = glm::dot(glm::normalize(v.camera), glm::normalize(v.light));
    return std::acos(std::max(-1.0, std::min(1.0, c))) * 180 / kPi;
}

glm::dvec3 camera_position(const AcqObject& obj, const ViewPair& v, const RigOptions& rig) {
    return glm::normalize(v.camera) * (rig.camera_distance * obj.radius);
}
glm::dvec3 light_position(const AcqObject& obj, const ViewPair& v, const RigOptions& rig) {
    return glm::normalize(v.light) * (rig.light_distance * obj.radius);
}
double light_intensity(const AcqObject& obj, const RigOptions& rig) { return rig.light_intensity * obj.radius * obj.radius; }

namespace {

// The measurement of one sample: noisy radiance back to f, and the weight (capture.h).
struct Measured {
    glm::dvec3 value;
    double weight;
};

Measured measure(const glm::dvec3& f, double E, double cos_o, const RigOptions& rig, uint64_t seed, uint64_t i) {
    glm::dvec3 L = f * E;
    for (int c = 0; c < 3; ++c) L[c] += radiance_std(rig, L[c]) * counter_gauss(seed, i * 3 + uint64_t(c));
    // The weight comes from the reading itself (the truth is unknown to the capture).
    return {L / E, cos_o * E / radiance_std(rig, luminance(L))};
}

}  // namespace

void capture_atlas(const AcqObject& obj, const BlendSvbrdf& truth, const ViewPair& view, const RigOptions& rig,
                   uint64_t seed, Capture* out, PointView* cam_out, PointView* light_out) {
    PointView cam, light;
    view_from_point(obj, camera_position(obj, view, rig), rig.depth_res, &cam);
    view_from_point(obj, light_position(obj, view, rig), rig.depth_res, &light);
    Capture c;
    c.view = view;
    const double cos_max = std::cos(rig.max_angle_deg * kPi / 180);
    const double I = light_intensity(obj, rig);
    if (separation_deg(view) >= rig.min_separation_deg) {
        for (int t : obj.atlas.texels) {
            const size_t i = size_t(t);
            if (!cam.ok[i] || !light.ok[i]) continue;
            const glm::dvec3 wo(cam.local[i]), wi(light.local[i]);
            if (wo.z < cos_max || wi.z < cos_max) continue;
            const double E = I * wi.z / light.dist2[i];
            const Measured m = measure(truth.eval(t, wi, wo), E, wo.z, rig, seed, uint64_t(t));
            c.texel.push_back(t);
            c.wi.push_back(glm::vec3(wi));
            c.wo.push_back(glm::vec3(wo));
            c.value.push_back(glm::vec3(m.value));
            c.weight.push_back(float(m.weight));
        }
    }
    *out = std::move(c);
    if (cam_out) *cam_out = std::move(cam);
    if (light_out) *light_out = std::move(light);
}

sepal_scene scene_for_view(const AcqObject& obj, const ViewPair& view, const RigOptions& rig) {
    sepal_scene s;
    sepal_scene_default(&s);
    const glm::dvec3 eye = camera_position(obj, view, rig), lp = light_position(obj, view, rig);
    const double d = glm::length(eye);
    for (int k = 0; k < 3; ++k) {
        s.camera.eye[k] = float(eye[k]);
        s.camera.target[k] = 0;
        s.lights[0].position[k] = float(lp[k]);
        s.lights[0].intensity[k] = float(light_intensity(obj, rig));
    }
    const bool vertical = std::fabs(eye.z) > 0.99 * d;
    s.camera.up[0] = 0;
    s.camera.up[1] = vertical ? 1.0f : 0.0f;
    s.camera.up[2] = vertical ? 0.0f : 1.0f;
    s.camera.fovy_degrees = float(2 * std::asin(obj.radius / d) * 180 / kPi * 1.08);
    s.camera.z_near = float(std::max(1e-3, d - 1.05 * obj.radius));
    s.camera.z_far = float(d + 1.05 * obj.radius);
    s.light_count = 1;
    return s;
}


bool render_svbrdf(const AcqObject& obj, const BlendSvbrdf& sv, const sepal_scene& scene, int width, int height,
                   const RenderSvbrdfOptions& o, Image* out, std::string* err, std::vector<PhotoSample>* samples) {
    if (width < 1 || height < 1 || width > 4096 || height > 4096) {
        if (err) *err = "render svbrdf: image size outside 1..4096";
        return false;
    }
    if ((o.noise || o.shadows) && !o.rig) {
        if (err) *err = "render svbrdf: noise and shadows need the rig";
        return false;
    }
    if (sv.maps.width != obj.atlas.res || sv.maps.height != obj.atlas.res) {
        if (err) *err = "render svbrdf: the SVBRDF's atlas does not match the object's";
        return false;
    }
    SurfaceBuffer g;
    std::string why;
    if (!rasterize_surface(scene, obj.mesh(), width, height, &g, &why)) {
        if (err) *err = "render svbrdf: " + why;
        return false;
    }
    std::vector<PointView> lit(size_t(scene.light_count));
    if (o.shadows)
        for (int l = 0; l < scene.light_count; ++l)
            view_from_point(obj, glm::dvec3(glm::make_vec3(scene.lights[l].position)), o.rig->depth_res, &lit[size_t(l)]);
    const double cos_max = o.rig ? std::cos(o.rig->max_angle_deg * kPi / 180) : 0.0;

    *out = Image(width, height, 3);
    const glm::dvec3 eye(glm::make_vec3(scene.camera.eye));
    const int K = sv.materials(), res = sv.maps.width;
    std::vector<std::vector<PhotoSample>> rows(static_cast<size_t>(height));
    parallel_for(size_t(height), 0, [&](size_t row) {
        const int y = int(row);
        std::vector<float> w(static_cast<size_t>(K));
        for (int x = 0; x < width; ++x) {
            const size_t p = size_t(y) * width + x;
            float* rgb = &out->data[p * 3];
            std::copy(scene.background, scene.background + 3, rgb);
            if (!g.covered[p]) continue;
            SurfacePoint sp;
            if (surface_point(g, p, &sp) == FrameStatus::BadNormal) continue;
            auto local = [&](const glm::dvec3& d) { return sp.local(d); };
            const glm::dvec3& pos = sp.position;
            const glm::dvec3 wo = local(glm::normalize(eye - pos));
            if (wo.z <= 0) continue;
            const float u = float(sp.uv.x), vv = float(sp.uv.y);  // as rasterized
            sv.maps.sample_all(u, vv, w.data());
            const int tx = std::min(res - 1, std::max(0, int(u * res))), ty = std::min(res - 1, std::max(0, int(vv * res)));
            const int texel = ty * res + tx;
            glm::dvec3 L(0.0);
            for (int l = 0; l < scene.light_count; ++l) {
                const sepal_light& light = scene.lights[l];
                const glm::dvec3 lp(glm::make_vec3(light.position));
                glm::dvec3 to = light.type == SEPAL_LIGHT_POINT ? lp - pos : lp;
                const double d2 = light.type == SEPAL_LIGHT_POINT ? glm::dot(to, to) : 1.0;
                const glm::dvec3 wi = local(glm::normalize(to));
                if (wi.z <= 0) continue;
                if (o.shadows && !lit[size_t(l)].ok[size_t(texel)]) continue;
                const double E = wi.z / d2;
                const glm::dvec3 f = sv.eval_weights(w.data(), wi, wo);
                L += f * E * glm::dvec3(glm::make_vec3(light.intensity));
                if (samples && o.shadows && l == 0 && wi.z >= cos_max && wo.z >= cos_max) {
                    const double El = E * light.intensity[1];
                    const Measured m = measure(f, El, wo.z, *o.rig, o.seed, p);
                    rows[row].push_back({x, y, texel, glm::vec3(wi), glm::vec3(wo), glm::vec3(m.value), float(m.weight)});
                }
            }
            if (o.noise)
                for (int c = 0; c < 3; ++c) L[c] += radiance_std(*o.rig, L[c]) * counter_gauss(o.seed, p * 3 + uint64_t(c));
            for (int c = 0; c < 3; ++c) rgb[c] = float(L[c]);
        }
    });
    if (samples) {
        samples->clear();
        for (auto& r : rows) samples->insert(samples->end(), r.begin(), r.end());
    }
    return true;
}

}  // namespace sepal
