// Distant lighting for the Monte Carlo renderer: radiance by world direction (z up, as the
// scene's default camera).
//
// Usage:
//   std::string err;
//   auto env = sepal::make_environment("sky", &err);   // or "constant", "constant:0.5",
//   glm::dvec3 L = env->radiance(dir);                  // "constant:1,0.9,0.8", "probe.hdr"
//
// Specs:
//   constant[:V | :R,G,B]   the same radiance everywhere (default 1): the paper's Table 2 setup,
//                           where the exact pixel value is the directional albedo
//   sky[:key=value,...]     a procedural clear sky, nothing downloaded: a zenith-to-horizon
//                           gradient (zenith 0.3/0.5/1, horizon 1/0.95/0.9), a dim ground
//                           (0.15/0.13/0.11) and a sun disk of radiance `sun` (default 100,
//                           over 100x the sky), angular radius `radius` (4 degrees), at
//                           `elevation` (35) and `azimuth` (-60 degrees from +x): high contrast
//                           (the sun gives about a third of an upward surface's irradiance),
//                           for Table 3
//   FILE.hdr                a Radiance .hdr latitude-longitude map: column u = 0.5 +
//                           atan2(y, x) / (2 pi), row v = acos(z) / pi (top row = zenith),
//                           nearest texel; up to 16384 pixels a side, non-finite or negative
//                           texels refused
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

class Environment {
  public:
    virtual ~Environment() = default;
    // Radiance arriving from the unit world direction dir.
    virtual glm::dvec3 radiance(const glm::dvec3& dir) const = 0;
    virtual std::string describe() const = 0;
    // True when the radiance is the same everywhere (the pixel's exact value is then the
    // directional albedo times it).
    virtual bool constant(glm::dvec3* value) const {
        (void)value;
        return false;
    }
};

std::unique_ptr<Environment> make_environment(const std::string& spec, std::string* err);

// Importance sampling of an environment by its luminance, the light half of multiple
// importance sampling in the Monte Carlo renderer (mc_render.h): a density constant over
// each cell of a latitude-longitude grid (width x height cells; phi from atan2(y, x), theta
// from +z), proportional to the cell's mean luminance over 4 x 4 points (a 4-degree sun
// covers dozens of 0.7-degree cells at the default 512 x 256), uniform in (phi, cos theta)
// inside a cell, so pdf() is exactly the density sample() draws (tested).
// Limits: width 4..4096, height 2..2048; an environment black everywhere cannot be sampled
// (build fails). Built once per render (2 M radiance lookups at the default size).
class EnvironmentSampler {
  public:
    bool build(const Environment& env, int width, int height, std::string* err);
    // A world direction for u in [0,1)^2 and its density per steradian.
    glm::dvec3 sample(double u0, double u1, double* pdf) const;
    double pdf(const glm::dvec3& dir) const;

  private:
    int w_ = 0, h_ = 0;
    std::vector<double> value_;     // per cell (row-major, theta rows from the zenith)
    std::vector<double> row_cdf_;   // h + 1
    std::vector<double> col_cdf_;   // h x (w + 1)
    double norm_ = 0;               // sum of value x solid angle
};

}  // namespace sepal
