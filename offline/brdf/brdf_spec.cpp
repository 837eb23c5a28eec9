#include "brdf/brdf_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>

namespace sepal {

static std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return "";
    const size_t b = s.find_last_not_of(" \t");
    return s.substr(a, b - a + 1);
}

static bool is_identifier(const std::string& s) {
    if (s.empty()) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
    return true;
}

bool split_spec(const std::string& spec, std::string* model, std::vector<SpecItem>* items,
                std::string* err) {
    items->clear();
    const size_t colon = spec.find(':');
    *model = trim(spec.substr(0, colon));
    if (model->empty()) {
        if (err) *err = "empty BRDF spec: expected 'model' or 'model:key=value,...'";
        return false;
    }
    if (!is_identifier(*model)) {
        if (err) *err = "bad BRDF model name '" + *model + "' in spec '" + spec + "'";
        return false;
    }
    if (colon == std::string::npos) return true;
    const std::string rest = spec.substr(colon + 1);
    size_t pos = 0;
    while (true) {
        const size_t comma = rest.find(',', pos);
        const std::string item =
            trim(rest.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos));
        if (item.empty()) {
            if (err)
                *err = *model + ": empty parameter in '" + spec +
                       "' (expected key=value separated by commas)";
            return false;
        }
        const size_t eq = item.find('=');
        if (eq == std::string::npos) {
            if (err) *err = *model + ": parameter '" + item + "' has no '=value'";
            return false;
        }
        SpecItem si{trim(item.substr(0, eq)), trim(item.substr(eq + 1))};
        if (!is_identifier(si.key)) {
            if (err) *err = *model + ": bad parameter name '" + si.key + "'";
            return false;
        }
        if (si.value.empty()) {
            if (err) *err = *model + ": parameter '" + si.key + "' has an empty value";
            return false;
        }
        items->push_back(si);
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    return true;
}

bool parse_finite(const std::string& s_in, double* v) {
    std::string s = s_in;
    // from_chars takes no '+'; accept one, but not "+-1".
    if (!s.empty() && s[0] == '+') {
        s.erase(0, 1);
        if (s.empty() || s[0] == '+' || s[0] == '-') return false;
    }
    if (s.empty()) return false;
    double x = 0.0;
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, x);
    if (r.ec != std::errc() || r.ptr != end || !std::isfinite(x)) return false;
    *v = x;
    return true;
}

std::string format_number(double v) {
    if (v == 0.0) return "0";  // no "-0"
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string format_colour(const glm::dvec3& c) {
    if (c.x == c.y && c.y == c.z) return format_number(c.x);
    return format_number(c.x) + "/" + format_number(c.y) + "/" + format_number(c.z);
}

std::string format_range(double lo, double hi) {
    return "[" + format_number(lo) + ", " + format_number(hi) + "]";
}

const std::vector<std::string>& ParamSet::repeated(const std::string& key) const {
    static const std::vector<std::string> none;
    auto it = rep_.find(key);
    return it == rep_.end() ? none : it->second;
}

// One value of a parameter: a scalar, or for a colour a scalar or r/g/b.
static bool parse_value(const std::string& model, const ParamDef& d, const std::string& text,
                        glm::dvec3* out, std::string* err) {
    const std::string where = model + ": parameter '" + d.name + "' = '" + text + "'";
    const std::string range = format_range(d.lo, d.hi);
    std::vector<std::string> parts;
    size_t pos = 0;
    while (true) {
        const size_t slash = text.find('/', pos);
        parts.push_back(
            trim(text.substr(pos, slash == std::string::npos ? std::string::npos : slash - pos)));
        if (slash == std::string::npos) break;
        pos = slash + 1;
    }
    const bool colour = d.kind == ParamKind::kColour;
    if (!(parts.size() == 1 || (colour && parts.size() == 3))) {
        if (err)
            *err = where + ": expected " +
                   (colour ? std::string("a number or r/g/b") : std::string("a number")) + " in " +
                   range;
        return false;
    }
    double v[3];
    for (size_t i = 0; i < parts.size(); ++i) {
        if (!parse_finite(parts[i], &v[i])) {
            if (err) *err = where + " is not a finite number; accepted range " + range;
            return false;
        }
        if (!(v[i] >= d.lo && v[i] <= d.hi)) {
            if (err) *err = where + " is out of range; accepted range " + range;
            return false;
        }
    }
    *out = parts.size() == 1 ? glm::dvec3(v[0]) : glm::dvec3(v[0], v[1], v[2]);
    return true;
}

static std::string names_of(const std::vector<ParamDef>& defs,
                            const std::vector<std::string>& repeated) {
    std::string s;
    for (const ParamDef& d : defs) s += (s.empty() ? "" : ", ") + std::string(d.name);
    for (const std::string& r : repeated) s += (s.empty() ? "" : ", ") + r;
    return s.empty() ? "none" : s;
}

bool bind_spec(const std::string& spec, const std::string& model, const std::vector<ParamDef>& defs,
               const std::vector<std::string>& repeated, ParamSet* out, std::string* err) {
    std::string name;
    std::vector<SpecItem> items;
    if (!split_spec(spec, &name, &items, err)) return false;
    if (name != model) {
        if (err) *err = "spec '" + spec + "' is not a '" + model + "' spec";
        return false;
    }
    *out = ParamSet();
    std::set<std::string> seen;
    for (const SpecItem& it : items) {
        if (std::find(repeated.begin(), repeated.end(), it.key) != repeated.end()) {
            out->add_repeated(it.key, it.value);
            continue;
        }
        auto d = std::find_if(defs.begin(), defs.end(),
                              [&](const ParamDef& p) { return it.key == p.name; });
        if (d == defs.end()) {
            if (err)
                *err = model + ": unknown parameter '" + it.key +
                       "'; parameters: " + names_of(defs, repeated);
            return false;
        }
        if (!seen.insert(it.key).second) {
            if (err) *err = model + ": parameter '" + it.key + "' is given twice";
            return false;
        }
        glm::dvec3 v;
        if (!parse_value(model, *d, it.value, &v, err)) return false;
        out->set(d->name, v);
    }
    // Defaults, then the ones that follow another parameter.
    for (const ParamDef& d : defs)
        if (!seen.count(d.name) && d.default_from.empty()) out->set(d.name, d.def);
    for (const ParamDef& d : defs)
        if (!seen.count(d.name) && !d.default_from.empty()) out->set(d.name, out->colour(d.default_from));
    return true;
}

std::string format_params(const std::vector<ParamDef>& defs, const ParamSet& p) {
    std::string s;
    for (const ParamDef& d : defs) {
        if (!s.empty()) s += ",";
        s += d.name;
        s += "=";
        s += d.kind == ParamKind::kColour ? format_colour(p.colour(d.name))
                                          : format_number(p.scalar(d.name));
    }
    return s;
}

}  // namespace sepal
