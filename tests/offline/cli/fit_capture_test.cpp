// sepal measure capture and sepal fit lafortune (docs/acquisition.md's command lines): a photograph of
// the virtual setup and its samples, a fit that recovers a known model within its intervals,
// and refusals that leave no output behind.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "cli/cli.h"
#include "fit/lafortune_fit.h"
#include "measured/samples.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "test_util.h"

namespace {

bool exists(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f) std::fclose(f);
    return f != nullptr;
}

int run(const char* command, const std::vector<std::string>& args, std::string* out) {
    return sepal_test::run_cmd(command, args, out);
}

}  // namespace

TEST_CASE("sepal measure capture: a photograph and its samples; a bad view writes nothing") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(run("measure", {"capture", "-o", dir + "/p.png", "--samples", dir + "/s.csv", "--atlas", "32",
                                     "--size", "64", "--object", "torus"},
                &out) == 0);
    sepal::Image img;
    REQUIRE(sepal::read_image(dir + "/p.png", &img, nullptr));
    CHECK(img.width == 64);
    std::vector<sepal::BrdfSample> s;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_brdf_samples(dir + "/s.csv", &s, &err), err);
    CHECK(s.size() > 500);
    for (const sepal::BrdfSample& x : s) {
        CHECK(x.wi.z > 0);
        CHECK(x.wo.z > 0);
        CHECK(x.weight > 0);
    }
    // Camera and light together: refused, and neither file is written.
    CHECK(run("measure", {"capture", "-o", dir + "/q.png", "--samples", dir + "/q.csv", "--camera", "0,30",
                                   "--light", "0,31"},
              &out) == 2);
    CHECK(out.find("degrees apart") != std::string::npos);
    CHECK_FALSE(exists(dir + "/q.png"));
    CHECK_FALSE(exists(dir + "/q.csv"));
    CHECK(run("measure", {"capture", "-o", dir + "/q.png", "--camera", "0"}, &out) == 2);
    CHECK(run("measure", {"capture", "-o", dir + "/q.png", "--object", "teapot"}, &out) == 2);
}

