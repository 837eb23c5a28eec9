// Small helpers shared by the inverse-shade-tree sources (not a public interface).
#pragma once
#include <string>

namespace sepal {
namespace ist_detail {

inline bool fail(std::string* err, const std::string& msg) {
    if (err) *err = msg;
    return false;
}

}  // namespace ist_detail
}  // namespace sepal
