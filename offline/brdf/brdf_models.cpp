// The analytic model registry, the shared base class, and the simple closed-form models:
// lambert, phong, blinn, lafortune, oren-nayar, hapke-lommel.
#include "brdf/brdf_models.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "brdf/brdf_models_impl.h"
#include "brdf/brdf_util.h"
#include "util/json.h"

namespace sepal {

using glm::dvec3;

// ---- registry ----------------------------------------------------------------------------

namespace {

const char kModelsJson[] =
#include "brdf/models.json.inc"
    ;

// One parameter of models.json: {"name", "kind", "default" (a number, or [r, g, b] for a
// colour) or "default_from", "min", "max", "doc"}.
bool read_param(const Json& v, const std::string& where, ParamDef* d, std::string* err) {
    const JsonField f{v, where};
    std::string kind;
    if (!v.is_object()) return *err = where + ": not an object", false;
    if (!json_string(f, "name", &d->name, err, true) || !json_string(f, "kind", &kind, err, true) ||
        !json_number(f, "min", -1e300, 1e300, &d->lo, err, true) ||
        !json_number(f, "max", d->lo, 1e300, &d->hi, err, true) || !json_string(f, "doc", &d->doc, err, true) ||
        !json_string(f, "default_from", &d->default_from, err))
        return false;
    if (kind != "scalar" && kind != "colour") return *err = where + ".kind: '" + kind + "' is not scalar or colour", false;
    d->kind = kind == "colour" ? ParamKind::kColour : ParamKind::kScalar;
    if (!d->default_from.empty()) return true;
    if (d->kind == ParamKind::kColour && v.contains("default") && v["default"].is_array()) {
        double rgb[3];
        if (!json_numbers(f, "default", 3, rgb, err, true)) return false;
        for (int c = 0; c < 3; ++c)
            if (!(rgb[c] >= d->lo && rgb[c] <= d->hi)) return *err = where + ".default: outside min..max", false;
        d->def = dvec3(rgb[0], rgb[1], rgb[2]);
        return true;
    }
    if (!json_number(f, "default", d->lo, d->hi, &d->def.x, err, true)) return false;
    d->def = dvec3(d->def.x);
    return true;
}

}  // namespace

bool read_model_table(const char* json, std::vector<ModelEntry>* out, std::string* err) {
    Json doc;
    const Json* models = nullptr;
    out->clear();
    if (!parse_json(json, "brdf/models.json", &doc, err) ||
        !json_array(JsonField{doc, "brdf/models.json"}, "models", 1, 256, &models, err, true))
        return false;
    std::vector<ModelCode> code(std::begin(kSimpleModels), std::end(kSimpleModels));
    code.insert(code.end(), std::begin(kMicrofacetModels), std::end(kMicrofacetModels));
    code.push_back(kPoulinFournierModel);
    std::vector<ModelEntry> entries(models->size());
    for (size_t i = 0; i < models->size(); ++i) {
        const std::string where = "brdf/models.json: models[" + std::to_string(i) + "]";
        const Json& m = (*models)[i];
        const JsonField f{m, where};
        ModelEntry& e = entries[i];
        const Json* params = nullptr;
        const Json* repeated = nullptr;
        if (!m.is_object()) return *err = where + ": not an object", false;
        if (!json_string(f, "name", &e.name, err, true) || !json_string(f, "summary", &e.summary, err, true) ||
            !json_string(f, "source", &e.source, err, true) || !json_array(f, "params", 0, 64, &params, err, true) ||
            !json_array(f, "repeated", 0, 8, &repeated, err))
            return false;
        for (size_t j = 0; j < params->size(); ++j) {
            const std::string at = where + ".params[" + std::to_string(j) + "]";
            e.params.emplace_back();
            if (!read_param((*params)[j], at, &e.params.back(), err)) return false;
            for (size_t k = 0; k + 1 < e.params.size(); ++k)
                if (e.params[k].name == e.params.back().name)
                    return *err = at + ": parameter '" + e.params[k].name + "' listed twice", false;
        }
        // A default taken from another parameter names a colour one of this model with a default
        // of its own (bind_spec sets the plain defaults first, then these from them).
        for (size_t j = 0; j < e.params.size(); ++j) {
            const ParamDef& d = e.params[j];
            if (d.default_from.empty()) continue;
            const auto from = std::find_if(e.params.begin(), e.params.end(),
                                           [&](const ParamDef& o) { return o.name == d.default_from; });
            if (from == e.params.end() || from->kind != ParamKind::kColour || !from->default_from.empty() ||
                d.kind != ParamKind::kColour)
                return *err = where + ".params[" + std::to_string(j) + "].default_from: '" + d.default_from +
                              "' is not a colour parameter of this model with its own default",
                       false;
        }
        for (size_t k = 0; k < i; ++k)
            if (entries[k].name == e.name) return *err = where + ": model '" + e.name + "' listed twice", false;
        for (size_t j = 0; repeated && j < repeated->size(); ++j) {
            if (!(*repeated)[j].is_string()) return *err = where + ".repeated: not a list of names", false;
            e.repeated.push_back((*repeated)[j].get<std::string>());
        }
        for (const ModelCode& c : code)
            if (e.name == c.name) e.make = c.make;
        if (!e.make) return *err = where + ": no code for model '" + e.name + "'", false;
    }
    for (const ModelCode& c : code)
        if (std::none_of(entries.begin(), entries.end(), [&](const ModelEntry& e) { return e.name == c.name; }))
            return *err = std::string("brdf/models.json: no entry for model '") + c.name + "'", false;
    *out = std::move(entries);
    return true;
}

namespace {

// models.json's entries, each paired with its code by name. Both are part of the build, so a
// mismatch is this build's defect (tests/offline/brdf/brdf_models_test.cpp fails on it); it
// is reported by every call that needs a model, never an abort.
struct Registry {
    std::vector<ModelEntry> entries;
    std::string error;
};

const Registry& registry_state() {
    static const Registry r = [] {
        Registry out;
        read_model_table(kModelsJson, &out.entries, &out.error);
        return out;
    }();
    return r;
}

const std::vector<ModelEntry>& registry() { return registry_state().entries; }

}  // namespace

std::string analytic_models_error() { return registry_state().error; }

std::vector<std::string> analytic_model_names() {
    std::vector<std::string> names;
    for (const ModelEntry& e : registry()) names.push_back(e.name);
    return names;
}

static std::string param_doc(const ParamDef& d) {
    std::string s = std::string(d.doc) + " (" + (d.kind == ParamKind::kColour ? "colour " : "") +
                    format_range(d.lo, d.hi);
    if (!d.default_from.empty())
        s += ", default: " + d.default_from;
    else
        s += ", default " +
             (d.kind == ParamKind::kColour ? format_colour(d.def) : format_number(d.def.x));
    return s + ")";
}

std::string analytic_models_help() {
    std::string s;
    for (const ModelEntry& e : registry()) {
        s += std::string(e.name) + ": " + e.summary + "\n  source: " + e.source + "\n";
        for (const ParamDef& d : e.params)
            s += "  " + std::string(d.name) + ": " + param_doc(d) + "\n";
        for (const std::string& r : e.repeated) s += "  " + r + ": repeatable (syntax above)\n";
    }
    return s;
}

std::unique_ptr<Brdf> make_analytic_brdf(const std::string& spec, std::string* err) {
    std::string model;
    std::vector<SpecItem> items;
    // The model name alone first (bind_spec reads the parameters), so a wrong name is
    // reported as that: "cornell:garnet" names no model, rather than a parameter without '=value'.
    if (!split_spec(spec.substr(0, spec.find(':')), &model, &items, err)) return nullptr;
    if (!analytic_models_error().empty()) {
        if (err) *err = "sepal's model table is broken (a build defect): " + analytic_models_error();
        return nullptr;
    }
    for (const ModelEntry& e : registry()) {
        if (model != e.name) continue;
        ParamSet p;
        if (!bind_spec(spec, e.name, e.params, e.repeated, &p, err)) return nullptr;
        return e.make(e, p, err);
    }
    if (err) {
        std::string names;
        for (const ModelEntry& e : registry())
            names += (names.empty() ? "" : ", ") + std::string(e.name);
        *err = "unknown BRDF model '" + model + "'; models: " + names +
               " (or a measured file: .binary, .brdf)";
    }
    return nullptr;
}

// ---- base class --------------------------------------------------------------------------

// Unit vector with z >= kMinCos, or false for input at/below the horizon or not finite.
static bool prepare(const dvec3& w, dvec3* out) {
    if (!(w.z > 0.0) || !std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
        return false;
    double len = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
    if (!(len > 0.0 && len < 1e150))  // squares over- or underflowed: the slow exact way
        len = std::hypot(std::hypot(w.x, w.y), w.z);
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    dvec3 u = w / len;
    if (u.z < kMinCos) {
        const double s = std::hypot(u.x, u.y);
        if (!(s > 0.0)) return false;
        const double k = std::sqrt(1.0 - kMinCos * kMinCos) / s;
        u = dvec3(u.x * k, u.y * k, kMinCos);
    }
    *out = u;
    return true;
}

dvec3 AnalyticBrdf::eval(const dvec3& wi, const dvec3& wo) const {
    dvec3 a, b;
    if (!prepare(wi, &a) || !prepare(wo, &b)) return dvec3(0.0);
    return eval_above(a, b);
}

std::string AnalyticBrdf::spec() const {
    return std::string(entry_.name) + ":" + format_params(entry_.params, p_) + extra_spec();
}

std::string AnalyticBrdf::model() const { return entry_.name; }

std::string AnalyticBrdf::info() const {
    std::string s = std::string(entry_.summary) + "\nsource: " + entry_.source + "\n";
    for (const ParamDef& d : entry_.params) {
        const std::string v = d.kind == ParamKind::kColour ? format_colour(p_.colour(d.name))
                                                           : format_number(p_.scalar(d.name));
        char line[160];
        std::snprintf(line, sizeof line, "%-6s = %-20s ", d.name.c_str(), v.c_str());
        s += line + param_doc(d) + "\n";
    }
    return s + extra_info();
}

// ---- lambert -----------------------------------------------------------------------------

namespace {

constexpr double kInvPi = 1.0 / kPi;

class Lambert final : public AnalyticBrdf {
  public:
    Lambert(const ModelEntry& e, const ParamSet& p) : AnalyticBrdf(e, p), rho_(colour("rho")) {}
    bool energy_conserving() const override { return max3(rho_) <= 1.0; }

  protected:
    dvec3 eval_above(const dvec3&, const dvec3&) const override { return rho_ * kInvPi; }

  private:
    dvec3 rho_;
};

// cos(angle between wo and the mirror of wi about n); symmetric in wi, wo by construction.
inline double mirror_cos(const dvec3& wi, const dvec3& wo) {
    return wi.z * wo.z - wi.x * wo.x - wi.y * wo.y;
}

// max(0, c)^n with c clamped to 1 against rounding; 0 for c <= 0 (also when n = 0).
inline double lobe_pow(double c, double n) {
    if (!(c > 0.0)) return 0.0;
    return std::pow(std::min(c, 1.0), n);
}

// ---- phong -------------------------------------------------------------------------------

class Phong final : public AnalyticBrdf {
  public:
    Phong(const ModelEntry& e, const ParamSet& p)
        : AnalyticBrdf(e, p), rd_(colour("rho_d")), rs_(colour("rho_s")), n_(scalar("n")) {}
    bool energy_conserving() const override { return max3(rd_ + rs_) <= 1.0; }

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        const double lobe = (n_ + 2.0) / (2.0 * kPi) * lobe_pow(mirror_cos(wi, wo), n_);
        return rd_ * kInvPi + rs_ * lobe;
    }

  private:
    dvec3 rd_, rs_;
    double n_;
};

// ---- blinn -------------------------------------------------------------------------------

// Largest directional albedo of the unit (n+8)/(8 pi) cos^n(theta_h) lobe: 1.0752, at
// normal incidence and n ~ 9 (the normalization is an approximation; the excess falls to
// 0.2% at n = 1000). Measured with directional_albedo over n in 0..1e6 and theta_i in
// 0..89.99 degrees; tests/offline/brdf/brdf_models_test.cpp re-checks it.
constexpr double kBlinnMaxAlbedo = 1.076;

class Blinn final : public AnalyticBrdf {
  public:
    Blinn(const ModelEntry& e, const ParamSet& p)
        : AnalyticBrdf(e, p), rd_(colour("rho_d")), rs_(colour("rho_s")), n_(scalar("n")) {}
    bool energy_conserving() const override { return max3(rd_ + kBlinnMaxAlbedo * rs_) <= 1.0; }

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        const dvec3 h = wi + wo;  // z > 0, never zero
        const double cos_h = h.z / std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
        const double lobe = (n_ + 8.0) / (8.0 * kPi) * lobe_pow(cos_h, n_);
        return rd_ * kInvPi + rs_ * lobe;
    }

  private:
    dvec3 rd_, rs_;
    double n_;
};

// ---- lafortune ---------------------------------------------------------------------------

struct Lobe {
    double cx, cy, cz, n;
    dvec3 w;
};

constexpr int kMaxLobes = 16;
constexpr double kLobeCMax = 100.0, kLobeNMax = 1e6, kLobeWMax = 1000.0;

bool parse_lobe(int index, const std::string& text, Lobe* out, std::string* err) {
    const std::string where = "lafortune: lobe " + std::to_string(index) + " = '" + text + "'";
    std::vector<double> v;
    size_t pos = 0;
    while (true) {
        const size_t slash = text.find('/', pos);
        double x;
        if (!parse_finite(
                text.substr(pos, slash == std::string::npos ? std::string::npos : slash - pos),
                &x)) {
            if (err) *err = where + ": every field must be a finite number";
            return false;
        }
        v.push_back(x);
        if (slash == std::string::npos) break;
        pos = slash + 1;
    }
    if (!(v.size() == 4 || v.size() == 5 || v.size() == 7)) {
        if (err) *err = where + ": expected Cx/Cy/Cz/n, Cx/Cy/Cz/n/w or Cx/Cy/Cz/n/r/g/b";
        return false;
    }
    for (int i = 0; i < 3; ++i)
        if (std::fabs(v[i]) > kLobeCMax) {
            if (err)
                *err = where + ": Cx, Cy, Cz must lie in " + format_range(-kLobeCMax, kLobeCMax);
            return false;
        }
    if (!(v[3] >= 0.0 && v[3] <= kLobeNMax)) {
        if (err) *err = where + ": exponent n must lie in " + format_range(0, kLobeNMax);
        return false;
    }
    for (size_t i = 4; i < v.size(); ++i)
        if (!(v[i] >= 0.0 && v[i] <= kLobeWMax)) {
            if (err) *err = where + ": weight must lie in " + format_range(0, kLobeWMax);
            return false;
        }
    // |Cx x + Cy y + Cz z| <= max|C| for unit vectors, so max|C|^n bounds the lobe.
    const double cmax = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
    if (cmax > 1.0 && v[3] * std::log10(cmax) > 200.0) {
        if (err) *err = where + ": max(|Cx|,|Cy|,|Cz|)^n exceeds 1e200 (overflow)";
        return false;
    }
    out->cx = v[0];
    out->cy = v[1];
    out->cz = v[2];
    out->n = v[3];
    out->w = v.size() == 4 ? dvec3(1.0) : v.size() == 5 ? dvec3(v[4]) : dvec3(v[4], v[5], v[6]);
    return true;
}

class Lafortune final : public AnalyticBrdf {
  public:
    Lafortune(const ModelEntry& e, const ParamSet& p, std::vector<Lobe> lobes)
        : AnalyticBrdf(e, p), rd_(colour("rho_d")), lobes_(std::move(lobes)) {}
    bool isotropic() const override {
        for (const Lobe& l : lobes_)
            if (l.cx != l.cy) return false;
        return true;
    }

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        dvec3 f = rd_ * kInvPi;
        for (const Lobe& l : lobes_) {
            const double c = l.cx * (wi.x * wo.x) + l.cy * (wi.y * wo.y) + l.cz * (wi.z * wo.z);
            if (c > 0.0) f += l.w * std::pow(c, l.n);
        }
        return f;
    }
    std::string extra_spec() const override {
        std::string s;
        for (const Lobe& l : lobes_) s += ",lobe=" + lobe_text(l);
        return s;
    }
    std::string extra_info() const override {
        std::string s;
        for (size_t i = 0; i < lobes_.size(); ++i)
            s += "lobe " + std::to_string(i + 1) + " = " + lobe_text(lobes_[i]) + "\n";
        return s;
    }

