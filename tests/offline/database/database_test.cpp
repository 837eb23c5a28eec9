// The BRDF database (database/database.h), its linear models (linear_model.h), measurement
// planning (measure_plan.h) and reconstruction (measure.h).
//
// Fast by construction: a coarse 16 x 16 x 32 grid and 12 materials (built once per run in a
// temporary folder, ~0.1 s); one test builds 3 materials on the MERL grid to check the .binary
// written by the reconstruction against merl.cpp's reader. The full leave-one-out over the 100
// materials lives in the bench (tests/bench/database.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <thread>

#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Core>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "database/database.h"
#include "database/linear_model.h"
#include "database/measure.h"
#include "database/measure_plan.h"
#include "database/plan_picture.h"
#include "measured/merl.h"
#include "util/io.h"
#include "util/parallel.h"
#include "test_util.h"

namespace {

const std::vector<std::string> kMaterials = {
    "gold-paint",   "dark-red-paint", "alum-bronze", "specular-orange-phenolic",
    "white-fabric", "blue-acrylic",   "nickel",      "pink-felt",
    "red-plastic",  "silver-paint",   "black-phenolic", "yellow-matte-plastic"};

std::shared_ptr<const sepal::NbrdfSet> nbrdf() {
    std::string err;
    auto s = sepal::load_nbrdf_set(sepal_test::source_path("data/merl-nbrdf/merl-nbrdf.json"), &err);
    REQUIRE_MESSAGE(bool(s), err);
    return s;
}

sepal::DatabaseOptions coarse_options(const std::string& dir) {
    sepal::DatabaseOptions o;
    o.grid.n_theta_h = 16;
    o.grid.n_theta_d = 16;
    o.grid.n_phi_d = 32;
    o.materials = kMaterials;
    o.cache_dir = dir;
    return o;
}

// The coarse database shared by the tests of this file.
const sepal::BrdfDatabase& coarse() {
    static std::unique_ptr<sepal::BrdfDatabase> db;
    if (!db) {
        std::string err;
        db = sepal::BrdfDatabase::open(*nbrdf(), coarse_options(sepal_test::temp_dir()), &err);
        REQUIRE_MESSAGE(bool(db), err);
    }
    return *db;
}

// The paper's plans (linear model, condition number) unless `log`: the log model's default.
sepal::MeasurementPlan make_plan(const sepal::BrdfDatabase& db, sepal::PlanMethod m, int n,
                                 const std::vector<uint8_t>& use, uint64_t seed = 1, bool log = false) {
    sepal::PlanOptions o;
    if (!log) {
        o.space = sepal::FitSpace::kLinear;
        o.objective = sepal::PlanObjective::kCondition;
    }
    o.samples = n;
    o.method = m;
    o.use = use;
    o.seed = seed;
    sepal::MeasurementPlan p;
    std::string err;
    REQUIRE_MESSAGE(sepal::plan_measurement(db, o, &p, &err), err);
    return p;
}

// 3 materials on the MERL grid (~2 s to build once; cached in build/cache afterwards).
std::unique_ptr<sepal::BrdfDatabase> merl_grid_db() {
    sepal::DatabaseOptions o;
    o.materials = {"gold-paint", "dark-red-paint", "white-fabric"};
    std::string err;
    auto db = sepal::BrdfDatabase::open(*nbrdf(), o, &err);
    REQUIRE_MESSAGE(bool(db), err);
    return db;
}

// The paper's linear model (combination_error_gram measures its coefficients exactly).
sepal::FitOptions linear_fit() {
    sepal::FitOptions fo;
    fo.space = sepal::FitSpace::kLinear;
    return fo;
}

// Leave-one-out relative RMS of material k from a plan of n samples (noise: multiplicative).
double loo_error(const sepal::BrdfDatabase& db, int k, sepal::PlanMethod m, int n, double noise,
                 uint64_t seed = 1) {
    std::string err;
    std::vector<uint8_t> use;
    REQUIRE(sepal::exclude_mask(db, {db.name(k)}, &use, &err));
    const sepal::MeasurementPlan p = make_plan(db, m, n, use, seed);
    auto f = sepal::make_brdf("nbrdf:" + db.name(k), &err);
    REQUIRE(bool(f));
    std::vector<double> v;
    REQUIRE(sepal::simulate_samples(db, p, *f, noise, seed, &v, &err));
    sepal::CombinationFit fit;
    REQUIRE_MESSAGE(sepal::fit_combination(db, p.rows, v, use, linear_fit(), &fit, &err), err);
    return sepal::combination_error_gram(db, fit.coeffs, k);
}

}  // namespace

