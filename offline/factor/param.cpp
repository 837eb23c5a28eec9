#include "factor/param.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace sepal {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Below this sin(theta) an azimuth is not defined (see param.h, "Degenerate frames").
constexpr double kPoleSin = 1e-12;

struct NamedParam {
    Param p;
    const char* name;
};
constexpr NamedParam kParams[] = {{Param::IncidentView, "iv"},
                                  {Param::GsHalf, "gs-half"},
                                  {Param::ViewHalf, "vh"},
                                  {Param::Rusinkiewicz, "rusinkiewicz"},
                                  {Param::ElevAzim, "elev-azim"},
                                  {Param::Axis, "axis"},
                                  {Param::GsMirror, "gs-mirror"}};

glm::dvec3 rotate_z(const glm::dvec3& v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {v.x * c - v.y * s, v.x * s + v.y * c, v.z};
}
glm::dvec3 rotate_y(const glm::dvec3& v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {v.x * c + v.z * s, v.y, -v.x * s + v.z * c};
}

// Angle in [0, 2 pi); 0 at the pole (param.h, "Degenerate frames").
double azimuth(const glm::dvec3& a) {
    if (a.x * a.x + a.y * a.y <= kPoleSin * kPoleSin) return 0.0;
    double phi = std::atan2(a.y, a.x);
    if (phi < 0) phi += 2 * kPi;
    // atan2 of a tiny negative y gives -tiny, and -tiny + 2 pi may round to 2 pi itself.
    return phi < 2 * kPi ? phi : 0.0;
}

// axis: latitude out of the cross-section plane and longitude within it (param.h).
// asin(w.x) for a unit w, written as atan2 so it keeps full precision near the poles w = +-t.
double axis_alpha(const glm::dvec3& w) { return std::atan2(w.x, std::sqrt(w.y * w.y + w.z * w.z)); }
double axis_beta(const glm::dvec3& w) {
    if (w.y == 0 && w.z == 0) return 0.0;  // w = +-t: no longitude (param.h)
    return std::atan2(w.y, w.z);
}
glm::dvec3 axis_direction(double alpha, double beta) {
    const double ca = std::cos(alpha);
    return {std::sin(alpha), ca * std::sin(beta), ca * std::cos(beta)};
}

// gs-mirror's r: wi reflected about the normal (an involution: mirror(mirror(w)) = w).
glm::dvec3 mirror(const glm::dvec3& w) { return {-w.x, -w.y, w.z}; }

glm::dvec3 difference_rusinkiewicz(const glm::dvec3& h, const glm::dvec3& wi) {
    const double theta_h = std::acos(glm::clamp(h.z, -1.0, 1.0));
    return rotate_y(rotate_z(wi, -rusinkiewicz_phi_h(h)), -theta_h);
}
}  // namespace

bool gs_half_frame(const glm::dvec3& h, glm::dvec3* tp, glm::dvec3* sp) {
    // t - (h.t) h = (1 - hx^2, -hx hy, -hx hz) = (hy^2 + hz^2, -hx hy, -hx hz) for a unit h,
    // of length r = sqrt(hy^2 + hz^2): written that way it keeps full precision as h nears
    // t, where 1 - hx^2 would cancel.
    const double r2 = h.y * h.y + h.z * h.z;
    const double r = std::sqrt(r2);
    if (r > kPoleSin) {
        *tp = glm::dvec3(r2, -h.x * h.y, -h.x * h.z) / r;
        *tp = glm::normalize(*tp);  // |h| = 1 up to rounding: renormalize the rounding away
        *sp = glm::cross(h, *tp);
        return true;
    }
    // h = +-t: t' from s instead, as the runtime does (runtime/src/param.cpp).
    *tp = glm::normalize(glm::dvec3(-h.y * h.x, 1 - h.y * h.y, -h.y * h.z));
    *sp = glm::cross(h, *tp);
    return false;
}

double rusinkiewicz_phi_h(const glm::dvec3& h, bool* fallback) {
    const bool pole = h.x * h.x + h.y * h.y <= kPoleSin * kPoleSin;
    if (fallback) *fallback = pole;
    return pole ? 0.0 : std::atan2(h.y, h.x);
}

