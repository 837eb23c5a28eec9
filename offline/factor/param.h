// Parameterizations of a BRDF for separable factors f(wi, wo) ~= sum_k G_k(x) H_k(y).
//
// Usage:
//   sepal::Param p; sepal::parse_param("gs-half", &p);
//   sepal::TexCoords tc;
//   if (sepal::param_forward(p, sepal::HemiMap::XY, wi, wo, &tc)) { lookup G at tc.x, H at tc.y }
//   // and back, for sampling: texture coordinates of both factors -> (wi, wo)
//   glm::dvec3 px, py, wi, wo;
//   if (factor_point(p, map, 0, uv_x, &px) && factor_point(p, map, 1, uv_y, &py) &&
//       combine_points(p, px, py, &wi, &wo)) { ... }
//
// Directions are in the local frame of brdf.h (n = +z, t = +x, s = +y), unit length, pointing
// away from the surface. Each factor is an N x N texture over texture coordinates
// (u, v) in [0,1]^2; texel (i, j) covers [i/N, (i+1)/N] x [j/N, (j+1)/N], centre
// ((i + 0.5)/N, (j + 0.5)/N).
//
// Parameterizations (x ; y), the factor G is a function of x, H of y:
//   iv            incident/view: x = wi, y = wo.                     hardware-compatible
//   gs-half       Gram-Schmidt half/difference (Kautz-McCool eq. 6): x = h = norm(wi + wo);
//                 y = wi in the frame (t', s', h), t' = norm(t - (h.t) h), s' = h x t'.
//                                                                      hardware-compatible
//   vh            view/half (Lawrence 2004): x = wo, y = h.          hardware-compatible
//   rusinkiewicz  x = h; y = d = rot_y(-theta_h) rot_z(-phi_h) wi (h rotated to the pole):
//                 unstable at h ~ n under per-vertex interpolation, per-pixel backends only.
//   elev-azim     x = (theta_i, theta_o), y = (phi_i, phi_o) as plain angle textures
//                 (u = theta / (pi/2); u = phi / (2 pi), periodic): per-pixel only; the
//                 hemisphere map does not apply to it.
//   axis          angles about the tangent (latitude and longitude with the pole on t):
//                 alpha = asin(w.t), out of the cross-section plane (s, n); beta =
//                 atan2(w.s, w.n), within it. x = (alpha_i, alpha_o), y = (beta_i, beta_o),
//                 u = angle / pi + 1/2 (both in (-pi/2, pi/2) above the horizon). Brushed,
//                 grooved and cylinder-like surfaces along t (Poulin-Fournier) are nearly
//                 separable here: a cylinder's specular peak depends on alpha_i + alpha_o,
//                 its shadowing and masking on the betas. Both poles (w = +-t) lie on the
//                 horizon, so every coordinate is smooth above it: hardware-compatible. No
//                 hemisphere map applies; every texel is valid.
//   gs-mirror     Gram-Schmidt mirror/view: x = r = (-wi.x, -wi.y, wi.z), the mirror
//                 direction of wi; y = wo in the frame (t', s', r) of gs-half's eq. 6 about
//                 r instead of h. A lobe about the mirror direction, (wo.r)^n (Phong,
//                 Lafortune's isotropic lobes), times cos(theta_i) = r.z is one product:
//                 G(r) = r.z, H(y) = y.z^n. (Under gs-half or vh it is no product at all:
//                 Phong n=1000 took eight terms at 8/128 texels for 39 dB.)
//                 wo.r < 0 (light and eye on the same side, far from the normal) lies
//                 behind r's horizon, where no hemisphere map reaches (XY would fold wo = -r
//                 onto the lobe's peak): y is taken to the rim, (y.x, y.y) / |(y.x, y.y)|, z
//                 = 0, the value at wo.r = 0 (a lobe about r is 0 there). Such pairs do not
//                 come back through combine_points. The runtime does the same.
//                                                                      hardware-compatible
// Hemisphere maps for a unit vector a with a.z >= 0 in its frame:
//   XY         (u, v) = ((a.x + 1)/2, (a.y + 1)/2)
//   parabolic  (u, v) = ((a.x/(1 + a.z) + 1)/2, (a.y/(1 + a.z) + 1)/2)
// Both map the hemisphere onto the disk inscribed in the texture; texels whose centre lies
// outside it are invalid (never sampled; filled from valid neighbours after factoring).
//
// Extremes (tests/extremes_test.cpp):
//   - param_forward refuses (returns false, *tc untouched) a pair with a direction at or
//     below the horizon (back-facing: the BRDF is 0 there) or with a non-finite component;
//     for every other pair of unit vectors, grazing ones included (89.9 degrees and beyond),
//     every coordinate is finite and inside [0, 1].
//   - Degenerate frames get a fixed, deterministic fallback, the same as the runtime's
//     (runtime/src/param.cpp) where it has one:
//     gs-half     t' = norm(t - (h.t) h) is computed as (hy^2 + hz^2, -hx hy, -hx hz) / r,
//                 r = sqrt(hy^2 + hz^2), exact to rounding as h nears t; only when
//                 r <= 1e-12 (h = +-t, possible only at the horizon) t' = norm(s - (h.s) h).
//     rusinkiewicz phi_h = atan2(h.y, h.x) is undefined at h = n: phi_h = 0 when
//                 hx^2 + hy^2 <= 1e-24 (sin theta_h <= 1e-12), whatever the signs of zero.
//                 An isotropic BRDF does not depend on phi_d at theta_h = 0, so nothing is
//                 lost; the sampler counts pairs built this way (FactorResult::frame_fallbacks).
//                 It happens at the texel centre (0.5, 0.5): only for --res 1.
//     elev-azim   the azimuth of a direction at the pole is 0 (same threshold).
//     axis        beta = atan2(w.s, w.n) is undefined at w = +-t (on the horizon, so only
//                 for grazing pairs): 0 there; alpha is atan2(w.t, |(w.s, w.n)|), asin(w.t)
//                 for a unit w without asin's loss of precision near the poles.
//     gs-mirror   as gs-half, with r for h: r = +-t is the light grazing along t.
//     frame_fallback() says whether a G point (the half vector, gs-mirror's r) takes a
//     fallback.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace sepal {

