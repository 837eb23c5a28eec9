// Poulin-Fournier microcylinders, evaluated numerically (see brdf_models.h for the model).
//
// Geometry, in units of the cylinder radius: parallel cylinders with axes along the tangent
// x, spaced d apart (d >= 2: no overlap), axes at height h above the base plane (h in
// [-1, 1]; -1 = flat). Everything happens in the y-z cross-section; a direction w projects
// to a 2D direction of length a = |(w.y, w.z)| and angle beta = atan2(w.y, w.z) from the
// normal. A cylinder point at angle psi has normal m = (0, sin psi, cos psi), so
// m.w = a cos(psi - beta).
//
// f(wi, wo) = [ integral over one period of the profile of f_m(wi, wo) (m.wi)(m.wo) V_i V_o
//               ] / (d cos_i cos_o)
// (the microsurface-to-macrosurface BRDF of a height field without interreflection; V is
// 1 where the point is neither self-facing-away nor hidden by a neighbouring cylinder).
// f_m is the modified Phong BRDF about m: Rd/pi + Rs (n+2)/(2 pi) max(0, r_m(wi).wo)^n.
//
// Visibility is exact and in closed form: on a cylinder, the points seen from beta > 0 are
// psi in (beta - pi/2, beta + asin(min(1, d cos beta - 1))] (the neighbour at +d hides the
// rest; nothing farther can, because a rising ray that clears one cylinder clears its
// translates); on the ground, each of the two neighbouring cylinders hides one interval.
// The diffuse part of the integral is then closed form; the specular part is 8-point
// Gauss-Legendre on panels around the lobe's peak psi* = (beta_i + beta_o)/2 that grow by
// 3x from the lobe's width, clipped to the visible interval and to the lobe's support.
// Every step is symmetric in (wi, wo), so the result is reciprocal to rounding.
#include <algorithm>
#include <cmath>

#include "brdf/brdf_models_impl.h"
#include "brdf/brdf_util.h"

namespace sepal {

using glm::dvec3;

namespace {

constexpr int kGL = 8;

struct Profile2D {
    double a, beta;  // length and angle of the direction's projection on the y-z plane
};

class PoulinFournier final : public AnalyticBrdf {
  public:
    PoulinFournier(const ModelEntry& e, const ParamSet& p)
        : AnalyticBrdf(e, p), d_(scalar("d")), h_(scalar("h")), n_(scalar("n")), rs_(colour("Rs")), rd_(colour("Rd")) {
        psi_max_ = std::acos(std::clamp(-h_, -1.0, 1.0));
        c_ = std::sqrt(std::max(0.0, 1.0 - h_ * h_));
        gauss_legendre(kGL, gx_, gw_);
        if (n_ >= 0.0 && n_ <= 1024.0 && n_ == std::floor(n_)) n_int_ = int(n_);
    }
    bool isotropic() const override { return h_ <= -1.0; }  // only the flat limit
    // Each facet's modified Phong conserves energy when Rd + Rs <= 1 (Lafortune-Willems);
    // masking and shadowing only remove light.
    bool energy_conserving() const override { return max3(rd_ + rs_) <= 1.0; }

  protected:
    dvec3 eval_above(const dvec3& wi, const dvec3& wo) const override {
        const Profile2D pi{std::sqrt(wi.y * wi.y + wi.z * wi.z), std::atan2(wi.y, wi.z)};
        const Profile2D po{std::sqrt(wo.y * wo.y + wo.z * wo.z), std::atan2(wo.y, wo.z)};
        const double dot_io = wi.x * wo.x + wi.y * wo.y + wi.z * wo.z;

        // Cylinder arc seen from both directions.
        double lo_i, hi_i, lo_o, hi_o;
        arc(pi.beta, &lo_i, &hi_i);
        arc(po.beta, &lo_o, &hi_o);
        const double A = std::max(lo_i, lo_o), B = std::min(hi_i, hi_o);
        double diff = 0.0, spec = 0.0;
        if (B > A) {
            const double bs = pi.beta + po.beta, aa = pi.a * po.a;
            diff = 0.5 * aa *
                   ((B - A) * std::cos(pi.beta - po.beta) +
                    0.5 * (std::sin(2.0 * B - bs) - std::sin(2.0 * A - bs)));
            spec = spec_integral(pi, po, wi, wo, dot_io, A, B);
        }

        // Flat ground between the cylinders, seen from both.
        const double ground = ground_length(pi.beta, po.beta);
        const double zz = wi.z * wo.z;
        const double flat_lobe = lobe(wi.z * wo.z - wi.x * wo.x - wi.y * wo.y);
        const double kd = (diff + ground * zz) / (kPi * d_ * zz);
        const double ks = (n_ + 2.0) / (2.0 * kPi) * (spec + ground * zz * flat_lobe) / (d_ * zz);
        return rd_ * kd + rs_ * ks;
    }

