// Small helpers around the Brdf interface: directions from angles, directional albedo by a
// deterministic quadrature, and a deterministic random number generator.
//
// Usage:
//   glm::dvec3 wi = sepal::dir_from_degrees(30, 0);        // theta from +z, phi from +x
//   glm::dvec3 a = sepal::directional_albedo(*brdf, sepal::deg2rad(30));
//   sepal::Rng rng(42); double u = rng.uniform();          // same seed, same sequence
//
// Angles: theta is the polar angle from the normal (+z), phi the azimuth from the tangent
// (+x) towards +y. Functions taking radians say so; *_degrees ones take degrees.
//
// directional_albedo integrates f(wi, wo) cos(theta_o) over the outgoing hemisphere with a
// product rule: 8-point Gauss-Legendre on panels in theta_o and in phi_o. Besides
// `samples`/8 equal theta panels and `samples`/2 equal phi panels, panel edges are graded
// geometrically (1e-8 rad, ratio 3) towards theta_i and towards the mirror and retro
// azimuths phi_i + pi and phi_i, where lobes peak; a lobe of roughness 1e-3 at 89.99 degrees
// is thus resolved without a fine grid everywhere. Measured accuracy with samples = 64
// against samples = 512 with 16 nodes: 1e-12 for Lambert (exact), <= 1e-7 relative for
// smooth lobes (Phong n = 1e4, Ward roughness 1e-3 to 1, theta_i up to 89.99 degrees); about
// 1e-5 where the integrand has a kink off the panel edges (Cook-Torrance's min() masking).
// Cost: about (samples + 170) x (4 samples + 340) evaluations (176,000 for samples = 64).
#pragma once
#include <cstdint>

#include <glm/vec3.hpp>

namespace sepal {

constexpr double kPi = 3.14159265358979323846;

inline double deg2rad(double d) { return d * (kPi / 180.0); }
inline double rad2deg(double r) { return r * (180.0 / kPi); }

// Unit vector at polar angle theta and azimuth phi (radians).
glm::dvec3 dir_from_angles(double theta, double phi);
glm::dvec3 dir_from_degrees(double theta_deg, double phi_deg);
// Polar angle in [0, pi] and azimuth in (-pi, pi] of a non-zero vector (radians).
void angles_of(const glm::dvec3& w, double* theta, double* phi);
// Mirror direction about the normal +z.
inline glm::dvec3 mirror_z(const glm::dvec3& w) { return glm::dvec3(-w.x, -w.y, w.z); }

class Brdf;
// Directional albedo rho(wi) = integral of f(wi, wo) cos(theta_o) d(wo) over the upper
// hemisphere, per channel; wi at (theta_i, phi_i) in radians. samples >= 8 (rounded up to
// a multiple of 8). See the accuracy note above.
glm::dvec3 directional_albedo(const Brdf& f, double theta_i, int samples = 128, double phi_i = 0.0);

// Gauss-Legendre nodes and weights on [-1, 1]; n in [1, 64]. Deterministic (Newton
// iterations from fixed starts), accurate to ~1e-15.
void gauss_legendre(int n, double* nodes, double* weights);

// SplitMix64: a tiny deterministic generator (not for cryptography).
class Rng {
  public:
    explicit Rng(uint64_t seed = 0x5e9a1u) : state_(seed) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1), 53 random bits.
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniformly distributed direction on the upper hemisphere (z >= 0).
    glm::dvec3 hemisphere();

  private:
    uint64_t state_;
};

}  // namespace sepal