enum class Param { IncidentView, GsHalf, ViewHalf, Rusinkiewicz, ElevAzim, Axis, GsMirror };
enum class HemiMap { XY, Parabolic };

const char* param_name(Param p);  // "iv", "gs-half", "vh", "rusinkiewicz", "elev-azim", "axis", "gs-mirror"
bool parse_param(const std::string& name, Param* p);
const char* map_name(HemiMap m);  // "xy", "parabolic"
bool parse_map(const std::string& name, HemiMap* m);
// True when texture coordinates computed per vertex may be interpolated linearly
// (iv, gs-half, vh, axis, gs-mirror): the parameterizations the GL ES backends can use.
bool hardware_compatible(Param p);
// Which factor depends on the half vector h only: 0 (G), 1 (H), or -1 (none).
int half_angle_factor(Param p);
// Which factor holds a lobe's sharp part, the one a bake gives the finer resolution: the
// half-angle factor, axis's G (the lobe along alpha_i + alpha_o), gs-mirror's H (wo about
// the mirror direction), or -1 (iv, elev-azim: both factors alike).
int sharp_factor(Param p);
// True when factor `which` (0 = G, 1 = H) is periodic in u and v (elev-azim's azimuths);
// all other factors clamp at the texture edge.
bool factor_wraps(Param p, int which);

// Hemisphere map of a unit vector with a.z >= 0 (parabolic also accepts a.z > -1).
glm::dvec2 map_forward(HemiMap m, const glm::dvec3& a);
// Inverse: false when (u, v) lies outside the unit disk of the map.
bool map_inverse(HemiMap m, const glm::dvec2& uv, glm::dvec3* a);

struct TexCoords {
    glm::dvec2 x, y;  // texture coordinates into G and H
};
// Forward: false when wi or wo is at or below the horizon (the BRDF is 0 there) or not
// finite.
bool param_forward(Param p, HemiMap m, const glm::dvec3& wi, const glm::dvec3& wo,
                   TexCoords* tc);

// Inverse, in two steps so samplers can precompute per texel: the point of factor `which`
// at texture coordinate uv (a unit vector in its frame; for elev-azim and axis the two
// angles in .x, .y), false outside the factor's domain; then the direction pair of two points,
// false when it is not a valid pair (a direction at or below the horizon).
bool factor_point(Param p, HemiMap m, int which, const glm::dvec2& uv, glm::dvec3* point);
bool combine_points(Param p, const glm::dvec3& px, const glm::dvec3& py, glm::dvec3* wi,
                    glm::dvec3* wo);

// The Gram-Schmidt frame (t', s') of eq. 6 for a unit half vector h; false when h = +-t and
// the fallback above was used.
bool gs_half_frame(const glm::dvec3& h, glm::dvec3* tp, glm::dvec3* sp);
// Rusinkiewicz's azimuth of h, 0 at the pole (*fallback, if given, says so).
double rusinkiewicz_phi_h(const glm::dvec3& h, bool* fallback = nullptr);
// True for the parameterizations whose factors are plain angle textures (elev-azim, axis):
// no hemisphere map applies.
bool angle_textures(Param p);
// True when the G point (the half vector of gs-half or rusinkiewicz, gs-mirror's r) has a degenerate frame
// and the fallback above applies; always false for the other parameterizations.
bool frame_fallback(Param p, const glm::dvec3& point);

// Validity of the texels of factor `which` at resolution n: 1 where the texel centre lies
// in the factor's domain. Row-major, j * n + i.
std::vector<uint8_t> valid_texels(Param p, HemiMap m, int which, int n);

}  // namespace sepal
