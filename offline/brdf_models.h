// Analytic BRDF models (stub: the BRDF-sources work fills this in).
#pragma once
#include "brdf.h"

namespace sepal {
std::unique_ptr<Brdf> make_analytic_brdf(const std::string& spec, std::string* err);
}  // namespace sepal