TEST_CASE("database: the table holds the nbrdf values at bin centres; Gram matrices match") {
    const sepal::BrdfDatabase& db = coarse();
    CHECK(db.size() == 12);
    CHECK(db.name(0) == "gold-paint");
    CHECK(db.valid_cells() > 4000);
    CHECK(db.valid_cells() < db.grid().cells());
    auto set = nbrdf();
    for (size_t v = 0; v < db.valid_cells(); v += 97) {
        glm::dvec3 wi, wo;
        sepal::from_half_diff(db.cell_center(db.grid_cell(v)), &wi, &wo);
        REQUIRE(wi.z > 0.0);
        REQUIRE(wo.z > 0.0);
        CHECK(db.valid_index(db.grid_cell(v)) == int64_t(v));
        for (int k = 0; k < db.size(); ++k) {
            const glm::dvec3 f = set->materials()[size_t(set->find(db.name(k)))].eval(wi, wo);
            for (int c = 0; c < 3; ++c) CHECK(db.value(k, 3 * v + size_t(c)) == float(f[c]));
        }
    }
    // Gram matrices against a direct sum over the table.
    const int K = db.size();
    for (int a = 0; a < K; a += 5)
        for (int b = 0; b < K; b += 3) {
            double g = 0.0, gl = 0.0;
            for (size_t r = 0; r < db.rows(); ++r) {
                g += double(db.value(a, r)) * db.value(b, r);
                gl += std::log(double(db.value(a, r)) + sepal::kDatabaseLogEps) *
                      std::log(double(db.value(b, r)) + sepal::kDatabaseLogEps);
            }
            CHECK(db.gram()[a * K + b] == doctest::Approx(g).epsilon(1e-9));
            CHECK(db.gram()[b * K + a] == db.gram()[a * K + b]);
            CHECK(db.gram_log()[a * K + b] == doctest::Approx(gl).epsilon(1e-9));
        }
    std::string err;
    CHECK_MESSAGE(db.verify_table(&err), err);
}

TEST_CASE("database: the cache is deterministic, reused, and rebuilt when corrupt") {
    const std::string d1 = sepal_test::temp_dir(), d2 = sepal_test::temp_dir();
    std::string err;
    sepal::DatabaseOptions o1 = coarse_options(d1), o2 = coarse_options(d2);
    o1.threads = 1;
    o2.threads = 2;
    o1.materials.resize(5);
    o2.materials.resize(5);
    std::string path;
    {
        auto a = sepal::BrdfDatabase::open(*nbrdf(), o1, &err);
        auto b = sepal::BrdfDatabase::open(*nbrdf(), o2, &err);
        REQUIRE(bool(a));
        REQUIRE(bool(b));
        CHECK(a->built_now());
        std::vector<uint8_t> ba, bb;
        REQUIRE(sepal::read_file(a->cache_path(), &ba, &err));
        REQUIRE(sepal::read_file(b->cache_path(), &bb, &err));
        CHECK(ba == bb);  // thread count does not change a byte
        path = a->cache_path();
    }
    {
        auto again = sepal::BrdfDatabase::open(*nbrdf(), o1, &err);
        REQUIRE(bool(again));
        CHECK(!again->built_now());
    }
    {
        // Corrupt one Gram entry: the header checksum catches it and the cache is rebuilt.
        std::vector<uint8_t> bytes;
        REQUIRE(sepal::read_file(path, &bytes, &err));
        bytes[400] ^= 0x40;
        REQUIRE(sepal::write_file_atomic(path, bytes.data(), bytes.size(), &err));
        auto rebuilt = sepal::BrdfDatabase::open(*nbrdf(), o1, &err);
        REQUIRE(bool(rebuilt));
        CHECK(rebuilt->built_now());
    }
    sepal::DatabaseOptions bad = o1;
    bad.materials = {"gold-paint", "no-such-paint"};
    CHECK(!sepal::BrdfDatabase::open(*nbrdf(), bad, &err));
    CHECK(err.find("no-such-paint") != std::string::npos);
    bad.materials = {"gold-paint", "gold-paint"};
    CHECK(!sepal::BrdfDatabase::open(*nbrdf(), bad, &err));
    CHECK(err.find("twice") != std::string::npos);
    bad = o1;
    bad.grid.n_phi_d = 0;
    CHECK(!sepal::BrdfDatabase::open(*nbrdf(), bad, &err));
}