  private:
    static std::string lobe_text(const Lobe& l) {
        std::string s = format_number(l.cx) + "/" + format_number(l.cy) + "/" +
                        format_number(l.cz) + "/" + format_number(l.n);
        if (l.w != dvec3(1.0)) s += "/" + format_colour(l.w);
        return s;
    }
    dvec3 rd_;
    std::vector<Lobe> lobes_;
};

// ---- oren-nayar --------------------------------------------------------------------------

class OrenNayar final : public AnalyticBrdf {
  public:
    OrenNayar(const ModelEntry& e, const ParamSet& p) : AnalyticBrdf(e, p), rho_(colour("rho")) {
        const double s2 = scalar("sigma") * scalar("sigma");
        a_ = 1.0 - 0.5 * s2 / (s2 + 0.33);
        b_ = 0.45 * s2 / (s2 + 0.09);
    }
    // The albedo grows with theta_i; at grazing incidence it tends to rho (A + B/2) (the
    // integral of the B term is B/2 there), which can exceed rho for small sigma.
    bool energy_conserving() const override { return max3(rho_) * (a_ + 0.5 * b_) <= 1.0; }

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        // sin(alpha) tan(beta) cos(phi_i - phi_o) = (xy_i . xy_o) / cos(beta), with
        // beta = min(theta_i, theta_o): no angles, no division by a vanishing sine.
        const double t = std::max(0.0, wi.x * wo.x + wi.y * wo.y) / std::max(wi.z, wo.z);
        return rho_ * (kInvPi * (a_ + b_ * t));
    }

  private:
    dvec3 rho_;
    double a_ = 1.0, b_ = 0.0;
};

