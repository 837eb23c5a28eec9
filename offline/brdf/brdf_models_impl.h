// Internal to the analytic models (brdf_models*.cpp): the shared base class and the table
// entry each model provides. Users include brdf_models.h instead.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/brdf_spec.h"

namespace sepal {

// Directions closer to the horizon than this cosine (89.99994 degrees) are evaluated as if
// at it: keeps every 1/cos finite without touching any angle a caller can meaningfully ask
// for (the extremes tests use 89.99 degrees, cos = 1.7e-4).
constexpr double kMinCos = 1e-6;

struct ModelEntry;

// Shared plumbing: spec/model/info from the table entry and parameter values; eval() checks
// the horizon and input, normalizes, lifts near-horizon directions to kMinCos, then calls
// eval_above() with unit vectors of z >= kMinCos.
class AnalyticBrdf : public Brdf {
  public:
    AnalyticBrdf(const ModelEntry& entry, const ParamSet& params) : entry_(entry), p_(params) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const final;
    std::string spec() const override;
    std::string model() const override;
    std::string info() const override;
    bool isotropic() const override { return true; }
    bool energy_conserving() const override { return false; }

  protected:
    virtual glm::dvec3 eval_above(const glm::dvec3& wi, const glm::dvec3& wo) const = 0;
    // Extra ",key=value" items after the table's parameters (Lafortune's lobes).
    virtual std::string extra_spec() const { return ""; }
    virtual std::string extra_info() const { return ""; }
    double scalar(const char* name) const { return p_.scalar(name); }
    glm::dvec3 colour(const char* name) const { return p_.colour(name); }

    const ModelEntry& entry_;
    ParamSet p_;
};

using ModelFactory = std::unique_ptr<Brdf> (*)(const ModelEntry& entry, const ParamSet& p,
                                               std::string* err);

// The factory of a model whose constructor takes (entry, params) and cannot fail.
template <class T>
std::unique_ptr<Brdf> make_model(const ModelEntry& e, const ParamSet& p, std::string*) {
    return std::make_unique<T>(e, p);
}

// A model: its description and parameters from brdf/models.json, its code from `make`.
struct ModelEntry {
    std::string name;
    std::string summary;
    std::string source;
    std::vector<ParamDef> params;
    std::vector<std::string> repeated;  // keys that may repeat (lafortune: "lobe")
    ModelFactory make = nullptr;
};

// The code side of each model, defined in the model files and paired with models.json's
// entry of the same name by the registry (brdf_models.cpp).
struct ModelCode {
    const char* name;
    ModelFactory make;
};
extern const ModelCode kSimpleModels[6];      // brdf_models.cpp
extern const ModelCode kMicrofacetModels[5];  // brdf_microfacet.cpp
extern const ModelCode kPoulinFournierModel;  // brdf_poulin_fournier.cpp

// Reads a model table in the format of brdf/models.json and pairs every entry with its code;
// false with the reason (what and where) when it is malformed, names a model without code, or
// leaves one out. The registry reads the compiled-in models.json this way; tests feed it others.
bool read_model_table(const char* json, std::vector<ModelEntry>* out, std::string* err);

inline double max3(const glm::dvec3& v) {
    return v.x > v.y ? (v.x > v.z ? v.x : v.z) : (v.y > v.z ? v.y : v.z);
}

}  // namespace sepal
