// `bake --timings`' cost model file (bake/cost_model.h, parse_cost_model) through the
// project's JSON reader: an accepted model has finite, non-negative coefficients in range,
// predicts a finite time, and a refusal names the file.
#include <cmath>
#include <string>

#include "bake/cost_model.h"
#include "fuzz/fuzz.h"

extern "C" int sepal_fuzz_cost_model(const uint8_t* data, size_t size) {
    const char* h = "cost_model";
    const std::string text(reinterpret_cast<const char*>(data), size);
    for (const char* backend : {"gles1", "cpu"}) {
        sepal::CostModel m;
        std::string err;
        if (!sepal::parse_cost_model(text, "t.json", backend, &m, &err)) {
            sepal_fuzz::check(err.compare(0, 6, "t.json") == 0, h, "a refusal that does not name the file");
            continue;
        }
        for (double v : {m.base_ms, m.per_pass_ms, m.per_term_ms, m.per_kib_ms, m.fit_error})
            sepal_fuzz::check(v >= 0 && v <= 1e9, h, "a coefficient out of range");
        sepal_fuzz::check(m.rows >= 0 && m.width >= 0 && m.width <= 16384 && m.height >= 0 && m.height <= 16384, h,
                          "rows or size out of range");
        sepal_fuzz::check(std::isfinite(m.predict(256, 16, int64_t(64) << 20)), h, "a non-finite prediction");
    }
    return 0;
}