TEST_CASE("linear model: PCA errors fall with the dimension; leave-one-out is harder") {
    const sepal::BrdfDatabase& db = coarse();
    const int K = db.size();
    const std::vector<double> var = sepal::pca_variances(db.gram(), K);
    for (size_t i = 1; i < var.size(); ++i) CHECK(var[i] <= var[i - 1] * (1 + 1e-12));
    for (const double* G : {db.gram(), db.gram_log()}) {
        for (int k = 0; k < K; ++k) {
            const std::vector<double> in = sepal::pca_projection_errors(G, K, k, false, K, nullptr);
            const std::vector<double> out = sepal::pca_projection_errors(G, K, k, true, K, nullptr);
            REQUIRE(in.size() >= 5);
            for (size_t d = 1; d < in.size(); ++d) CHECK(in[d] <= in[d - 1] * (1 + 1e-9) + 1e-12);
            // All K-1 components: every material is exactly in the span.
            CHECK(in.back() <= 1e-6 * G[k * K + k]);
            // Leave-one-out at the same dimension never explains more.
            for (size_t d = 0; d < std::min(in.size(), out.size()); ++d)
                CHECK(out[d] >= in[d] * (1 - 1e-6) - 1e-9 * G[k * K + k]);
        }
    }
}

TEST_CASE("linear model: Gram-matrix error equals the full-grid error; exact recovery in the span") {
    const sepal::BrdfDatabase& db = coarse();
    const int K = db.size();
    std::vector<double> c(size_t(K), 0.0);
    c[1] = 0.7;
    c[4] = 0.2;
    c[7] = 0.1;
    const std::vector<float> approx = sepal::combination_values(db, c);
    const std::vector<float> truth(db.column(1), db.column(1) + db.rows());
    CHECK(sepal::combination_error_gram(db, c, 1) ==
          doctest::Approx(sepal::relative_rms(approx, truth)).epsilon(1e-4));

    // A new material that is a mix of database materials is recovered from a plan of it.
    std::vector<double> mix(size_t(K), 0.0);
    mix[0] = 0.5;
    mix[3] = 0.3;
    mix[9] = 0.2;
    const sepal::MeasurementPlan p = make_plan(db, sepal::PlanMethod::kGreedy, 60, {});
    std::vector<double> v;
    for (size_t r : p.rows) {
        double s = 0.0;
        for (int k = 0; k < K; ++k) s += mix[size_t(k)] * db.value(k, r);
        v.push_back(s);
    }
    for (sepal::Solver solver : {sepal::Solver::kLeastSquares, sepal::Solver::kNonNegative}) {
        sepal::FitOptions fo = linear_fit();
        fo.solver = solver;
        sepal::CombinationFit fit;
        std::string err;
        REQUIRE(sepal::fit_combination(db, p.rows, v, {}, fo, &fit, &err));
        for (int k = 0; k < K; ++k) CHECK(fit.coeffs[size_t(k)] == doctest::Approx(mix[size_t(k)]).epsilon(1e-3).scale(1));
        CHECK(fit.sample_rms < 1e-6);
    }
}

TEST_CASE("linear model: NNLS meets the KKT conditions") {
    // A random SPD problem whose unconstrained solution has negative entries.
    const int n = 8;
    std::vector<double> A(n * n), g(n);
    Eigen::MatrixXd B(n + 3, n);
    sepal::SplitMix64 rng(3);
    for (int i = 0; i < n + 3; ++i)
        for (int j = 0; j < n; ++j) B(i, j) = rng.uniform() - 0.3;
    const Eigen::MatrixXd M = B.transpose() * B;
    for (int i = 0; i < n; ++i) {
        g[size_t(i)] = rng.uniform() - 0.5;
        for (int j = 0; j < n; ++j) A[size_t(i * n + j)] = M(i, j);
    }
    std::vector<double> c;
    sepal::nnls_gram(A, g, n, &c);
    int zeros = 0;
    for (int i = 0; i < n; ++i) {
        double w = g[size_t(i)];
        for (int j = 0; j < n; ++j) w -= A[size_t(i * n + j)] * c[size_t(j)];
        CHECK(c[size_t(i)] >= 0.0);
        if (c[size_t(i)] > 0.0) {
            CHECK(std::fabs(w) < 1e-9);  // stationary on the free set
        } else {
            CHECK(w <= 1e-9);  // no descent direction into the feasible set
            ++zeros;
        }
    }
    CHECK(zeros > 0);  // the constraint was active: the test exercised it
}