bool frame_fallback(Param p, const glm::dvec3& point) {
    if (p == Param::GsHalf || p == Param::GsMirror) {
        glm::dvec3 tp, sp;
        return !gs_half_frame(point, &tp, &sp);
    }
    if (p == Param::Rusinkiewicz) {
        bool pole = false;
        rusinkiewicz_phi_h(point, &pole);
        return pole;
    }
    return false;
}

const char* param_name(Param p) {
    for (const NamedParam& n : kParams)
        if (n.p == p) return n.name;
    return "?";
}

bool parse_param(const std::string& name, Param* p) {
    for (const NamedParam& n : kParams)
        if (name == n.name) {
            *p = n.p;
            return true;
        }
    return false;
}

const char* map_name(HemiMap m) { return m == HemiMap::XY ? "xy" : "parabolic"; }

bool parse_map(const std::string& name, HemiMap* m) {
    if (name == "xy") *m = HemiMap::XY;
    else if (name == "parabolic") *m = HemiMap::Parabolic;
    else return false;
    return true;
}

bool hardware_compatible(Param p) {
    return p == Param::IncidentView || p == Param::GsHalf || p == Param::ViewHalf || p == Param::Axis ||
           p == Param::GsMirror;
}

bool angle_textures(Param p) { return p == Param::ElevAzim || p == Param::Axis; }

int half_angle_factor(Param p) {
    switch (p) {
        case Param::GsHalf:
        case Param::Rusinkiewicz: return 0;
        case Param::ViewHalf: return 1;
        default: return -1;
    }
}

int sharp_factor(Param p) { return p == Param::Axis ? 0 : p == Param::GsMirror ? 1 : half_angle_factor(p); }

bool factor_wraps(Param p, int which) { return p == Param::ElevAzim && which == 1; }

glm::dvec2 map_forward(HemiMap m, const glm::dvec3& a) {
    if (m == HemiMap::XY) return {(a.x + 1) * 0.5, (a.y + 1) * 0.5};
    const double d = 1 + a.z;
    return {(a.x / d + 1) * 0.5, (a.y / d + 1) * 0.5};
}

bool map_inverse(HemiMap m, const glm::dvec2& uv, glm::dvec3* a) {
    const double x = 2 * uv.x - 1, y = 2 * uv.y - 1;
    const double r2 = x * x + y * y;
    if (!(r2 < 1)) return false;
    if (m == HemiMap::XY) {
        *a = {x, y, std::sqrt(1 - r2)};
    } else {
        const double k = 1 / (1 + r2);
        *a = {2 * x * k, 2 * y * k, (1 - r2) * k};
    }
    return true;
}

bool param_forward(Param p, HemiMap m, const glm::dvec3& wi, const glm::dvec3& wo,
                   TexCoords* tc) {
    if (!(wi.z > 0) || !(wo.z > 0)) return false;  // also NaN
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(wi[c]) || !std::isfinite(wo[c])) return false;
    switch (p) {
        case Param::IncidentView:
            tc->x = map_forward(m, wi);
            tc->y = map_forward(m, wo);
            return true;
        case Param::GsHalf: {
            const glm::dvec3 h = glm::normalize(wi + wo);
            glm::dvec3 tp, sp;
            gs_half_frame(h, &tp, &sp);
            tc->x = map_forward(m, h);
            tc->y = map_forward(m, {glm::dot(wi, tp), glm::dot(wi, sp), glm::dot(wi, h)});
            return true;
        }
        case Param::ViewHalf: {
            const glm::dvec3 h = glm::normalize(wi + wo);
            tc->x = map_forward(m, wo);
            tc->y = map_forward(m, h);
            return true;
        }
        case Param::Rusinkiewicz: {
            const glm::dvec3 h = glm::normalize(wi + wo);
            tc->x = map_forward(m, h);
            tc->y = map_forward(m, difference_rusinkiewicz(h, wi));
            return true;
        }
        case Param::ElevAzim: {
            const double ti = std::acos(glm::clamp(wi.z, -1.0, 1.0));
            const double to = std::acos(glm::clamp(wo.z, -1.0, 1.0));
            tc->x = {ti / (0.5 * kPi), to / (0.5 * kPi)};
            tc->y = {azimuth(wi) / (2 * kPi), azimuth(wo) / (2 * kPi)};
            return true;
        }
        case Param::Axis:
            tc->x = {axis_alpha(wi) / kPi + 0.5, axis_alpha(wo) / kPi + 0.5};
            tc->y = {axis_beta(wi) / kPi + 0.5, axis_beta(wo) / kPi + 0.5};
            return true;
        case Param::GsMirror: {
            const glm::dvec3 r = mirror(wi);
            glm::dvec3 tp, sp;
            gs_half_frame(r, &tp, &sp);
            tc->x = map_forward(m, r);
            glm::dvec3 d(glm::dot(wo, tp), glm::dot(wo, sp), glm::dot(wo, r));
            if (d.z < 0) {  // behind r's horizon: to the rim (param.h)
                const double l = std::sqrt(d.x * d.x + d.y * d.y);
                d = l > 1e-12 ? glm::dvec3(d.x / l, d.y / l, 0.0) : glm::dvec3(1, 0, 0);
            }
            tc->y = map_forward(m, d);
            return true;
        }
    }
    return false;
}