// ---- hapke-lommel ------------------------------------------------------------------------

class HapkeLommel final : public AnalyticBrdf {
  public:
    HapkeLommel(const ModelEntry& e, const ParamSet& p)
        : AnalyticBrdf(e, p), r_(colour("r")), g_(scalar("g")), f_(scalar("f")) {}

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        // Phase angle alpha between the directions to the light and to the viewer.
        const dvec3 x(wi.y * wo.z - wi.z * wo.y, wi.z * wo.x - wi.x * wo.z,
                      wi.x * wo.y - wi.y * wo.x);
        const double sin_a = std::sqrt(x.x * x.x + x.y * x.y + x.z * x.z);
        const double cos_a = std::clamp(wi.x * wo.x + wi.y * wo.y + wi.z * wo.z, -1.0, 1.0);
        // Lambert-sphere phase function plus Hapke's forward-scattering term.
        const double phase = lambert_sphere(sin_a, cos_a) + f_ * (1.0 - cos_a) * (1.0 - cos_a);
        const double s = 2.0 / (3.0 * kPi) * phase;
        return r_ * (s * retro(sin_a, cos_a) / (wi.z + wo.z));
    }

  private:
    // (sin a + (pi - a) cos a) / pi. Near a = pi (grazing forward scattering) the two terms
    // cancel to (pi - a)^3 / 3: there, with d = pi - a, sin d - d cos d by its series.
    static double lambert_sphere(double sin_a, double cos_a) {
        const double d = std::atan2(sin_a, -cos_a);  // pi - a, accurate when small
        if (d > 0.1) return (sin_a + d * cos_a) / kPi;
        const double d2 = d * d;
        return d * d2 * (1.0 / 3.0 - d2 * (1.0 / 30.0 - d2 * (1.0 / 840.0 - d2 / 45360.0))) / kPi;
    }
    // Hapke's retrodirective function B(alpha, g): 2 at alpha = 0, falling to 1 at 90
    // degrees and beyond. With x = g / tan(alpha):
    //   B = 2 - (1 - e^-x)(3 - e^-x) / (2x).
    double retro(double sin_a, double cos_a) const {
        if (cos_a <= 0.0 || g_ <= 0.0) return 1.0;
        if (sin_a <= 0.0) return 2.0;
        const double x = g_ * cos_a / sin_a;
        const double e = std::exp(-x);
        return 2.0 - (-std::expm1(-x)) * (3.0 - e) / (2.0 * x);
    }
    dvec3 r_;
    double g_, f_;
};

// ---- factories ---------------------------------------------------------------------------

std::unique_ptr<Brdf> make_lafortune(const ModelEntry& e, const ParamSet& p, std::string* err) {
    std::vector<std::string> texts = p.repeated("lobe");
    if (texts.empty()) texts = {"-1/-1/1/20/0.5"};  // the documented default lobe
    if (texts.size() > size_t(kMaxLobes)) {
        if (err) *err = "lafortune: at most " + std::to_string(kMaxLobes) + " lobes";
        return nullptr;
    }
    std::vector<Lobe> lobes(texts.size());
    for (size_t i = 0; i < texts.size(); ++i)
        if (!parse_lobe(int(i) + 1, texts[i], &lobes[i], err)) return nullptr;
    return std::make_unique<Lafortune>(e, p, std::move(lobes));
}

}  // namespace

const ModelCode kSimpleModels[6] = {
    {"lambert", make_model<Lambert>},
    {"phong", make_model<Phong>},
    {"blinn", make_model<Blinn>},
    {"lafortune", make_lafortune},
    {"oren-nayar", make_model<OrenNayar>},
    {"hapke-lommel", make_model<HapkeLommel>},
};

}  // namespace sepal