TEST_CASE("plan: greedy conditions far better than random; deterministic; JSON round trip") {
    const sepal::BrdfDatabase& db = coarse();
    // 4 samples per material (the paper: 800 for 100); the MERL-grid figure is in the bench.
    const sepal::MeasurementPlan g1 = make_plan(db, sepal::PlanMethod::kGreedy, 48, {});
    const sepal::MeasurementPlan g2 = make_plan(db, sepal::PlanMethod::kGreedy, 48, {});
    CHECK(g1.rows == g2.rows);
    CHECK(g1.rows.size() == 48);
    std::vector<size_t> sorted = g1.rows;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::unique(sorted.begin(), sorted.end()) == sorted.end());
    double worst_random = 0, best_random = 1e300;
    for (uint64_t seed = 1; seed <= 5; ++seed) {
        const sepal::MeasurementPlan r = make_plan(db, sepal::PlanMethod::kRandom, 48, {}, seed);
        worst_random = std::max(worst_random, r.condition);
        best_random = std::min(best_random, r.condition);
    }
    const sepal::MeasurementPlan u = make_plan(db, sepal::PlanMethod::kUniform, 48, {});
    MESSAGE("condition numbers: greedy " << g1.condition << ", random " << best_random << " .. "
                                         << worst_random << ", uniform " << u.condition);
    CHECK(g1.condition * 10 <= best_random);  // the issue: at most 1/10 of a random plan's
    CHECK(g1.condition < u.condition);

    const std::string dir = sepal_test::temp_dir();
    std::string err;
    REQUIRE(sepal::write_plan_json(dir + "/plan.json", db, g1, &err));
    sepal::MeasurementPlan back;
    REQUIRE_MESSAGE(sepal::read_plan_json(dir + "/plan.json", db, &back, &err), err);
    CHECK(back.rows == g1.rows);
    CHECK(back.condition == doctest::Approx(g1.condition));

    auto write_text = [&](const std::string& name, const std::string& text) {
        const std::string p = dir + "/" + name;
        REQUIRE(sepal::write_file_atomic(p, text.data(), text.size(), &err));
        return p;
    };
    const std::string head = R"({"format":"sepal-measure-plan","version":1,)";
    CHECK(!sepal::read_plan_json(write_text("a.json", "{"), db, &back, &err));
    CHECK(err.find("not valid JSON") != std::string::npos);
    CHECK(!sepal::read_plan_json(write_text("b.json", head + R"("grid":[90,90,180],"plan":[]})"), db, &back, &err));
    CHECK(err.find("grid [90,90,180] is not the database's [16,16,32]") != std::string::npos);
    CHECK(!sepal::read_plan_json(write_text("c.json", head + R"("grid":[16,16,32],"plan":[{"cell":99999,"channel":0}]})"), db, &back, &err));
    CHECK(err.find("plan[0]: cell 99999") != std::string::npos);
    // The last cell (theta_h, theta_d near 90 deg) is below the horizon.
    CHECK(!sepal::read_plan_json(write_text("d.json", head + R"("grid":[16,16,32],"plan":[{"cell":8191,"channel":1}]})"), db, &back, &err));
    CHECK(err.find("below the horizon") != std::string::npos);
    CHECK(!sepal::read_plan_json(write_text("e.json", head + R"("grid":[16,16,32],"plan":[{"cell":0,"channel":3}]})"), db, &back, &err));
    sepal::PlanOptions bad;
    bad.samples = 0;
    CHECK(!sepal::plan_measurement(db, bad, &back, &err));
}