bool factor_point(Param p, HemiMap m, int which, const glm::dvec2& uv, glm::dvec3* point) {
    if (p == Param::ElevAzim) {
        if (!(uv.x >= 0 && uv.x <= 1 && uv.y >= 0 && uv.y <= 1)) return false;
        const double scale = which == 0 ? 0.5 * kPi : 2 * kPi;
        *point = {uv.x * scale, uv.y * scale, 0};
        return true;
    }
    if (p == Param::Axis) {
        if (!(uv.x >= 0 && uv.x <= 1 && uv.y >= 0 && uv.y <= 1)) return false;
        *point = {(uv.x - 0.5) * kPi, (uv.y - 0.5) * kPi, 0};  // (alpha_i, alpha_o) or (beta_i, beta_o)
        return true;
    }
    return map_inverse(m, uv, point);
}

bool combine_points(Param p, const glm::dvec3& px, const glm::dvec3& py, glm::dvec3* wi,
                    glm::dvec3* wo) {
    switch (p) {
        case Param::IncidentView:
            *wi = px;
            *wo = py;
            break;
        case Param::GsHalf: {
            glm::dvec3 tp, sp;
            gs_half_frame(px, &tp, &sp);
            *wi = py.x * tp + py.y * sp + py.z * px;
            *wo = 2 * glm::dot(*wi, px) * px - *wi;
            break;
        }
        case Param::ViewHalf: {
            const double c = glm::dot(px, py);
            if (!(c > 0)) return false;  // h must bisect wi and wo
            *wo = px;
            *wi = 2 * c * py - px;
            break;
        }
        case Param::Rusinkiewicz: {
            const double theta_h = std::acos(glm::clamp(px.z, -1.0, 1.0));
            *wi = rotate_z(rotate_y(py, theta_h), rusinkiewicz_phi_h(px));
            *wo = 2 * glm::dot(*wi, px) * px - *wi;
            break;
        }
        case Param::ElevAzim: {
            const double si = std::sin(px.x), so = std::sin(px.y);
            *wi = {si * std::cos(py.x), si * std::sin(py.x), std::cos(px.x)};
            *wo = {so * std::cos(py.y), so * std::sin(py.y), std::cos(px.y)};
            break;
        }
        case Param::Axis:
            *wi = axis_direction(px.x, py.x);
            *wo = axis_direction(px.y, py.y);
            break;
        case Param::GsMirror: {
            glm::dvec3 tp, sp;
            gs_half_frame(px, &tp, &sp);
            *wo = py.x * tp + py.y * sp + py.z * px;
            *wi = mirror(px);
            break;
        }
    }
    // Renormalize against rounding: evaluators expect unit vectors.
    *wi = glm::normalize(*wi);
    *wo = glm::normalize(*wo);
    return wi->z > 0 && wo->z > 0;
}

std::vector<uint8_t> valid_texels(Param p, HemiMap m, int which, int n) {
    std::vector<uint8_t> valid(size_t(n) * n, 0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            glm::dvec3 point;
            valid[size_t(j) * n + i] =
                factor_point(p, m, which, {(i + 0.5) / n, (j + 0.5) / n}, &point) ? 1 : 0;
        }
    return valid;
}

}  // namespace sepal
