#include "sampling/mc_render.h"

#include <atomic>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "brdf/brdf_util.h"
#include "reference/surface.h"
#include "util/parallel.h"
#include "util/progress.h"

namespace sepal {

using glm::dvec3;

bool render_mc(const Brdf& brdf, const sepal_sampler& sampler, const Environment& env,
               const sepal_scene& scene, const sepal_mesh& mesh, int width, int height,
               const McOptions& o, McResult* out, std::string* err) {
    if (o.spp < 1 || o.spp > 1000000) {
        if (err) *err = "render: --spp " + std::to_string(o.spp) + " out of range 1..1000000";
        return false;
    }
    const auto start = std::chrono::steady_clock::now();
    const bool mis = o.mis == Mis::On || (o.mis == Mis::Auto && !env.constant(nullptr));
    EnvironmentSampler own;
    const EnvironmentSampler* light = o.light;
    if (mis && !light) {
        if (!own.build(env, kMcLightWidth, kMcLightHeight, err)) return false;
        light = &own;
    }
    SurfaceBuffer g;
    if (!rasterize_surface(scene, mesh, width, height, &g, err)) return false;
    McResult r;
    r.image = Image(width, height, 3);
    r.shaded.assign(size_t(width) * height, 0);
    const sepal_camera& cam = scene.camera;
    const dvec3 eye(cam.eye[0], cam.eye[1], cam.eye[2]);
    const dvec3 fwd = glm::normalize(dvec3(cam.target[0], cam.target[1], cam.target[2]) - eye);
    const dvec3 right = glm::normalize(glm::cross(fwd, dvec3(cam.up[0], cam.up[1], cam.up[2])));
    const dvec3 up = glm::cross(right, fwd);
    const double tan_half = std::tan(cam.fovy_degrees * kPi / 360.0), aspect = double(width) / height;
    std::atomic<int64_t> shaded{0}, back{0}, degenerate{0}, samples{0}, below{0}, failed{0}, lights{0};
    Progress progress(o.progress, "sepal render: " + std::to_string(o.spp) + " spp", size_t(height));
    parallel_for(size_t(height), o.threads, [&](size_t row) {
        const int y = int(row);
        std::vector<float> u, ul;
        int64_t sh = 0, bf = 0, dg = 0, sm = 0, bl = 0, fl = 0, ls = 0;
        for (int x = 0; x < width; ++x) {
            const size_t p = size_t(y) * width + x;
            float* rgb = &r.image.data[p * 3];
            dvec3 L(0.0);
            if (!g.covered[p]) {
                const double sx = (2.0 * (x + 0.5) / width - 1.0) * aspect * tan_half;
                const double sy = (1.0 - 2.0 * (y + 0.5) / height) * tan_half;
                L = env.radiance(glm::normalize(fwd + sx * right + sy * up));
            } else {
                SurfacePoint sp;
                const FrameStatus fs = surface_point(g, p, &sp);
                if (fs != FrameStatus::Ok) ++dg;
                const dvec3 wo = fs == FrameStatus::BadNormal ? dvec3(0, 0, -1) : sp.local(glm::normalize(eye - sp.position));
                if (fs != FrameStatus::BadNormal && !(wo.z > 0)) ++bf;
                if (fs != FrameStatus::BadNormal && wo.z > 0) {
                    ++sh;
                    r.shaded[p] = 1;
                    const float wof[3] = {float(wo.x), float(wo.y), float(wo.z)};
                    sepal_sampler_view view;
                    sepal_sampler_set_view(&sampler, wof, &view);
                    pixel_points(o.sequence, o.spp, o.seed, p, &u);
                    // The light samples' own sequence: another seed, so the two are independent.
                    if (mis) pixel_points(o.sequence, o.spp, o.seed ^ 0x6c1a5eedULL, p, &ul);
                    for (int s = 0; s < o.spp; ++s) {
                        float wi[3], pdf;
                        const int k = sepal_sampler_sample(&view, &u[size_t(s) * 2], wi, &pdf);
                        if (k == 1) {
                            const dvec3 wl(wi[0], wi[1], wi[2]);
                            const dvec3 dir = glm::normalize(sp.world(wl));
                            const dvec3 f = brdf.eval(wl, wo);
                            L += env.radiance(dir) * f * (wl.z / (pdf + (mis ? light->pdf(dir) : 0.0)));
                        } else {
                            ++(k == 0 ? bl : fl);
                        }
                        if (!mis) continue;
                        double pl = 0;
                        const dvec3 dir = light->sample(ul[size_t(s) * 2], ul[size_t(s) * 2 + 1], &pl);
                        ++ls;
                        const dvec3 wl = sp.local(dir);
                        if (!(wl.z > 0) || !(pl > 0)) continue;
                        const float wlf[3] = {float(wl.x), float(wl.y), float(wl.z)};
                        const double pb = sepal_sampler_pdf(&view, wlf);
                        L += env.radiance(dir) * brdf.eval(wl, wo) * (wl.z / (pl + pb));
                    }
                    L /= double(o.spp);
                    sm += o.spp;
                }
            }
            for (int c = 0; c < 3; ++c) rgb[c] = std::isfinite(L[c]) ? float(L[c]) : 0.0f;
        }
        shaded += sh, back += bf, degenerate += dg, samples += sm, below += bl, failed += fl, lights += ls;
        progress.advance();
    });
    r.shaded_pixels = shaded, r.back_facing = back, r.degenerate = degenerate;
    r.samples = samples, r.below_horizon = below, r.failed = failed;
    r.light_samples = lights, r.mis = mis;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    *out = std::move(r);
    return true;
}

}  // namespace sepal