  private:
    double lobe(double c) const {
        double r[1] = {c}, l[1];
        lobes<1>(r, l);
        return l[0];
    }
    // max(0, min(c, 1))^n for a panel's nodes at once. Integer exponents (the default 20) by
    // squaring, the nodes' chains side by side: pow was a quarter of the sampling bench's
    // table 1; squaring rounds <= 2 log2(n) times (~1e-15 relative).
    template <int N = kGL>
    void lobes(const double* c, double* out) const {
        double x[N];
        for (int j = 0; j < N; ++j) x[j] = c[j] > 0.0 ? std::min(c[j], 1.0) : 0.0;
        if (n_int_ < 0) {
            for (int j = 0; j < N; ++j) out[j] = x[j] > 0.0 ? std::pow(x[j], n_) : 0.0;
            return;
        }
        for (int j = 0; j < N; ++j) out[j] = 1.0;
        for (int e = n_int_; e; e >>= 1) {
            if (e & 1)
                for (int j = 0; j < N; ++j) out[j] *= x[j];
            for (int j = 0; j < N; ++j) x[j] *= x[j];
        }
        for (int j = 0; j < N; ++j)
            if (!(c[j] > 0.0)) out[j] = 0.0;  // n = 0: 0^0 would be 1
    }

    // Visible interval of psi on a cylinder from a direction of profile angle beta.
    void arc(double beta, double* lo, double* hi) const {
        *lo = std::max(-psi_max_, beta - 0.5 * kPi);
        *hi = std::min(psi_max_, beta + 0.5 * kPi);
        const double u = d_ * std::cos(beta) - 1.0;  // >= -1 because d >= 2
        if (u < 1.0) {
            const double limit = std::asin(std::max(-1.0, u));
            if (beta > 0.0) *hi = std::min(*hi, beta + limit);
            if (beta < 0.0) *lo = std::max(*lo, beta - limit);
        }
    }

    // Interval of ground points y0 (ground spans [c, d - c]) hidden by the cylinder centred
    // at (cx, h) from profile angle beta; empty when lo >= hi. A ray from (y0, 0) along
    // (sin beta, cos beta) hits the circle iff |cross| < 1 and it lies ahead (dot > 0).
    void ground_shadow(double cx, double beta, double* lo, double* hi) const {
        const double sb = std::sin(beta), cb = std::cos(beta);
        // X = cx - y0: cross = X cb - h sb in (-1, 1); dot = X sb + h cb > 0.
        double xlo = (h_ * sb - 1.0) / cb, xhi = (h_ * sb + 1.0) / cb;
        if (sb > 0.0) {
            xlo = std::max(xlo, -h_ * cb / sb);
        } else if (sb < 0.0) {
            xhi = std::min(xhi, -h_ * cb / sb);
        } else if (h_ <= 0.0) {
            xhi = xlo;  // straight up: only an overhang (h > 0) hides ground
        }
        *lo = cx - xhi;
        *hi = cx - xlo;
    }

    double ground_length(double beta_i, double beta_o) const {
        const double g0 = c_, g1 = d_ - c_;
        if (g1 <= g0) return 0.0;
        std::pair<double, double> iv[4];
        ground_shadow(0.0, beta_i, &iv[0].first, &iv[0].second);
        ground_shadow(d_, beta_i, &iv[1].first, &iv[1].second);
        ground_shadow(0.0, beta_o, &iv[2].first, &iv[2].second);
        ground_shadow(d_, beta_o, &iv[3].first, &iv[3].second);
        for (auto& v : iv) {
            v.first = std::clamp(v.first, g0, g1);
            v.second = std::clamp(v.second, g0, g1);
        }
        std::sort(iv, iv + 4);
        double hidden = 0.0, end = g0;
        for (const auto& v : iv) {
            if (v.second <= v.first) continue;
            const double start = std::max(v.first, end);
            if (v.second > start) hidden += v.second - start;
            end = std::max(end, v.second);
        }
        return std::max(0.0, (g1 - g0) - hidden);
    }