TEST_CASE("plan: picture keeps the random candidate whose leave-one-out pictures are best, then swaps rows while they improve") {
    const sepal::BrdfDatabase& db = coarse();
    std::string err;
    std::vector<int> cols;
    for (int k = 0; k < db.size(); ++k) cols.push_back(k);
    sepal::PlanPictureScorer scorer;
    REQUIRE_MESSAGE(scorer.init(db, cols, sepal::PlanOptions{}.picture_size, &err), err);
    MESSAGE(scorer.pixels() << " lit pixels in the judged views");
    CHECK(scorer.pixels() > 1500);  // the lit sphere in 5 views at 32 x 32
    sepal::PlanOptions o;
    o.method = sepal::PlanMethod::kPicture;
    o.samples = 48;
    o.candidates = 6;
    o.picture_swaps = 0;
    o.seed = 3;
    sepal::MeasurementPlan p, again;
    REQUIRE_MESSAGE(sepal::plan_measurement(db, o, &p, &err), err);
    REQUIRE(sepal::plan_measurement(db, o, &again, &err));
    CHECK(p.rows == again.rows);
    CHECK(p.method == sepal::PlanMethod::kPicture);
    // The plan is one of the candidates (random plans of seeds 3..8), the best by the score.
    double best = -1e300, worst = 1e300;
    int chosen = -1;
    for (uint64_t seed = 3; seed < 9; ++seed) {
        const sepal::MeasurementPlan r = make_plan(db, sepal::PlanMethod::kRandom, 48, {}, seed);
        const double s = scorer.score(r.rows);
        best = std::max(best, s), worst = std::min(worst, s);
        if (r.rows == p.rows) chosen = int(seed);
    }
    MESSAGE("candidates' leave-one-out pictures " << worst << " .. " << best << " dB; kept seed " << chosen);
    CHECK(chosen >= 3);
    CHECK(p.picture_db == doctest::Approx(best));
    CHECK(scorer.score(p.rows) == doctest::Approx(best));
    CHECK(best > worst);  // the candidates differ: the choice is not a tie
    // Then swaps: the figure only rises, and the same options give the same plan.
    o.picture_swaps = 300;
    sepal::MeasurementPlan swapped, swapped_again;
    REQUIRE(sepal::plan_measurement(db, o, &swapped, &err));
    REQUIRE(sepal::plan_measurement(db, o, &swapped_again, &err));
    CHECK(swapped.rows == swapped_again.rows);
    MESSAGE("after " << o.picture_swaps << " proposals (" << swapped.swaps << " kept): " << swapped.picture_db << " dB");
    CHECK(swapped.swaps > 0);
    CHECK(swapped.picture_db > best);
    CHECK(scorer.score(swapped.rows) == doctest::Approx(swapped.picture_db));
    o.picture_swaps = -1;
    CHECK_FALSE(sepal::plan_measurement(db, o, &p, &err));
    CHECK(err.find("-1 picture swaps") != std::string::npos);
    // Every row of the database: nothing to swap in, and the planner still ends.
    o.samples = int(db.rows());
    o.candidates = 1;
    o.picture_swaps = 50;
    REQUIRE_MESSAGE(sepal::plan_measurement(db, o, &p, &err), err);
    CHECK(p.rows.size() == db.rows());
    CHECK(p.swaps == 0);
    o.samples = 48;
    o.picture_swaps = 0;
    o.candidates = 0;
    CHECK_FALSE(sepal::plan_measurement(db, o, &p, &err));
    CHECK(err.find("0 candidates") != std::string::npos);
}

TEST_CASE("measure: samples CSV round trip; mismatched samples are refused") {
    const sepal::BrdfDatabase& db = coarse();
    const sepal::MeasurementPlan p = make_plan(db, sepal::PlanMethod::kGreedy, 50, {});
    std::string err;
    auto f = sepal::make_brdf("nbrdf:gold-paint", &err);
    REQUIRE(bool(f));
    std::vector<double> clean, noisy, noisy2;
    REQUIRE(sepal::simulate_samples(db, p, *f, 0.0, 1, &clean, &err));
    REQUIRE(sepal::simulate_samples(db, p, *f, 0.01, 7, &noisy, &err));
    REQUIRE(sepal::simulate_samples(db, p, *f, 0.01, 7, &noisy2, &err));
    CHECK(noisy == noisy2);
    double dev = 0.0;
    for (size_t i = 0; i < clean.size(); ++i) {
        CHECK(float(clean[i]) == db.value(0, p.rows[i]));  // the instrument sees the bin centre
        dev += std::pow(noisy[i] / clean[i] - 1.0, 2);
    }
    dev = std::sqrt(dev / double(clean.size()));
    CHECK(dev > 0.006);
    CHECK(dev < 0.015);
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(sepal::write_samples_csv(dir + "/s.csv", db, p, noisy, "test", &err));
    std::vector<double> back;
    REQUIRE_MESSAGE(sepal::read_samples_csv(dir + "/s.csv", db, p, &back, &err), err);
    REQUIRE(back.size() == noisy.size());
    for (size_t i = 0; i < back.size(); ++i) CHECK(back[i] == doctest::Approx(noisy[i]).epsilon(1e-8));
    const sepal::MeasurementPlan other = make_plan(db, sepal::PlanMethod::kRandom, 50, {});
    CHECK(!sepal::read_samples_csv(dir + "/s.csv", db, other, &back, &err));
    CHECK(err.find("do not belong together") != std::string::npos);
    const std::string junk = "sample,cell,channel,theta_i,phi_i,theta_o,phi_o,value\n0,1,x\n";
    REQUIRE(sepal::write_file_atomic(dir + "/j.csv", junk.data(), junk.size(), &err));
    CHECK(!sepal::read_samples_csv(dir + "/j.csv", db, p, &back, &err));
    CHECK(err.find("line 2") != std::string::npos);
    CHECK(!sepal::simulate_samples(db, p, *f, -0.1, 1, &back, &err));
}

