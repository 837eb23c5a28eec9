// BRDF spec strings (brdf/brdf.h, make_brdf: "model:key=value,...", "nbrdf:NAME"; file paths
// are left out, the file readers have their own harnesses). An accepted spec gives a BRDF
// whose canonical spec() parses back, and finite values >= 0 at a few direction pairs.
#include <cmath>
#include <memory>
#include <string>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "fuzz/fuzz.h"
#include "util/io.h"

extern "C" int sepal_fuzz_spec(const uint8_t* data, size_t size) {
    const char* h = "spec";
    const std::string spec(reinterpret_cast<const char*>(data), size);
    const std::string ext = sepal::file_extension(spec);
    if (spec.find(':') == std::string::npos && (ext == "binary" || ext == "brdf")) return 0;
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, &err);
    if (!f) {
        sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
        return 0;
    }
    std::unique_ptr<sepal::Brdf> again = sepal::make_brdf(f->spec(), &err);
    sepal_fuzz::check(again && again->spec() == f->spec(), h, "the canonical spec does not parse back to itself");
    const glm::dvec3 dirs[] = {{0, 0, 1}, {0.6, 0, 0.8}, {-0.6, 0, 0.8}, {0, 0.99498743710662, 0.1}, {0.8, 0.36, 0.48}};
    for (const glm::dvec3& wi : dirs)
        for (const glm::dvec3& wo : dirs) {
            const glm::dvec3 v = f->eval(wi, wo);
            for (int c = 0; c < 3; ++c) sepal_fuzz::check(std::isfinite(v[c]) && v[c] >= 0, h, "f not finite or < 0");
        }
    return 0;
}
