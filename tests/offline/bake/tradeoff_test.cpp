// The speed-accuracy trade (offline/bake/cost_model.h, bake's --max-error pick): the frame-time
// model's fit, its file, and the bake's pick lying on the front of predicted frame time and
// quantized error. The measured sweep itself is `make bench` (tests/bench/tradeoff.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "bake/bake.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "bake/cost_model.h"
#include "util/io.h"
#include "util/json.h"
#include "test_util.h"

namespace {

const char* kWard = "ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15";

// Does any candidate beat c on both axes (as fast and as accurate, better in one)?
// Written here, not taken from bake.cpp, so the test checks the bake's marking.
bool dominated(const std::vector<sepal::BakeCandidate>& all, const sepal::BakeCandidate& c) {
    for (const sepal::BakeCandidate& d : all)
        if (d.ok && d.ms <= c.ms && d.error_quantized <= c.error_quantized &&
            (d.ms < c.ms || d.error_quantized < c.error_quantized))
            return true;
    return false;
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
}

// A trade-off JSON with one gles1 model, as `make bench` writes it.
std::string timings(double base, double pass, double term, double kib) {
    char b[512];
    std::snprintf(b, sizeof b,
                  "{\"device\": \"test\", \"size\": [64, 64], \"cost_models\": [{\"backend\": \"gles1\", "
                  "\"base_ms\": %g, \"per_pass_ms\": %g, \"per_term_ms\": %g, \"per_kib_ms\": %g, \"fit_error\": 0, "
                  "\"rows\": 9}], \"rows\": []}",
                  base, pass, term, kib);
    return b;
}

}  // namespace

TEST_CASE("cost model: the fit recovers exact coefficients and never gives a negative slope") {
    std::vector<sepal::CostSample> s;
    for (int p = 1; p <= 6; ++p)
        for (int k = 1; k <= 3; ++k)
            for (int64_t kib : {4, 16, 64}) s.push_back({p, k, kib * 1024, 2.0 + 0.5 * p + 0.25 * k + 0.01 * double(kib)});
    sepal::CostModel m;
    std::string err;
    REQUIRE_MESSAGE(sepal::fit_cost_model(s, &m, &err), err);
    CHECK(m.base_ms == doctest::Approx(2.0).epsilon(1e-9));
    CHECK(m.per_pass_ms == doctest::Approx(0.5).epsilon(1e-9));
    CHECK(m.per_term_ms == doctest::Approx(0.25).epsilon(1e-9));
    CHECK(m.per_kib_ms == doctest::Approx(0.01).epsilon(1e-9));
    CHECK(m.fit_error < 1e-9);
    CHECK(m.rows == int(s.size()));
    CHECK(m.predict(2, 1, 8192) == doctest::Approx(2 + 1 + 0.25 + 0.08));
    // Frames that get faster with more passes (noise, or a driver's batching): the slope is
    // dropped to zero rather than fitted negative, which would rank 6 passes above 1.
    std::vector<sepal::CostSample> odd;
    for (int p = 1; p <= 6; ++p) odd.push_back({p, 1, 4096, 10.0 - 0.5 * p});
    REQUIRE(sepal::fit_cost_model(odd, &m, &err));
    CHECK(m.per_pass_ms == 0);
    CHECK(m.per_term_ms >= 0);
    CHECK(m.per_kib_ms >= 0);
    CHECK(m.base_ms == doctest::Approx(10.0 - 0.5 * 3.5));
    // Too little to fit, and non-finite times, are refused or ignored.
    CHECK_FALSE(sepal::fit_cost_model({{1, 1, 100, NAN}, {2, 2, 100, 3.0}}, &m, &err));
    CHECK(err.find("at least 2") != std::string::npos);
}

TEST_CASE("cost model: built-in models, the bench file, and refusals") {
    sepal::CostModel m;
    std::string err;
    for (const char* b : {"gles1", "gles2-fused", "cpu"}) {
        CAPTURE(b);
        REQUIRE_MESSAGE(sepal::default_cost_model(b, &m, &err), err);
        CHECK(m.backend == b);
        // Positive and growing with work: more terms never predict a faster frame.
        CHECK(m.predict(1, 1, 8000) > 0);
        CHECK(m.predict(6, 6, 8000) > m.predict(1, 1, 8000));
    }
    CHECK_FALSE(sepal::default_cost_model("vulkan", &m, &err));
    CHECK(err.find("gles1, gles2-fused, cpu") != std::string::npos);
    const std::string dir = sepal_test::temp_dir();
    write_text(dir + "/t.json", timings(1, 2, 3, 4));
    REQUIRE_MESSAGE(sepal::read_cost_model(dir + "/t.json", "gles1", &m, &err), err);
    CHECK(m.base_ms == 1);
    CHECK(m.per_pass_ms == 2);
    CHECK(m.per_term_ms == 3);
    CHECK(m.per_kib_ms == 4);
    CHECK(m.device == "test");
    CHECK(m.width == 64);
    CHECK_FALSE(sepal::read_cost_model(dir + "/t.json", "cpu", &m, &err));
    CHECK(err.find("no cost model for backend 'cpu'") != std::string::npos);
    write_text(dir + "/neg.json", timings(1, -2, 3, 4));
    CHECK_FALSE(sepal::read_cost_model(dir + "/neg.json", "gles1", &m, &err));
    CHECK(err.find("per_pass_ms") != std::string::npos);
    write_text(dir + "/none.json", "{\"rows\": []}");
    CHECK_FALSE(sepal::read_cost_model(dir + "/none.json", "gles1", &m, &err));
    CHECK(err.find("make bench") != std::string::npos);
    write_text(dir + "/broken.json", "{\"cost_models\": [");
    CHECK_FALSE(sepal::read_cost_model(dir + "/broken.json", "gles1", &m, &err));
    CHECK_FALSE(sepal::read_cost_model(dir + "/missing.json", "gles1", &m, &err));
}

