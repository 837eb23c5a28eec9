// The Cornell .brdf reader (measured/cornell.h, parse_cornell), then a small tabulation
// (8 x 8 x 16 cells: the same splat and push-pull as the default 90 x 90 x 180, fast enough
// per input). Accepted samples have finite angles in range and finite colours >= 0; the
// table gives finite values >= 0 at every sample.
#include <cmath>
#include <string>

#include "fuzz/fuzz.h"
#include "measured/cornell.h"

extern "C" int sepal_fuzz_cornell(const uint8_t* data, size_t size) {
    const char* h = "cornell";
    sepal::CornellData d;
    std::string err;
    if (!sepal::parse_cornell(std::string(reinterpret_cast<const char*>(data), size), "c.brdf", &d, &err)) {
        sepal_fuzz::check(err.compare(0, 7, "c.brdf:") == 0 && err.size() > 8, h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(!d.samples.empty() && d.samples.size() <= sepal::kCornellMaxSamples, h, "sample count");
    for (const sepal::CornellSample& s : d.samples) {
        sepal_fuzz::check(s.theta_i >= 0 && s.theta_i <= M_PI / 2 && s.theta_s >= 0 && s.theta_s <= M_PI / 2, h,
                          "theta outside [0, pi/2]");
        sepal_fuzz::check(std::isfinite(s.phi_i) && std::isfinite(s.phi_s), h, "phi not finite");
        for (int c = 0; c < 3; ++c) sepal_fuzz::check(std::isfinite(s.rgb[c]) && s.rgb[c] >= 0, h, "colour not finite or < 0");
    }
    sepal::CornellTabulation how;
    how.res[0] = 8, how.res[1] = 8, how.res[2] = 16;
    sepal::Tabulated table;
    sepal::tabulate_cornell(d.samples, &table, how);
    for (size_t i = 0; i < d.samples.size(); i += 1 + d.samples.size() / 64) {
        const glm::dvec3 f = table.eval(d.samples[i].wi(), d.samples[i].wo());
        for (int c = 0; c < 3; ++c) sepal_fuzz::check(std::isfinite(f[c]) && f[c] >= 0, h, "table value not finite or < 0");
    }
    return 0;
}
