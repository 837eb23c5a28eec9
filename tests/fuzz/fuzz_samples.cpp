// Sample CSVs of a measurement (database/measure.h: read_samples_csv) against the harnesses'
// 40-sample plan (fuzz.h), then the reconstruction from them. Accepted samples are one finite
// value within +-kMaxSampleValue per plan row; a reconstruction either refuses with a message
// or gives finite values >= 0 in every cell.
#include <cmath>
#include <string>
#include <vector>

#include "database/database.h"
#include "database/measure.h"
#include "fuzz/fuzz.h"

extern "C" int sepal_fuzz_samples(const uint8_t* data, size_t size) {
    const char* h = "samples";
    const sepal::BrdfDatabase& db = sepal_fuzz::database();
    const sepal::MeasurementPlan& plan = sepal_fuzz::samples_plan();
    const std::string path = sepal_fuzz::write_scratch("samples.csv", data, size);
    std::vector<double> v;
    std::string err;
    if (!sepal::read_samples_csv(path, db, plan, &v, &err)) {
        sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(v.size() == plan.rows.size(), h, "not one value per plan sample");
    for (double x : v) sepal_fuzz::check(std::isfinite(x) && std::fabs(x) <= sepal::kMaxSampleValue, h, "a value out of range");
    sepal::DatabaseReconstruction r;
    if (!sepal::reconstruct(db, plan, v, {}, sepal::FitOptions{}, &r, &err)) {
        sepal_fuzz::check(!err.empty(), h, "a reconstruction refused without a message");
        return 0;
    }
    for (float x : r.values) sepal_fuzz::check(std::isfinite(x) && x >= 0, h, "a reconstructed value not finite or < 0");
    return 0;
}
