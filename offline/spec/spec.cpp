#include "spec/spec.h"

#include "brdf/brdf_models.h"
#include "measured/measured.h"
#include "measured/nbrdf.h"
#include "util/io.h"

namespace sepal {

std::unique_ptr<Brdf> make_brdf(const std::string& spec, std::string* err) {
    if (spec.compare(0, 6, "nbrdf:") == 0) return make_nbrdf_brdf(spec, err);
    // A spec with a file extension of measured data is a path; anything else is a model.
    const std::string ext = file_extension(spec);
    if (spec.find(':') == std::string::npos && (ext == "binary" || ext == "brdf"))
        return load_measured_brdf(spec, err);
    return make_analytic_brdf(spec, err);
}

}  // namespace sepal
