// Spec strings of analytic BRDF models: "model" or "model:key=value,key=value,...".
//
// Usage (brdf_models.cpp does this for every model of brdf/models.json):
//   static const std::vector<sepal::ParamDef> defs = {
//       {"rho", sepal::ParamKind::kColour, glm::dvec3(0.5), 0.0, 1.0, "diffuse albedo", ""}};
//   sepal::ParamSet p;
//   if (!sepal::bind_spec(spec, "lambert", defs, {}, &p, &err)) return nullptr;
//   glm::dvec3 rho = p.colour("rho");
//
// Syntax: keys are identifiers; a value is a number (C locale: "0.5", "1e-3", "-2") or,
// for a colour parameter, a scalar (grey) or "r/g/b". A "repeated" key (Lafortune's lobe)
// may occur several times; its raw values are handed to the model in order. Errors name the
// key and the accepted range: unknown key, duplicate key, malformed number, NaN or inf, out
// of range, empty item. No exceptions; nothing is locale dependent.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

struct SpecItem {
    std::string key, value;
};

// Splits "model:key=value,..." into the model name and its items (order kept). Only the
// syntax is checked here. Spaces around names and values are ignored.
bool split_spec(const std::string& spec, std::string* model, std::vector<SpecItem>* items,
                std::string* err);

// Strict finite number: the whole string must parse; NaN, inf and overflow are refused.
bool parse_finite(const std::string& s, double* v);
// Shortest decimal that parses back to exactly v ("0.1", "1e-05", "20").
std::string format_number(double v);
// "v" when r == g == b, else "r/g/b".
std::string format_colour(const glm::dvec3& c);

enum class ParamKind { kScalar, kColour };

struct ParamDef {
    std::string name;
    ParamKind kind = ParamKind::kScalar;
    glm::dvec3 def{0.0};  // default (a scalar's is def.x)
    double lo = 0.0, hi = 0.0;  // accepted closed range, for each channel of a colour
    std::string doc;
    // When not empty, an absent parameter takes this other (colour) parameter's value, e.g.
    // Cook-Torrance's F0 defaults to its Rd.
    std::string default_from;
};

class ParamSet {
  public:
    double scalar(const std::string& name) const { return values_.at(name).x; }
    glm::dvec3 colour(const std::string& name) const { return values_.at(name); }
    void set(const std::string& name, const glm::dvec3& v) { values_[name] = v; }
    // Raw values of a repeated key, in spec order.
    const std::vector<std::string>& repeated(const std::string& key) const;
    void add_repeated(const std::string& key, const std::string& v) { rep_[key].push_back(v); }

  private:
    std::map<std::string, glm::dvec3> values_;
    std::map<std::string, std::vector<std::string>> rep_;
};

// Parses, validates against defs and fills *out (defaults for absent keys). `model` must
// equal the spec's model name (it prefixes the messages). `repeated` lists keys that may
// occur several times; their values are stored raw for the model to parse.
bool bind_spec(const std::string& spec, const std::string& model, const std::vector<ParamDef>& defs,
               const std::vector<std::string>& repeated, ParamSet* out, std::string* err);

// Range text for messages: "[0, 1]".
std::string format_range(double lo, double hi);

// "name=value,..." of defs in order (colours via format_colour); no model prefix.
std::string format_params(const std::vector<ParamDef>& defs, const ParamSet& p);

}  // namespace sepal
