#include "brdf_models.h"

namespace sepal {
std::unique_ptr<Brdf> make_analytic_brdf(const std::string& spec, std::string* err) {
    if (err) *err = "analytic models are not implemented yet: '" + spec + "'";
    return nullptr;
}
}  // namespace sepal
