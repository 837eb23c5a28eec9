// The measurement harnesses' seeds (fixtures/fuzz-seeds/plan, samples) are files the readers
// accept against the harnesses' own database (fuzz.h), so libFuzzer starts from inputs that
// reach every check. SEPAL_WRITE_FUZZ_SEEDS=1 rewrites them (after a change to that database).
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "database/database.h"
#include "database/measure.h"
#include "database/measure_plan.h"
#include "fuzz/fuzz.h"
#include "test_util.h"
#include "util/io.h"

TEST_CASE("fuzz seeds: the plan and samples seeds are accepted by the harnesses' readers") {
    const sepal::BrdfDatabase& db = sepal_fuzz::database();
    const sepal::MeasurementPlan& plan = sepal_fuzz::samples_plan();
    const std::string plan_seed = sepal_test::source_path("fixtures/fuzz-seeds/plan/uniform40.json");
    const std::string samples_seed = sepal_test::source_path("fixtures/fuzz-seeds/samples/uniform40.csv");
    std::string err;
    const char* write = std::getenv("SEPAL_WRITE_FUZZ_SEEDS");
    if (write && std::string(write) == "1") {
        REQUIRE(sepal::make_dirs(sepal_test::source_path("fixtures/fuzz-seeds/plan"), &err));
        REQUIRE(sepal::make_dirs(sepal_test::source_path("fixtures/fuzz-seeds/samples"), &err));
        REQUIRE_MESSAGE(sepal::write_plan_json(plan_seed, db, plan, &err), err);
        std::vector<double> v(plan.rows.size());
        for (size_t i = 0; i < v.size(); ++i) v[i] = db.value(int(i % size_t(db.size())), plan.rows[i]);
        REQUIRE_MESSAGE(sepal::write_samples_csv(samples_seed, db, plan, v, "fuzz seed: database values", &err), err);
    }
    sepal::MeasurementPlan back;
    REQUIRE_MESSAGE(sepal::read_plan_json(plan_seed, db, &back, &err), err);
    CHECK(back.rows == plan.rows);
    std::vector<double> values;
    REQUIRE_MESSAGE(sepal::read_samples_csv(samples_seed, db, plan, &values, &err), err);
    CHECK(values.size() == plan.rows.size());
}