TEST_CASE("measure: leave-one-out from planned samples beats random; 1% noise costs < 2x") {
    const sepal::BrdfDatabase& db = coarse();
    int wins = 0;
    for (int k = 0; k < db.size(); ++k) {
        const double planned = loo_error(db, k, sepal::PlanMethod::kGreedy, 100, 0.0);
        const double noisy = loo_error(db, k, sepal::PlanMethod::kGreedy, 100, 0.01);
        double random = 0.0;
        for (uint64_t seed = 1; seed <= 3; ++seed)
            random += loo_error(db, k, sepal::PlanMethod::kRandom, 100, 0.0, seed) / 3;
        INFO(db.name(k) << ": planned " << planned << ", with 1% noise " << noisy << ", random " << random);
        CHECK(noisy < 2.0 * planned);
        CHECK(planned < 0.5);
        wins += planned < random;
    }
    MESSAGE("planned beats the mean of 3 random plans for " << wins << " of " << db.size());
    CHECK(wins >= db.size() * 3 / 4);
}

TEST_CASE("measure: the reconstruction's MERL .binary reads back through merl.cpp") {
    auto db = merl_grid_db();
    std::string err;
    CHECK(db->valid_cells() == 1096216);
    std::vector<uint8_t> use;
    REQUIRE(sepal::exclude_mask(*db, {"gold-paint"}, &use, &err));
    CHECK(!sepal::exclude_mask(*db, {"nope"}, &use, &err));
    REQUIRE(sepal::exclude_mask(*db, {"gold-paint"}, &use, &err));
    const sepal::MeasurementPlan p = make_plan(*db, sepal::PlanMethod::kGreedy, 30, use);
    auto f = sepal::make_brdf("nbrdf:gold-paint", &err);
    std::vector<double> v;
    REQUIRE(sepal::simulate_samples(*db, p, *f, 0.0, 1, &v, &err));
    sepal::DatabaseReconstruction r;
    REQUIRE_MESSAGE(sepal::reconstruct(*db, p, v, use, linear_fit(), &r, &err), err);
    CHECK(r.fit.coeffs[0] == 0.0);  // gold-paint itself is left out
    const std::string path = sepal_test::temp_dir() + "/gold.binary";
    REQUIRE_MESSAGE(sepal::write_reconstruction_merl(path, *db, r, &err), err);
    sepal::Tabulated t;
    sepal::MerlStats st;
    REQUIRE_MESSAGE(sepal::read_merl(path, &t, &st, &err), err);
    CHECK(st.missing_cells == sepal::kMerlCells - db->valid_cells());
    for (size_t vc = 0; vc < db->valid_cells(); vc += 1009) {
        const glm::dvec3 x = t.value(db->grid_cell(vc));
        for (int c = 0; c < 3; ++c)
            CHECK(x[c] == doctest::Approx(r.values[3 * vc + size_t(c)]).epsilon(1e-6));
    }
    // Its error against the truth: the clamped values are never further than P c.
    std::vector<float> truth;
    REQUIRE(sepal::tabulate_rows(*db, *f, &truth, &err));
    const double direct = sepal::relative_rms(r.values, truth);
    const double gram = sepal::combination_error_gram(*db, r.fit.coeffs, 0);
    MESSAGE("gold-paint from dark-red-paint and white-fabric, 30 samples: " << direct);
    CHECK(direct <= gram * (1 + 1e-4));
    CHECK(direct > 0.05);  // two unrelated materials do not make gold paint
    // A coarse grid cannot be written as MERL.
    CHECK(!sepal::write_reconstruction_merl(path, coarse(), r, &err));
}

