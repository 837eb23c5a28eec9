#include "bake/asset_brdf.h"

#include <algorithm>
#include <cstdio>

#include "util/io.h"
#include "util/json.h"

namespace sepal {

std::string evaluation_formula(bool radiance, bool reciprocal, bool profile, bool capped, double horizon) {
    char window[64] = "";
    if (radiance && horizon > 0) std::snprintf(window, sizeof window, " min(1, cos(theta_i) / %.6g)", horizon);
    std::string sum = std::string("max(0, ratio_c sum_k G_k(x) H_k(y)") + (reciprocal ? " G_k(x~))" : ")") +
                      (radiance ? window : " cos(theta_i)") + " + diffuse_c cos(theta_i)" +
                      (profile ? " profile_c(cos(theta_i), cos(theta_o))" : "");
    return capped ? "min(white_level, " + sum + ")" : sum;
}

std::unique_ptr<AssetBrdf> AssetBrdf::load(const std::string& path, std::string* err) {
    auto a = std::unique_ptr<AssetBrdf>(new AssetBrdf());
    a->path_ = path;
    if (!read_file(path, &a->bytes_, err, uint64_t(SEPAL_FMT_MAX_FILE_BYTES) + 1)) return nullptr;
    a->asset_ = std::make_unique<sepal_asset>();
    sepal_error e{};
    if (sepal_asset_parse(a->bytes_.data(), a->bytes_.size(), a->asset_.get(), &e) != SEPAL_OK) {
        *err = path + ": invalid: " + e.message;
        return nullptr;
    }
    Json meta;
    if (a->asset_->meta &&
        parse_json(std::string(a->asset_->meta, a->asset_->meta_bytes), path + " META", &meta, nullptr))
        json_string(JsonField{meta, ""}, "spec", &a->source_, nullptr);
    return a;
}

glm::dvec3 AssetBrdf::drawn_cos(const glm::dvec3& wi, const glm::dvec3& wo) const {
    const float i[3] = {float(wi.x), float(wi.y), float(wi.z)}, o[3] = {float(wo.x), float(wo.y), float(wo.z)};
    float fc[3];
    if (sepal_asset_eval(asset_.get(), i, o, fc) != 1) return glm::dvec3(0.0);
    return glm::dvec3(fc[0], fc[1], fc[2]);
}

glm::dvec3 AssetBrdf::eval_cos(const glm::dvec3& wi, const glm::dvec3& wo) const {
    glm::dvec3 v = drawn_cos(wi, wo);
    const double white = asset_->material.white_level;
    if (white > 0)
        for (int c = 0; c < 3; ++c) v[c] = std::min(v[c], white);
    return v;
}

glm::dvec3 AssetBrdf::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    if (wi.z <= 0 || wo.z <= 0) return glm::dvec3(0.0);
    return eval_cos(wi, wo) / wi.z;
}

std::string AssetBrdf::info() const {
    const sepal_fmt_material& m = asset_->material;
    const bool radiance = (m.flags & SEPAL_MATERIAL_RADIANCE) != 0;
    char line[512];
    std::string s = "source             " + (source_.empty() ? std::string("not recorded") : source_) + "\n";
    std::snprintf(line, sizeof line, "factors            %u term%s, %s, colour ratio %g %g %g%s\n", m.terms,
                  m.terms == 1 ? "" : "s", radiance ? "holding f cos(theta_i) (radiance)" : "holding f",
                  double(m.ratio[0]), double(m.ratio[1]), double(m.ratio[2]),
                  (m.flags & SEPAL_MATERIAL_RECIPROCAL) ? ", reciprocal (G H G~)" : "");
    s += line;
    std::snprintf(line, sizeof line, "diffuse part       %g %g %g /sr%s\n", double(m.diffuse[0]), double(m.diffuse[1]),
                  double(m.diffuse[2]),
                  asset_->diffuse_side ? (" times a " + std::to_string(asset_->diffuse_side) + "x" +
                                          std::to_string(asset_->diffuse_side) + " profile over (cos_i, cos_o)")
                                             .c_str()
                                       : "");
    s += line;
    if (m.white_level > 0)
        std::snprintf(line, sizeof line, "white level        %.6g/sr: f cos(theta_i) is capped there\n",
                      double(m.white_level));
    else
        std::snprintf(line, sizeof line, "white level        none (nothing capped)\n");
    s += line;
    const std::string sum = evaluation_formula(radiance, (m.flags & SEPAL_MATERIAL_RECIPROCAL) != 0,
                                               asset_->diffuse_side > 0, m.white_level > 0, m.horizon);
    s += "evaluated as       f cos(theta_i) = " + sum + ", level 0 sampled bilinearly as the CPU backend does\n";
    return s;
}

}  // namespace sepal
