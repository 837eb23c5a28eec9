// Measured BRDF data (stub: the BRDF-sources work fills this in).
#pragma once
#include "brdf.h"

namespace sepal {
std::unique_ptr<Brdf> load_measured_brdf(const std::string& path, std::string* err);
}  // namespace sepal
