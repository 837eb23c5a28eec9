// A chi-square goodness-of-fit test of a direction sampler against its own pdf, as pbrt-v4's
// bsdfs_test does it (read, re-written): samples binned into a theta x phi histogram of the
// upper hemisphere plus one cell for draws at or below the horizon, expected counts from the
// pdf integrated over each cell (nested adaptive Simpson of pdf sin(theta) on 8 x 8 fixed
// panels; the lower hemisphere gets the rest of the unit mass), cells expecting < 5 pooled,
// the p-value from the chi-square CDF and a Sidak-corrected significance level.
#pragma once
#include <functional>
#include <string>

#include <glm/vec3.hpp>

namespace sepal_test {

struct Chi2Result {
    bool pass = false;
    double statistic = 0, p_value = 0, alpha = 0;
    int dof = 0;
    double pdf_upper = 0;     // the pdf integrated over the upper hemisphere
    // pdf_upper + the share of draws below the horizon: the pdf's integral over the sphere
    // (1 when the pdf is normalized and the lower-hemisphere mass is right)
    double pdf_integral = 0;
    std::string message;
};

// sample(i) returns the i-th direction (unit, any hemisphere) and false when there is none;
// pdf(w) its density per steradian. tests: how many tests the significance is shared by.
Chi2Result chi2_test(const std::function<bool(int, glm::dvec3*)>& sample,
                     const std::function<double(const glm::dvec3&)>& pdf, int samples, int tests,
                     double significance = 0.01, int theta_res = 10, int phi_res = 20);

// The chi-square distribution's CDF (regularized lower incomplete gamma), exposed for tests.
double chi2_cdf(double x, int dof);

}  // namespace sepal_test