    // Integral over psi in [A, B] of (m.wi)(m.wo) max(0, 2 (m.wi)(m.wo) - wi.wo)^n.
    double spec_integral(const Profile2D& pi, const Profile2D& po, const dvec3& wi, const dvec3& wo,
                         double dot_io, double A, double B) const {
        const double aa = pi.a * po.a, xx = wi.x * wo.x;
        const double peak = aa - xx;  // the largest r_m.wo over psi
        if (!(peak > 0.0) || !(aa > 0.0)) return 0.0;
        const double centre = 0.5 * (pi.beta + po.beta);
        // Support: cos(2 (psi - centre)) > xx / aa.
        const double kappa = xx / aa;
        const double support = kappa <= -1.0 ? 0.5 * kPi : 0.5 * std::acos(std::min(kappa, 1.0));
        // Where the lobe falls to 1/e: 2 aa sin^2(delta) = peak / n.
        const double width = std::min(
            support, std::asin(std::sqrt(std::min(1.0, peak / (2.0 * aa * std::max(n_, 1.0))))));
        const double lo = std::max(A, centre - support), hi = std::min(B, centre + support);
        if (!(hi > lo) || !(width > 0.0)) return 0.0;

        // Panel edges: centre +- width * 3^k up to the support, clipped to [lo, hi].
        double edges[64];
        int ne = 0;
        edges[ne++] = lo;
        edges[ne++] = hi;
        if (centre > lo && centre < hi) edges[ne++] = centre;
        for (double r = width; ne < 60; r *= 3.0) {
            const double rr = std::min(r, support);
            for (double e : {centre - rr, centre + rr})
                if (e > lo && e < hi) edges[ne++] = e;
            if (rr >= support) break;
        }
        std::sort(edges, edges + ne);

        // With t = psi - centre, (m.wi)(m.wo) = aa (cos(beta_i - beta_o) + cos 2t) / 2, so the
        // lobe's argument 2 (m.wi)(m.wo) - wi.wo is peak - 2 aa sin^2 t and
        // (m.wi)(m.wo) = (that + wi.wo) / 2: symmetric in (wi, wo). The nodes' sines by angle
        // addition from the panel's middle (the nodes pair up as mid +- half x_j).
        double sum = 0.0;
        for (int k = 0; k + 1 < ne; ++k) {
            const double a = edges[k], b = edges[k + 1];
            if (!(b > a)) continue;
            // The lobe falls away from the centre: a panel whose nearest edge has none
            // has none anywhere (exactly 0: skipping it changes no bit).
            const double near = a >= centre ? a - centre : b <= centre ? centre - b : 0.0;
            const double sn = std::sin(near);
            if (lobe(peak - 2.0 * aa * sn * sn) == 0.0) continue;
            const double half = 0.5 * (b - a), mid = 0.5 * (a + b) - centre;
            const double sm = std::sin(mid), cm = std::cos(mid);
            double r[kGL];
            for (int j = 0; j < kGL / 2; ++j) {
                const double sx = std::sin(half * gx_[j]), cx = std::cos(half * gx_[j]);
                const double s1 = sm * cx + cm * sx, s2 = sm * cx - cm * sx;  // +x_j, -x_j
                r[j] = peak - 2.0 * aa * s1 * s1;
                r[kGL - 1 - j] = peak - 2.0 * aa * s2 * s2;
            }
            double l[kGL];
            lobes(r, l);
            double s = 0.0;
            for (int j = 0; j < kGL; ++j) s += gw_[j] * 0.5 * (r[j] + dot_io) * l[j];
            sum += half * s;
        }
        return sum;
    }

    double d_, h_, n_;
    dvec3 rs_, rd_;
    double psi_max_ = 0.0, c_ = 0.0;
    int n_int_ = -1;  // n when it is a small integer (lobe by squaring), else -1
    double gx_[kGL], gw_[kGL];
};

}  // namespace

const ModelCode kPoulinFournierModel = {"poulin-fournier", make_model<PoulinFournier>};

}  // namespace sepal
