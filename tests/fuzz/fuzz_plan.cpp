// Measurement plans (database/measure_plan.h: read_plan_json) against the harnesses' coarse
// database (fuzz.h). An accepted plan holds 1..100000 rows, each a valid cell's channel of that
// database, at least as many as the materials it fits, and excludes only materials it has.
#include <string>

#include "database/database.h"
#include "database/measure_plan.h"
#include "fuzz/fuzz.h"

extern "C" int sepal_fuzz_plan(const uint8_t* data, size_t size) {
    const char* h = "plan";
    const sepal::BrdfDatabase& db = sepal_fuzz::database();
    const std::string path = sepal_fuzz::write_scratch("plan.json", data, size);
    sepal::MeasurementPlan p;
    std::string err;
    if (!sepal::read_plan_json(path, db, &p, &err)) {
        sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(!p.rows.empty() && p.rows.size() <= 100000, h, "a plan of 0 or over 100000 samples");
    for (size_t r : p.rows) sepal_fuzz::check(r < db.rows(), h, "a row outside the database");
    for (const std::string& n : p.excluded) sepal_fuzz::check(db.find(n) >= 0, h, "an unknown excluded material");
    sepal_fuzz::check(p.excluded.size() < size_t(db.size()), h, "every material excluded");
    sepal_fuzz::check(p.rows.size() >= size_t(db.size()) - p.excluded.size(), h,
                      "fewer samples than the materials the plan fits");
    return 0;
}
