// Sample files: round trip, refusals with the line named, Cornell measurements fitted.
#include <doctest/doctest.h>

#include <cmath>

#include <glm/glm.hpp>

#include "fit/lafortune_fit.h"
#include "measured/samples.h"
#include "test_util.h"

TEST_CASE("fit samples: written samples read back to 9 digits, extra columns ignored") {
    std::vector<sepal::BrdfSample> s(5);
    for (int i = 0; i < 5; ++i) {
        s[size_t(i)].wi = sepal::direction_from_degrees(10 + 10 * i, 20 * i - 40);
        s[size_t(i)].wo = sepal::direction_from_degrees(70 - 10 * i, 100 + i);
        s[size_t(i)].value = glm::dvec3(0.1 * i, 0.2, 1.0 / 3);
        s[size_t(i)].weight = 1 + i;
    }
    const std::string path = sepal_test::temp_dir() + "/s.csv";
    std::string err;
    REQUIRE(sepal::write_brdf_samples(path, s, "test", &err, {"texel"}, {{1, 2, 3, 4, 5}}));
    std::vector<sepal::BrdfSample> r;
    REQUIRE_MESSAGE(sepal::read_brdf_samples(path, &r, &err), err);
    REQUIRE(r.size() == s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        CHECK(glm::length(r[i].wi - s[i].wi) < 1e-7);
        CHECK(glm::length(r[i].wo - s[i].wo) < 1e-7);
        CHECK(r[i].value.z == doctest::Approx(1.0 / 3).epsilon(1e-8));
        CHECK(r[i].weight == s[i].weight);
    }
}

TEST_CASE("fit samples: bad files are refused with the line") {
    std::vector<sepal::BrdfSample> r;
    std::string err;
    CHECK_FALSE(sepal::parse_brdf_samples("theta_i,phi_i,theta_o,r,g,b\n1,2,3,4,5,6\n", "f", &r, &err));
    CHECK(err.find("phi_o") != std::string::npos);
    CHECK_FALSE(sepal::parse_brdf_samples("# c\ntheta_i,phi_i,theta_o,phi_o,value\n10,0,10,180,nan\n", "f", &r, &err));
    CHECK(err.find("f:3") != std::string::npos);
    CHECK_FALSE(sepal::parse_brdf_samples("theta_i,phi_i,theta_o,phi_o,value\n95,0,10,180,1\n", "f", &r, &err));
    CHECK(err.find("theta") != std::string::npos);
    CHECK_FALSE(sepal::parse_brdf_samples("theta_i,phi_i,theta_o,phi_o,value\n10,0,10\n", "f", &r, &err));
    CHECK_FALSE(sepal::parse_brdf_samples("theta_i,phi_i,theta_o,phi_o,value,weight\n10,0,10,1,1,-1\n", "f", &r, &err));
    CHECK_FALSE(sepal::parse_brdf_samples("sample,cell,channel,theta_i,phi_i,theta_o,phi_o,value\n", "f", &r, &err));
    CHECK_FALSE(sepal::parse_brdf_samples("# only a comment\n", "f", &r, &err));
    CHECK(sepal::parse_brdf_samples("theta_i,phi_i,theta_o,phi_o,value\n10,0,20,180,0.5\n", "f", &r, &err));
    CHECK(r[0].value == glm::dvec3(0.5));
}

TEST_CASE("fit samples: a Cornell measurement reads as samples and takes a Lafortune fit") {
    std::vector<sepal::BrdfSample> s;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_brdf_samples(sepal_test::source_path("fixtures/cornell/cayman.brdf"), &s, &err), err);
    CHECK(s.size() > 1000);
    sepal::LafortuneFit fit;
    REQUIRE_MESSAGE(sepal::fit_lafortune(s, sepal::LafortuneFitOptions(), &fit, &err), err);
    CHECK(fit.rank == 6);
    CHECK(std::isfinite(fit.rms));
}