TEST_CASE("measure: the log model recovers a recoloured database material, the linear one cannot") {
    // blue-acrylic with its channels scaled by 1, 0.5, 0.25: outside the span of the linear
    // model (one coefficient per material for all three channels), inside the log model's
    // (a per-channel offset is a colour scale).
    const sepal::BrdfDatabase& db = coarse();
    const int k = db.find("blue-acrylic");
    REQUIRE(k >= 0);
    const double scale[3] = {1.0, 0.5, 0.25};
    std::vector<float> truth(db.rows());
    for (size_t r = 0; r < db.rows(); ++r) truth[r] = float(db.value(k, r) * scale[r % 3]);
    const sepal::MeasurementPlan p = make_plan(db, sepal::PlanMethod::kGreedy, 120, {});
    CHECK(std::isfinite(p.condition));
    std::vector<double> v;
    for (size_t r : p.rows) v.push_back(truth[r]);
    std::string err;
    double e[2];
    for (int m = 0; m < 2; ++m) {
        sepal::FitOptions fo = m == 0 ? sepal::FitOptions{} : linear_fit();
        sepal::CombinationFit fit;
        REQUIRE_MESSAGE(sepal::fit_combination(db, p.rows, v, {}, fo, &fit, &err), err);
        CHECK(fit.space == fo.space);
        const std::vector<float> values = sepal::fit_values(db, fit);
        e[m] = sepal::relative_rms(values, truth);
        if (m == 0) {
            // The colour scale lands in the offsets: green and blue below red by about log 2 and log 4.
            CHECK(fit.offsets[0] - fit.offsets[1] == doctest::Approx(std::log(2.0)).epsilon(0.1));
            CHECK(fit.offsets[0] - fit.offsets[2] == doctest::Approx(std::log(4.0)).epsilon(0.1));
        }
    }
    MESSAGE("recoloured blue-acrylic: log " << e[0] << ", linear " << e[1]);
    CHECK(e[0] < 0.02);
    CHECK(e[1] > 3 * e[0]);
}

TEST_CASE("measure: a reconstruction renders as its rows say (rows_brdf)") {
    auto db = merl_grid_db();
    std::string err;
    const std::vector<float> col(db->column(1), db->column(1) + db->rows());
    auto f = sepal::rows_brdf(*db, col, "dark-red-paint (table)", &err);
    REQUIRE_MESSAGE(bool(f), err);
    auto truth = sepal::make_brdf("nbrdf:dark-red-paint", &err);
    REQUIRE(bool(truth));
    for (size_t vc = 0; vc < db->valid_cells(); vc += 7919) {
        glm::dvec3 wi, wo;
        sepal::plan_row_directions(*db, 3 * vc, &wi, &wo);
        const glm::dvec3 a = f->eval(wi, wo), b = truth->eval(wi, wo);
        for (int c = 0; c < 3; ++c) CHECK(a[c] == doctest::Approx(b[c]).epsilon(1e-3).scale(1e-3));
    }
    CHECK_FALSE(sepal::rows_brdf(*db, std::vector<float>(5), "short", &err));
    CHECK_FALSE(sepal::rows_brdf(coarse(), std::vector<float>(coarse().rows()), "coarse", &err));
}

namespace {

std::vector<std::string> cache_listing(const std::string& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec))
        out.push_back(e.path().filename().string());
    return out;
}

}  // namespace

TEST_CASE("database: a full disk is a message before the work, never a Bus error, and leaves no temporary") {
    std::string err;
    {
        // The fault hook: the space cannot be reserved.
        const std::string dir = sepal_test::temp_dir();
        sepal::inject_write_failure(1000);
        auto db = sepal::BrdfDatabase::open(*nbrdf(), coarse_options(dir), &err);
        sepal::inject_write_failure(-1);
        CHECK_FALSE(db);
        CHECK(err.find("No space left on device") != std::string::npos);
        CHECK(err.find("the cache needs") != std::string::npos);
        CHECK(cache_listing(dir).empty());
    }
    // A real 64 KiB tmpfs (root only): the table was written through a mapping, where a full
    // disk was SIGBUS; now the free space is checked first and the blocks reserved.
    const std::string dir = sepal_test::temp_dir();
    if (geteuid() != 0 || mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0) {
        MESSAGE("not root or tmpfs not mountable here: the fault hook above covers this");
        return;
    }
    auto db = sepal::BrdfDatabase::open(*nbrdf(), coarse_options(dir), &err);
    const std::vector<std::string> left = cache_listing(dir);
    umount(dir.c_str());
    CHECK_FALSE(db);
    CHECK_MESSAGE(err.find("MB free there") != std::string::npos, err);
    CHECK(left.empty());
}

