#include "bake/image_score.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "util/enum_names.h"
#include "reference/render_exact.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_material.h"
#include "sepal/internal/sepal_emulate.h"

namespace sepal {
namespace {

// 8-bit levels (as floats in [0, 1]) of a linear image, as a PNG would store it.
void quantize8(Image* img) {
    for (float& v : img->data) v = std::round(std::min(1.0f, std::max(0.0f, v)) * 255.0f) / 255.0f;
}

}  // namespace

constexpr EnumName<Target> kTargets[] = {{Target::Gles1, "gles1"}, {Target::Gles2, "gles2"}, {Target::Cpu, "cpu"}};

const char* target_name(Target t) { return enum_name(kTargets, t); }

bool parse_target(const std::string& name, Target* t) { return parse_enum(kTargets, name, t); }

sepal_mesh BakeView::mesh() const {
    sepal_mesh m = {};
    m.vertices = const_cast<sepal_vertex*>(vertices.data());
    m.indices = const_cast<uint16_t*>(indices.data());
    m.vertex_count = int(vertices.size());
    m.index_count = int(indices.size());
    return m;
}

BakeView sphere_view(const std::string& name, const sepal_scene& scene) {
    BakeView v;
    v.name = name;
    v.scene = scene;
    // The sphere of the scene flags' `--mesh sphere`.
    const int sl = SEPAL_SCENE_SPHERE_SLICES, st = SEPAL_SCENE_SPHERE_STACKS;
    v.vertices.resize(size_t(sl + 1) * size_t(st + 1));
    v.indices.resize(size_t(sl) * size_t(st) * 6);
    sepal_mesh m = {v.vertices.data(), v.indices.data(), int(v.vertices.size()), int(v.indices.size())};
    sepal_error e = {};
    if (sepal_mesh_sphere(sl, st, &m, &e) == SEPAL_OK) {
        v.vertices.resize(size_t(m.vertex_count));
        v.indices.resize(size_t(m.index_count));
    }
    return v;
}

std::vector<BakeView> default_bake_views() {
    sepal_scene s;
    sepal_scene_default(&s);
    std::vector<BakeView> views;
    views.push_back(sphere_view("default", s));
    // Lit from the right and behind, at the default light's distance and intensity: the
    // terminator runs across the visible half, and the light grazes most of what is lit.
    const float behind[3] = {3.83f, 1.91f, 0.96f};
    for (int k = 0; k < 3; ++k) s.lights[0].position[k] = behind[k];
    views.push_back(sphere_view("grazing", s));
    return views;
}

double min_lit_irradiance(const std::vector<BakeView>& views) {
    double lowest = 0;
    for (const BakeView& v : views) {
        const sepal_camera& cam = v.scene.camera;
        for (const sepal_vertex& vx : v.vertices) {
            const glm::dvec3 p(vx.position[0], vx.position[1], vx.position[2]);
            const glm::dvec3 n = glm::dvec3(vx.normal[0], vx.normal[1], vx.normal[2]);
            const glm::dvec3 eye(cam.eye[0], cam.eye[1], cam.eye[2]);
            if (glm::dot(n, eye - p) <= 0) continue;  // not visible
            for (int l = 0; l < v.scene.light_count; ++l) {
                const sepal_light& light = v.scene.lights[l];
                glm::dvec3 to(light.position[0], light.position[1], light.position[2]);
                double falloff = 1;
                if (light.type == SEPAL_LIGHT_POINT) {
                    to -= p;
                    falloff = 1.0 / std::max(1e-12, glm::dot(to, to));
                }
                if (glm::dot(n, to) <= 0) continue;  // not lit
                const double e = std::max({light.intensity[0], light.intensity[1], light.intensity[2]}) * falloff;
                if (e > 0 && (lowest == 0 || e < lowest)) lowest = e;
            }
        }
    }
    return lowest;
}

bool ImageJudge::init(const Brdf& brdf, const std::vector<BakeView>& views, int size, int, std::string* err) {
    views_ = views;
    size_ = size;
    refs_.clear();
    for (const BakeView& v : views_) {
        Image img;
        if (!render_exact(brdf, v.scene, v.mesh(), size, size, &img, nullptr, err, false, kReferenceSupersample))
            return false;
        quantize8(&img);
        refs_.push_back(std::move(img));
    }
    min_irradiance_ = min_lit_irradiance(views_);
    return true;
}

bool ImageJudge::render(const std::vector<uint8_t>& bytes, Target target, size_t view, Image* out,
                        std::string* err, int* doublings) const {
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    if (sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }
    const BakeView& v = views_[view];
    const sepal_mesh mesh = v.mesh();
    if (target == Target::Cpu) {
        Image img(size_, size_, 3);
        std::vector<float> depth(size_t(size_) * size_), scratch(sepal_cpu_scratch_floats(mesh.vertex_count));
        sepal_cpu_desc d = {};
        d.asset = asset.get();
        d.mesh = &mesh;
        d.scene = &v.scene;
        d.width = d.height = size_;
        d.color = img.data.data();
        d.depth = depth.data();
        d.scratch = scratch.data();
        d.scratch_floats = scratch.size();
        if (sepal_draw_cpu(&d, &e) != SEPAL_OK) {
            if (err) *err = e.message;
            return false;
        }
        quantize8(&img);
        *out = std::move(img);
        return true;
    }
    std::vector<uint8_t> rgba(size_t(size_) * size_ * 4);
    std::vector<float> scratch(sepal_emulate_scratch_floats(size_, size_, mesh.vertex_count, v.scene.light_count));
    sepal_emulate_desc d = {};
    d.asset = asset.get();
    d.mesh = &mesh;
    d.scene = &v.scene;
    d.width = d.height = size_;
    d.gles_version = target == Target::Gles1 ? 1 : 2;
    d.rgba = rgba.data();
    d.scratch = scratch.data();
    d.scratch_floats = scratch.size();
    sepal_draw_stats stats = {};
    d.stats = &stats;
    if (sepal_emulate_draw(&d, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        return false;
    }
    *out = to_rgb(image_from_rgba8(rgba.data(), size_, size_));
    if (doublings) *doublings = stats.doublings;
    return true;
}

bool ImageJudge::score(const std::vector<uint8_t>& bytes, Target target, ImageScore* out, std::string* err) const {
    *out = ImageScore{};
    double total = 0;
    int64_t values = 0;
    for (size_t i = 0; i < views_.size(); ++i) {
        Image img;
        if (!render(bytes, target, i, &img, err, i == 0 ? &out->doublings : nullptr)) return false;
        const ImageDiff d = diff_images(refs_[i], img, 16);
        out->per_view.push_back(d.psnr);
        out->share_over16.push_back(d.share_over);
        total += d.mse * double(img.data.size());
        values += int64_t(img.data.size());
    }
    const double mse = values ? total / double(values) : 0;
    out->psnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
    return true;
}

}  // namespace sepal
