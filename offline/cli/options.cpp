#include "cli/options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <ostream>
#include <vector>

namespace sepal {
namespace {

// Every enumerator a user may name; a new one (a new factor method) joins here and in its
// *_name()/parse_*() pair.
const Param kParams[] = {Param::GsHalf, Param::IncidentView, Param::ViewHalf, Param::Rusinkiewicz, Param::ElevAzim, Param::Axis, Param::GsMirror};
const HemiMap kMaps[] = {HemiMap::XY, HemiMap::Parabolic};
const Method kMethods[] = {Method::SVD, Method::WSVD, Method::ND, Method::NMF, Method::ACLS, Method::Homomorphic};
const ColourMode kColours[] = {ColourMode::PerChannel, ColourMode::Luminance};
const Target kTargets[] = {Target::Gles1, Target::Gles2, Target::Cpu};

// CLI11 converts an enum from its integer, so the check also rewrites the name into it.
template <typename T, size_t N>
CLI::Validator names(const T (&values)[N], const char* (*name)(T)) {
    std::string list;
    for (T x : values) list += std::string(list.empty() ? "" : ",") + name(x);
    return CLI::Validator(
        [&values, name, list](std::string& s) -> std::string {
            for (T x : values)
                if (s == name(x)) {
                    s = std::to_string(int(x));
                    return "";
                }
            return "'" + s + "' is not one of " + list;
        },
        "{" + list + "}");
}

}  // namespace

std::ostream& operator<<(std::ostream& out, Param p) { return out << param_name(p); }
std::ostream& operator<<(std::ostream& out, HemiMap m) { return out << map_name(m); }
std::ostream& operator<<(std::ostream& out, Method m) { return out << method_name(m); }
std::ostream& operator<<(std::ostream& out, ColourMode c) { return out << colour_name(c); }
std::ostream& operator<<(std::ostream& out, Target t) { return out << target_name(t); }

CLI::Validator param_names() { return names(kParams, param_name); }
CLI::Validator map_names() { return names(kMaps, map_name); }
CLI::Validator method_names() { return names(kMethods, method_name); }
CLI::Validator colour_names() { return names(kColours, colour_name); }
CLI::Validator target_names() { return names(kTargets, target_name); }

CLI::Validator finite_range(double lo, double hi) {
    const std::string range = "[" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
    return CLI::Validator(
        [lo, hi, range](std::string& s) -> std::string {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || *end || errno == ERANGE || !std::isfinite(v)) return "'" + s + "' is not a finite number";
            if (v < lo || v > hi) return s + " is outside " + range;
            return "";
        },
        "in " + range);
}

CLI::Validator positive() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || *end || errno == ERANGE || !std::isfinite(v)) return "'" + s + "' is not a finite number";
            return v > 0 ? "" : s + " is not > 0";
        },
        "> 0");
}

}  // namespace sepal
