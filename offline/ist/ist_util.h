// Small helpers shared by the inverse-shade-tree sources (not a public interface).
#pragma once
#include <string>

#include <glm/vec3.hpp>

#include "util/json.h"

namespace sepal {
namespace ist_detail {

inline bool fail(std::string* err, const std::string& msg) {
    if (err) *err = msg;
    return false;
}

inline bool json_vec3(const JsonField& f, const char* key, glm::dvec3* out, std::string* err) {
    double v[3];
    if (!json_numbers(f, key, 3, v, err, true)) return false;
    *out = glm::dvec3(v[0], v[1], v[2]);
    return true;
}

}  // namespace ist_detail
}  // namespace sepal
