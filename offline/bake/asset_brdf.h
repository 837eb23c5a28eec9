// A baked asset read back as the BRDF it represents: what `sepal eval ASSET` and `sepal info
// ASSET` evaluate, so an asset can be compared with its source, or another tool's factors,
// at any direction pair.
//
// Usage:
//   std::string err;
//   std::unique_ptr<sepal::AssetBrdf> a = sepal::AssetBrdf::load("ward.sepal", &err);
//   if (!a) { fprintf(stderr, "%s\n", err.c_str()); return 2; }
//   glm::dvec3 f = a->eval(wi, wo);           // per steradian, as every Brdf
//   glm::dvec3 fc = a->eval_cos(wi, wo);      // f cos(theta_i): what the factors hold
//
// What it represents: the CPU backend's value for the pair (sepal_asset_eval: the factors'
// sum times the colour ratio, at least 0, times cos(theta_i) unless the material is a
// radiance one, plus the diffuse part times cos(theta_i) times its profile), capped per
// channel at the material's white level where it has one. The bake fits min(f cos, white):
// above the white level every light of the asset's range shows white, so the cap is part of
// what the asset stands for, and under such a light min(1, E eval_cos) is the CPU backend's
// pixel clipped to the display. drawn_cos is the uncapped value. f = f cos / cos(theta_i).
// Limits: level 0 only (what the CPU backend samples, not the GL backends' MIP levels and
// 8-bit combiners); isotropy is not claimed (the factors need not be).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "sepal/sepal_asset.h"

namespace sepal {

// The formula of f_c cos(theta_i) in these terms (for `sepal info` and the export's manifest);
// horizon: the radiance factors' horizon window c0 (0: none).
std::string evaluation_formula(bool radiance, bool reciprocal, bool profile, bool capped, double horizon);

class AssetBrdf : public Brdf {
  public:
    // Null with the reason in *err: unreadable file, or one the runtime's reader refuses.
    static std::unique_ptr<AssetBrdf> load(const std::string& path, std::string* err);
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override;
    glm::dvec3 eval_cos(const glm::dvec3& wi, const glm::dvec3& wo) const;
    glm::dvec3 drawn_cos(const glm::dvec3& wi, const glm::dvec3& wo) const;
    std::string spec() const override { return path_; }
    std::string model() const override { return "asset"; }
    std::string info() const override;
    bool isotropic() const override { return false; }
    const sepal_asset& asset() const { return *asset_; }
    // The META's "spec": the BRDF the asset was baked from ("" when it does not say).
    const std::string& source() const { return source_; }

  private:
    std::string path_, source_;
    std::vector<uint8_t> bytes_;  // the parsed asset points into them
    std::unique_ptr<sepal_asset> asset_;
};

}  // namespace sepal