TEST_CASE("sepal fit lafortune: a known model is recovered within its 95% intervals") {
    const std::string dir = sepal_test::temp_dir();
    std::string err;
    const char* spec = "lafortune:rho_d=0.3/0.2/0.1,lobe=-0.9/-0.9/0.9/25";
    auto f = sepal::make_brdf(spec, &err);
    REQUIRE_MESSAGE(f, err);
    // Noiseless samples on a grid of directions: the fit must land on the truth.
    std::vector<sepal::BrdfSample> s;
    for (int ti = 0; ti < 8; ++ti)
        for (int to = 0; to < 8; ++to)
            for (int p = 0; p < 12; ++p) {
                sepal::BrdfSample x;
                x.wi = sepal::direction_from_degrees(5 + 10 * ti, 0);
                x.wo = sepal::direction_from_degrees(5 + 10 * to, 30.0 * p);
                x.value = f->eval(x.wi, x.wo);
                s.push_back(x);
            }
    REQUIRE_MESSAGE(sepal::write_brdf_samples(dir + "/s.csv", s, "test", &err), err);
    std::string out;
    REQUIRE(run("fit", {"lafortune", dir + "/s.csv", "-o", dir + "/fit.json"}, &out) == 0);
    CHECK(out.find("rank 6") != std::string::npos);
    sepal::Json j;
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/fit.json", &j, &err), err);
    const double truth[] = {0.3, 0.2, 0.1, -0.9, 0.9, 25};
    REQUIRE(j["parameters"].size() == 6u);
    for (size_t i = 0; i < 6; ++i) {
        CAPTURE(i);
        CHECK(std::fabs(j["parameters"][i]["value"].get<double>() - truth[i]) <= 1e-3 * std::fabs(truth[i]));
    }
    CHECK(j["covariance"].size() == 6u);
    CHECK(j.find("picture") == j.end());  // only with --truth
    // Judged by its picture against the BRDF the samples came from: a recovered model renders
    // as the truth.
    REQUIRE(run("fit", {"lafortune", dir + "/s.csv", "-o", dir + "/fit2.json", "--truth", spec}, &out) == 0);
    CHECK(out.find("picture    default scene") != std::string::npos);
    sepal::Json j2;
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/fit2.json", &j2, &err), err);
    REQUIRE(j2.contains("picture"));
    CHECK(j2["picture"]["views"].size() == 5u);
    CHECK(j2["picture"]["views"][0]["psnr_db"].get<double>() > 50.0);
    CHECK(run("fit", {"lafortune", dir + "/s.csv", "--truth", "nosuch:model"}, &out) == 2);
    // The printed spec is a spec: it builds.
    CHECK(sepal::make_brdf(j["spec"].get<std::string>(), &err) != nullptr);
    CHECK(out.find("warning") == std::string::npos);  // unweighted samples state no noise
    CHECK(j["model_fits_noise"].get<bool>());
    // Weighted samples (1/std, as a capture writes them): noise of the stated size fits
    // quietly; the same samples mixed with a second material's cannot be one lobe.
    auto g = sepal::make_brdf("lafortune:rho_d=0.05/0.3/0.6,lobe=-0.5/-0.5/0.9/3", &err);
    REQUIRE_MESSAGE(g, err);
    std::vector<sepal::BrdfSample> noisy = s, mixed = s;
    for (size_t i = 0; i < s.size(); ++i) {
        const double std_dev = 0.01;
        noisy[i].weight = mixed[i].weight = 1.0 / std_dev;
        const double e = std_dev * (double((i * 7919) % 1000) / 1000.0 - 0.5) * std::sqrt(12.0);
        noisy[i].value += glm::dvec3(e);
        if (i % 2) mixed[i].value = g->eval(s[i].wi, s[i].wo);
    }
    REQUIRE_MESSAGE(sepal::write_brdf_samples(dir + "/noisy.csv", noisy, "test", &err), err);
    REQUIRE_MESSAGE(sepal::write_brdf_samples(dir + "/mixed.csv", mixed, "test", &err), err);
    REQUIRE(run("fit", {"lafortune", dir + "/noisy.csv"}, &out) == 0);
    CHECK_MESSAGE(out.find("warning") == std::string::npos, out);
    REQUIRE(run("fit", {"lafortune", dir + "/mixed.csv", "-o", dir + "/mixed.json"}, &out) == 0);
    CHECK_MESSAGE(out.find("warning    the residual is") != std::string::npos, out);
    CHECK(out.find("1 lobe does not describe these samples") != std::string::npos);
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/mixed.json", &j, &err), err);
    CHECK_FALSE(j["model_fits_noise"].get<bool>());
    CHECK(out.find("energy     largest directional albedo") != std::string::npos);
    REQUIRE(j["max_albedo"].is_number());
    CHECK(j["plausible"].get<bool>() ==
          (!j["clamped"].get<bool>() && j["max_albedo"].get<double>() <= sepal::kPlausibleAlbedo));
    // Samples of a model that reflects more than it receives: the fit recovers it and says so.
    auto hot = sepal::make_brdf("lafortune:rho_d=0.5/0.5/0.5,lobe=-1.2/-1.2/1.2/4", &err);
    REQUIRE_MESSAGE(hot, err);
    std::vector<sepal::BrdfSample> h = s;
    for (sepal::BrdfSample& x : h) x.value = hot->eval(x.wi, x.wo);
    REQUIRE_MESSAGE(sepal::write_brdf_samples(dir + "/hot.csv", h, "test", &err), err);
    REQUIRE(run("fit", {"lafortune", dir + "/hot.csv", "-o", dir + "/hot.json"}, &out) == 0);
    CHECK_MESSAGE(out.find("warning    the model reflects more light than it receives") != std::string::npos, out);
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/hot.json", &j, &err), err);
    CHECK_FALSE(j["plausible"].get<bool>());
    CHECK(j["max_albedo"].get<double>() > sepal::kPlausibleAlbedo);
    // A retro-reflective lobe: the free fit follows it; --forward keeps Cxy <= 0 and says so.
    auto retro = sepal::make_brdf("lafortune:rho_d=0.05/0.1/0.4,lobe=0.6/0.6/0.5/4", &err);
    REQUIRE_MESSAGE(retro, err);
    for (sepal::BrdfSample& x : h) x.value = retro->eval(x.wi, x.wo);
    REQUIRE_MESSAGE(sepal::write_brdf_samples(dir + "/retro.csv", h, "test", &err), err);
    REQUIRE(run("fit", {"lafortune", dir + "/retro.csv", "-o", dir + "/retro.json"}, &out) == 0);
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/retro.json", &j, &err), err);
    CHECK_FALSE(j["forward"].get<bool>());
    CHECK(j["parameters"][3]["value"].get<double>() > 0.3);
    REQUIRE(run("fit", {"lafortune", dir + "/retro.csv", "--forward", "-o", dir + "/retro.json"}, &out) == 0);
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/retro.json", &j, &err), err);
    CHECK(j["forward"].get<bool>());
    CHECK(j["parameters"][3]["value"].get<double>() <= 0.0);
    // Refusals: a missing file, a bad lobe count; a failed fit writes no JSON.
    CHECK(run("fit", {"lafortune", dir + "/none.csv", "-o", dir + "/x.json"}, &out) == 2);
    CHECK(run("fit", {"lafortune", dir + "/s.csv", "--lobes", "5"}, &out) == 2);
    CHECK(run("fit", {"nonsense"}, &out) == 2);
    CHECK(out.find("unknown subcommand 'nonsense' (one of lafortune)") != std::string::npos);
    CHECK_FALSE(exists(dir + "/x.json"));
}
