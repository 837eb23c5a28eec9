#include "measured.h"

namespace sepal {
std::unique_ptr<Brdf> load_measured_brdf(const std::string& path, std::string* err) {
    if (err) *err = "measured data is not implemented yet: '" + path + "'";
    return nullptr;
}
}  // namespace sepal