TEST_CASE("database: SIGTERM during a build removes its temporary") {
    const std::string dir = sepal_test::temp_dir();
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        // The default actions, as a tool's process has them (the test runner handles these).
        signal(SIGTERM, SIG_DFL);
        signal(SIGINT, SIG_DFL);
        sepal::DatabaseOptions o = coarse_options(dir);
        o.grid = sepal::DatabaseGrid();  // MERL's: seconds of tabulation, time to interrupt
        o.materials.resize(3);
        std::string err;
        sepal::BrdfDatabase::open(*nbrdf(), o, &err);
        _exit(0);
    }
    bool seen = false;
    for (int i = 0; i < 4000 && !seen; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        for (const std::string& f : cache_listing(dir)) seen = seen || f.find(".db.tmp.") != std::string::npos;
    }
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(seen);
    CHECK(WIFSIGNALED(status));
    for (const std::string& f : cache_listing(dir)) CHECK_MESSAGE(f.find(".tmp.") == std::string::npos, f);
}

TEST_CASE("database: a table overwritten in place is caught by its checksum and rebuilt") {
    const std::string dir = sepal_test::temp_dir();
    sepal::DatabaseOptions o = coarse_options(dir);
    o.materials.resize(4);
    std::string err, path;
    size_t table_bytes = 0;
    {
        auto db = sepal::BrdfDatabase::open(*nbrdf(), o, &err);
        REQUIRE_MESSAGE(bool(db), err);
        path = db->cache_path();
        table_bytes = db->rows() * size_t(db->size()) * sizeof(float);
    }
    // 30% of the table (the end of the file) set to 1e30: the header and its checksum still
    // match, only the table's checksum can tell.
    std::vector<uint8_t> bytes;
    REQUIRE(sepal::read_file(path, &bytes, &err));
    const float huge = 1e30f;
    const size_t n = table_bytes * 3 / 10 / sizeof(float);
    for (size_t i = 0; i < n; ++i) std::memcpy(&bytes[bytes.size() - (i + 1) * sizeof(float)], &huge, sizeof huge);
    REQUIRE(sepal::write_file_atomic(path, bytes.data(), bytes.size(), &err));
    auto db = sepal::BrdfDatabase::open(*nbrdf(), o, &err);
    REQUIRE_MESSAGE(bool(db), err);
    CHECK(db->built_now());
    CHECK_MESSAGE(db->verify_table(&err), err);
}

TEST_CASE("measure: a plan with fewer samples than materials is refused, written or read") {
    const sepal::BrdfDatabase& db = coarse();
    std::string err;
    for (sepal::PlanMethod m : {sepal::PlanMethod::kPicture, sepal::PlanMethod::kGreedy, sepal::PlanMethod::kRandom,
                                sepal::PlanMethod::kUniform}) {
        sepal::PlanOptions o;
        o.samples = db.size() - 1;
        o.method = m;
        sepal::MeasurementPlan p;
        CHECK_FALSE(sepal::plan_measurement(db, o, &p, &err));
        CHECK_MESSAGE(err.find("cannot fit the weights of " + std::to_string(db.size()) + " materials") !=
                          std::string::npos,
                      err);
    }
    // A plan file of too few samples (written by hand or by an older sepal) is refused on reading.
    const sepal::MeasurementPlan ok = make_plan(db, sepal::PlanMethod::kUniform, 40, {});
    sepal::MeasurementPlan few = ok;
    few.rows.resize(3);
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(sepal::write_plan_json(dir + "/few.json", db, few, &err));
    sepal::MeasurementPlan back;
    CHECK_FALSE(sepal::read_plan_json(dir + "/few.json", db, &back, &err));
    CHECK(err.find("3 samples cannot fit") != std::string::npos);
}

TEST_CASE("measure: sample values beyond a BRDF's range are refused, and a reconstruction never overflows") {
    const sepal::BrdfDatabase& db = coarse();
    std::string err;
    const sepal::MeasurementPlan p = make_plan(db, sepal::PlanMethod::kUniform, 40, {});
    std::vector<double> v(p.rows.size(), 0.5);
    v[7] = 1e38;  // finite, so the finiteness check passed it
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(sepal::write_samples_csv(dir + "/s.csv", db, p, v, "test", &err));
    std::vector<double> back;
    CHECK_FALSE(sepal::read_samples_csv(dir + "/s.csv", db, p, &back, &err));
    CHECK_MESSAGE(err.find("line") != std::string::npos, err);
    CHECK(err.find("beyond +-1e+06") != std::string::npos);
    // In range, the reconstruction's values stay finite.
    v[7] = 1e6;
    sepal::DatabaseReconstruction r;
    REQUIRE_MESSAGE(sepal::reconstruct(db, p, v, {}, sepal::FitOptions{}, &r, &err), err);
    for (float x : r.values) REQUIRE(std::isfinite(x));
}