TEST_CASE("tradeoff: the --max-error pick lies on the front of predicted ms and error, at every budget") {
    std::string err;
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(kWard, &err);
    REQUIRE_MESSAGE(f, err);
    sepal::BakeOptions o;
    o.params = {sepal::Param::GsHalf};
    o.resolutions = {16, 32};
    o.methods = {sepal::Method::WSVD, sepal::Method::NMF};
    o.terms = {1, 2, 3};
    o.bits = {8, 16};
    o.cap = 2;
    o.keep_assets = true;  // one search, then every budget picks from the same candidates
    o.judge_size = 32;     // the rule under test does not read the image
    // Factors of f and a direction-space budget: the rule of --max-error under test (a budget
    // every candidate meets marks the front of predicted ms and quantized error).
    o.radiance = false;
    o.max_error = 1e9;
    sepal::BakeResult all;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &all, &err), err);
    REQUIRE(all.candidates.size() == 24);
    std::vector<double> errors;
    int front = 0;
    for (const sepal::BakeCandidate& c : all.candidates) {
        REQUIRE(c.ok);
        CHECK(c.ms > 0);
        CHECK(c.on_front == !dominated(all.candidates, c));
        front += c.on_front;
        errors.push_back(c.error_quantized);
    }
    // A front, not everything: 16-bit twins cost bytes and buy little on 8-bit hardware.
    CHECK(front >= 2);
    CHECK(front < int(all.candidates.size()) / 2);
    std::sort(errors.begin(), errors.end());
    // Every distinct budget through the bake's own rule on these candidates (a bake per
    // budget would factor again: the rule is what is under test).
    for (double budget : errors) {
        o.max_error = budget;
        CAPTURE(budget);
        std::vector<sepal::BakeCandidate> cands = all.candidates;
        const int wi = sepal::choose_winner(&cands, o);
        REQUIRE(wi >= 0);
        const sepal::BakeCandidate& w = cands[size_t(wi)];
        CHECK(w.error_quantized <= budget);
        CHECK(w.on_front);
        // Nothing meeting the budget is predicted faster.
        for (const sepal::BakeCandidate& c : cands)
            if (c.error_quantized <= budget) CHECK(c.ms >= w.ms);
    }
    // And bake() itself: its winner is that rule's, with the reason said.
    o.max_error = errors[errors.size() / 2];
    o.terms = {1, 2, 3};
    sepal::BakeResult r;
    REQUIRE_MESSAGE(sepal::bake(*f, o, &r, &err), err);
    std::vector<sepal::BakeCandidate> cands = all.candidates;
    CHECK(r.winner == sepal::choose_winner(&cands, o));
    CHECK(r.candidates[size_t(r.winner)].on_front);
    CHECK(r.why.find("fastest predicted frame") != std::string::npos);
}

TEST_CASE("sepal bake --timings: the measured model decides the pick, and the report says so") {
    const std::string dir = sepal_test::temp_dir();
    const std::string sepal = sepal_test::bin("sepal");
    // Passes dear: the fewest passes win (32x32, 1 term). Bytes dear: the smallest asset wins,
    // even with more passes (16x16, 3 nmf terms: 0.5996 <= 0.6).
    write_text(dir + "/passes.json", timings(1, 10, 0, 0.001));
    write_text(dir + "/bytes.json", timings(1, 0.001, 0, 10));
    // The bounded-albedo Ward, whose errors these budgets were chosen on (factors of f).
    const std::string base = sepal + " bake 'ward-duer" + std::string(kWard).substr(4) +
                             "' --param gs-half --res 16,32 --method wsvd,nmf --terms 1,2,3 --cap 2 --max-error 0.6 --fit brdf --judge-size 32 ";
    std::string out;
    REQUIRE(sepal_test::run(base + "--timings " + dir + "/passes.json -o " + dir + "/p.sepal --report " + dir + "/p.json",
                            &out) == 0);
    CHECK(out.find("<- winner") != std::string::npos);
    REQUIRE(sepal_test::run(base + "--timings " + dir + "/bytes.json -o " + dir + "/b.sepal --report " + dir + "/b.json",
                            &out) == 0);
    auto winner = [&](const std::string& report) {
        std::string err;
        sepal::Json v;
        REQUIRE_MESSAGE(sepal::read_json_file(report, &v, &err), err);
        REQUIRE(v.contains("winner"));
        REQUIRE(v.contains("candidates"));
        const sepal::Json& c = v["candidates"].at(v["winner"].get<size_t>());
        CHECK(c["on_front"] == true);
        CHECK(c["ms_predicted"].get<double>() > 0);
        CHECK(v["cost_model"]["device"] == "test");
        return std::make_pair(c["passes"].get<int>(), c["bytes"].get<int>());
    };
    const auto p = winner(dir + "/p.json"), b = winner(dir + "/b.json");
    CHECK(p.first < b.first);   // fewer passes when passes are dear
    CHECK(b.second < p.second);  // fewer bytes when bytes are dear
    // Unknown backends and missing files are refused before any work.
    CHECK(sepal_test::run(base + "--backend vulkan -o " + dir + "/x.sepal", &out) == 2);
    CHECK(out.find("no built-in model for backend 'vulkan'") != std::string::npos);
    CHECK(sepal_test::run(base + "--timings " + dir + "/absent.json -o " + dir + "/x.sepal", &out) == 2);
    CHECK_FALSE(std::ifstream(dir + "/x.sepal").good());
}
