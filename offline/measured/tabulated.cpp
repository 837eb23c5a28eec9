#include "measured/tabulated.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace sepal {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfPi = kPi / 2;

// rotate_z / rotate_y by angle a (right-handed, as the Rodrigues formula of MERL's reader).
glm::dvec3 rotate_z(const glm::dvec3& v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return glm::dvec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
}
glm::dvec3 rotate_y(const glm::dvec3& v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return glm::dvec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}

double safe_acos(double x) { return std::acos(std::max(-1.0, std::min(1.0, x))); }

// int(u) clamped to [0, n-1]; NaN goes to 0 (int(NaN) would be undefined).
int clamp_index(double u, int n) {
    if (!(u >= 0.0)) return 0;
    if (u >= double(n)) return n - 1;
    return std::min(int(u), n - 1);
}

// phi_d folded as MERL does: a negative phi_d gets pi added (values outside [-pi, pi] are
// first brought into it), giving [0, pi].
// 0..1 along the theta_h axis.
double theta_h_unit_of(double theta_h, ThetaHMapping mapping) {
    if (!(theta_h > 0.0)) return 0.0;  // MERL: index 0 when theta_h <= 0 (and for NaN)
    const double u = theta_h / kHalfPi;
    return mapping == ThetaHMapping::kSqrt ? std::sqrt(u) : u;
}

double fold_phi_d(double pd) {
    if (!std::isfinite(pd)) return 0.0;
    if (pd < -kPi || pd > kPi) pd = std::fmod(pd, kPi);
    if (pd < 0.0) pd += kPi;
    return pd;
}

// The two neighbours and the fraction of continuous coordinate c along an axis of n cells.
void axis_corners(double c, int n, bool periodic, int* lo, int* hi, double* t) {
    if (n == 1) {
        *lo = *hi = 0;
        *t = 0.0;
        return;
    }
    if (periodic) {
        const double f = std::floor(c);
        *t = c - f;
        int i = int(f) % n;
        if (i < 0) i += n;
        *lo = i;
        *hi = (i + 1) % n;
        return;
    }
    c = std::max(0.0, std::min(double(n - 1), c));
    int i = std::min(int(c), n - 2);
    *lo = i;
    *hi = i + 1;
    *t = c - i;
}

}  // namespace

HalfDiff to_half_diff(const glm::dvec3& wi, const glm::dvec3& wo) {
    HalfDiff a;
    glm::dvec3 h = wi + wo;
    const double len = glm::length(h);
    h = len > 0.0 ? h / len : glm::dvec3(0, 0, 1);
    a.theta_h = safe_acos(h.z);
    const double phi_h = std::atan2(h.y, h.x);
    const glm::dvec3 d = rotate_y(rotate_z(wi, -phi_h), -a.theta_h);
    a.theta_d = safe_acos(d.z);
    a.phi_d = std::atan2(d.y, d.x);
    return a;
}

void from_half_diff(const HalfDiff& a, glm::dvec3* wi, glm::dvec3* wo) {
    const double st = std::sin(a.theta_d);
    const glm::dvec3 d(st * std::cos(a.phi_d), st * std::sin(a.phi_d), std::cos(a.theta_d));
    const glm::dvec3 h(std::sin(a.theta_h), 0.0, std::cos(a.theta_h));
    *wi = rotate_y(d, a.theta_h);
    *wo = 2.0 * glm::dot(*wi, h) * h - *wi;
}

bool Tabulated::init(int nh, int nd, int np, ThetaHMapping mapping, std::string* err) {
    const int n[3] = {nh, nd, np};
    for (int k = 0; k < 3; ++k) {
        if (n[k] < 1 || n[k] > kMaxDim) {
            if (err)
                *err = "table dimension " + std::to_string(n[k]) + " is outside 1.." +
                       std::to_string(kMaxDim);
            return false;
        }
    }
    const size_t cells = size_t(nh) * size_t(nd) * size_t(np);
    if (cells > kMaxCells) {
        if (err)
            *err = "table of " + std::to_string(cells) + " cells is over the limit of " +
                   std::to_string(kMaxCells);
        return false;
    }
    for (int k = 0; k < 3; ++k) n_[k] = n[k];
    mapping_ = mapping;
    val_.assign(3 * cells, 0.0f);
    conf_.assign(cells, 0.0f);
    state_.assign(cells, State::kMissing);
    acc_.clear();
    hit_.clear();
    occupied_ = 0;
    rejected_ = 0;
    return true;
}

Tabulated Tabulated::merl() {
    Tabulated t;
    t.init(90, 90, 180, ThetaHMapping::kSqrt, nullptr);
    return t;
}

double Tabulated::theta_h_unit(double theta_h) const { return theta_h_unit_of(theta_h, mapping_); }

size_t Tabulated::cell_index(const HalfDiff& a) const { return table_cell_index(n_[0], n_[1], n_[2], mapping_, a); }

size_t table_cell_index(int n_theta_h, int n_theta_d, int n_phi_d, ThetaHMapping mapping, const HalfDiff& a) {
    const int ih = clamp_index(theta_h_unit_of(a.theta_h, mapping) * n_theta_h, n_theta_h);
    const int id = clamp_index(a.theta_d / kHalfPi * n_theta_d, n_theta_d);
    const int ip = clamp_index(fold_phi_d(a.phi_d) / kPi * n_phi_d, n_phi_d);
    return size_t(ip) + size_t(n_phi_d) * (size_t(id) + size_t(n_theta_d) * size_t(ih));
}

HalfDiff table_cell_center(int n_theta_h, int n_theta_d, int n_phi_d, ThetaHMapping mapping,
                           size_t i) {
    const int ip = int(i % size_t(n_phi_d));
    const int id = int((i / size_t(n_phi_d)) % size_t(n_theta_d));
    const int ih = int(i / (size_t(n_phi_d) * size_t(n_theta_d)));
    HalfDiff a;
    const double uh = (ih + 0.5) / n_theta_h;
    a.theta_h = (mapping == ThetaHMapping::kSqrt ? uh * uh : uh) * kHalfPi;
    a.theta_d = (id + 0.5) / n_theta_d * kHalfPi;
    a.phi_d = (ip + 0.5) / n_phi_d * kPi;
    return a;
}

HalfDiff Tabulated::cell_center(size_t i) const {
    return table_cell_center(n_[0], n_[1], n_[2], mapping_, i);
}

void Tabulated::coords(const HalfDiff& a, double c[3]) const {
    // Cell centres sit at integer coordinates: bin k covers [k - 0.5, k + 0.5).
    c[0] = theta_h_unit(a.theta_h) * n_[0] - 0.5;
    c[1] = (std::isfinite(a.theta_d) ? a.theta_d : 0.0) / kHalfPi * n_[1] - 0.5;
    c[2] = fold_phi_d(a.phi_d) / kPi * n_[2] - 0.5;
}

void Tabulated::set(size_t i, const glm::dvec3& v, float confidence, State s) {
    // A value that is not finite as a float would poison every lookup that blends it in:
    // the cell stays missing instead, counted.
    const double limit = double(std::numeric_limits<float>::max());
    for (int c = 0; c < 3; ++c)
        if (!(std::fabs(v[c]) <= limit)) {  // also NaN
            ++rejected_;
            set_missing(i);
            return;
        }
    val_[3 * i] = float(v.x);
    val_[3 * i + 1] = float(v.y);
    val_[3 * i + 2] = float(v.z);
    conf_[i] = confidence;
    state_[i] = s;
}

void Tabulated::set_missing(size_t i) {
    val_[3 * i] = val_[3 * i + 1] = val_[3 * i + 2] = 0.0f;
    conf_[i] = 0.0f;
    state_[i] = State::kMissing;
}

void Tabulated::corners(const HalfDiff& a, size_t cells[8], double weights[8]) const {
    double c[3];
    coords(a, c);
    int lo[3], hi[3];
    double t[3];
    for (int k = 0; k < 3; ++k) axis_corners(c[k], n_[k], k == 2, &lo[k], &hi[k], &t[k]);
    for (int corner = 0; corner < 8; ++corner) {
        int idx[3];
        double w = 1.0;
        for (int k = 0; k < 3; ++k) {
            const bool up = (corner >> k) & 1;
            idx[k] = up ? hi[k] : lo[k];
            w *= up ? t[k] : 1.0 - t[k];
        }
        cells[corner] = index(idx[0], idx[1], idx[2]);
        weights[corner] = w;
    }
}

bool Tabulated::trilinear(const HalfDiff& a, glm::dvec3* out) const {
    if (state_.empty()) return false;
    size_t cells[8];
    double ws[8];
    corners(a, cells, ws);
    glm::dvec3 sum(0.0);
    double wsum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        const size_t i = cells[corner];
        const double w = ws[corner];
        if (w <= 0.0 || !usable(i)) continue;  // missing corners are skipped, not zero
        sum += w * value(i);
        wsum += w;
    }
    if (wsum <= 0.0) {
        // Every corner with weight is missing (or the point is exactly on a missing cell
        // centre): fall back to the nearest usable cell of the block.
        return nearest(a, out);
    }
    *out = sum / wsum;
    return true;
}

bool Tabulated::nearest(const HalfDiff& a, glm::dvec3* out) const {
    if (state_.empty()) return false;
    const size_t home = cell_index(a);
    if (usable(home)) {
        *out = value(home);
        return true;
    }
    size_t cells[8];
    double ws[8];
    corners(a, cells, ws);
    double best_w = -1.0;
    size_t best = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const size_t i = cells[corner];
        const double w = ws[corner];
        if (usable(i) && w > best_w) {
            best_w = w;
            best = i;
        }
    }
    if (best_w < 0.0) return false;
    *out = value(best);
    return true;
}

glm::dvec3 Tabulated::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    // Written so that NaN directions also return 0.
    if (!(wi.z > 0.0 && wo.z > 0.0)) return glm::dvec3(0.0);
    glm::dvec3 v;
    if (!trilinear(to_half_diff(wi, wo), &v)) return glm::dvec3(0.0);
    return v;
}

void Tabulated::splat(const HalfDiff& a, const glm::dvec3& v, double weight, Kernel kernel) {
    if (state_.empty() || !(weight > 0.0)) return;
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
        !std::isfinite(weight)) {
        ++rejected_;  // dropped, counted: it would poison the cell's weighted mean
        return;
    }
    if (acc_.empty()) {
        acc_.assign(4 * size(), 0.0);
        hit_.assign(size(), 0);
    }
    const size_t home = cell_index(a);
    hit_[home] = 1;
    if (kernel == Kernel::kNearest) {
        double* s = &acc_[4 * home];
        s[0] += weight;
        s[1] += weight * v.x;
        s[2] += weight * v.y;
        s[3] += weight * v.z;
        return;
    }
    size_t cells[8];
    double ws[8];
    corners(a, cells, ws);
    for (int corner = 0; corner < 8; ++corner) {
        const double w = weight * ws[corner];
        if (w <= 0.0) continue;
        double* s = &acc_[4 * cells[corner]];
        s[0] += w;
        s[1] += w * v.x;
        s[2] += w * v.y;
        s[3] += w * v.z;
    }
}

void Tabulated::finish_splats() {
    if (acc_.empty()) return;
    occupied_ = 0;
    for (size_t i = 0; i < size(); ++i) {
        occupied_ += hit_[i];
        const double* s = &acc_[4 * i];
        if (s[0] <= 0.0) continue;
        set(i, glm::dvec3(s[1], s[2], s[3]) / s[0], float(std::min(1.0, s[0])),
            State::kMeasured);
    }
    acc_.clear();
    acc_.shrink_to_fit();
    hit_.clear();
    hit_.shrink_to_fit();
}

size_t Tabulated::fill_missing(FillDomain domain) {
    const bool log1p = domain == FillDomain::kLog1p;
    // One pyramid level: weights w (unclamped sums, as Gortler's pull) and values x.
    struct Level {
        int n[3];
        bool periodic;  // phi_d wraps exactly: every level above halved an even size
        std::vector<float> w, x;
        size_t at(int i, int j, int k) const {
            return size_t(k) + size_t(n[2]) * (size_t(j) + size_t(n[1]) * size_t(i));
        }
    };
    std::vector<Level> levels(1);
    Level& base = levels[0];
    for (int k = 0; k < 3; ++k) base.n[k] = n_[k];
    base.periodic = true;
    base.w.assign(size(), 0.0f);
    base.x.assign(3 * size(), 0.0f);
    bool any = false;
    for (size_t i = 0; i < size(); ++i) {
        if (state_[i] != State::kMeasured) continue;
        base.w[i] = conf_[i];
        for (int c = 0; c < 3; ++c) {
            const float v = val_[3 * i + c];
            base.x[3 * i + c] = log1p ? std::log1p(std::max(0.0f, v)) : v;
        }
        any = any || conf_[i] > 0.0f;
    }
    if (!any) return 0;

    // Pull: box filter over the 2x2x2 children, each weighted by its confidence clamped to 1.
    while (levels.back().n[0] > 1 || levels.back().n[1] > 1 || levels.back().n[2] > 1) {
        const Level& f = levels.back();
        Level g;
        for (int k = 0; k < 3; ++k) g.n[k] = (f.n[k] + 1) / 2;
        g.periodic = f.periodic && f.n[2] % 2 == 0;
        const size_t cells = size_t(g.n[0]) * g.n[1] * g.n[2];
        g.w.assign(cells, 0.0f);
        g.x.assign(3 * cells, 0.0f);
        for (int i = 0; i < g.n[0]; ++i)
            for (int j = 0; j < g.n[1]; ++j)
                for (int k = 0; k < g.n[2]; ++k) {
                    double w = 0.0, x[3] = {0, 0, 0};
                    for (int di = 0; di < 2; ++di)
                        for (int dj = 0; dj < 2; ++dj)
                            for (int dk = 0; dk < 2; ++dk) {
                                const int fi = 2 * i + di, fj = 2 * j + dj, fk = 2 * k + dk;
                                if (fi >= f.n[0] || fj >= f.n[1] || fk >= f.n[2]) continue;
                                const size_t s = f.at(fi, fj, fk);
                                const double cw = std::min(1.0f, f.w[s]);
                                if (cw <= 0.0) continue;
                                w += cw;
                                for (int c = 0; c < 3; ++c) x[c] += cw * f.x[3 * s + c];
                            }
                    const size_t d = g.at(i, j, k);
                    g.w[d] = float(w);
                    for (int c = 0; c < 3; ++c) g.x[3 * d + c] = w > 0 ? float(x[c] / w) : 0.0f;
                }
        levels.push_back(std::move(g));
    }

    // Push: from the coarsest level down, a cell with confidence w < 1 becomes
    // w x + (1 - w) x_coarse, x_coarse interpolated trilinearly from the level above with
    // weights times that level's (clamped) confidence.
    Level& top = levels.back();
    for (float& w : top.w) w = std::min(1.0f, w);
    for (size_t L = levels.size() - 1; L-- > 0;) {
        Level& f = levels[L];
        const Level& g = levels[L + 1];
        for (int i = 0; i < f.n[0]; ++i)
            for (int j = 0; j < f.n[1]; ++j)
                for (int k = 0; k < f.n[2]; ++k) {
                    const size_t s = f.at(i, j, k);
                    const double w = std::min(1.0f, f.w[s]);
                    if (w >= 1.0) {
                        f.w[s] = 1.0f;
                        continue;
                    }
                    // Fine centre i sits at coarse coordinate (i + 0.5)/2 - 0.5.
                    const int fi[3] = {i, j, k};
                    int lo[3], hi[3];
                    double t[3];
                    for (int a = 0; a < 3; ++a)
                        axis_corners(0.5 * fi[a] - 0.25, g.n[a], a == 2 && g.periodic, &lo[a],
                                     &hi[a], &t[a]);
                    double tw = 0.0, tx[3] = {0, 0, 0};
                    for (int corner = 0; corner < 8; ++corner) {
                        int idx[3];
                        double h = 1.0;
                        for (int a = 0; a < 3; ++a) {
                            const bool up = (corner >> a) & 1;
                            idx[a] = up ? hi[a] : lo[a];
                            h *= up ? t[a] : 1.0 - t[a];
                        }
                        const size_t gi = g.at(idx[0], idx[1], idx[2]);
                        const double hw = h * g.w[gi];
                        if (hw <= 0.0) continue;
                        tw += hw;
                        for (int c = 0; c < 3; ++c) tx[c] += hw * g.x[3 * gi + c];
                    }
                    if (tw <= 0.0) {
                        f.w[s] = float(w);
                        continue;
                    }
                    for (int c = 0; c < 3; ++c)
                        f.x[3 * s + c] = float(w * f.x[3 * s + c] + (1.0 - w) * tx[c] / tw);
                    f.w[s] = float(w + (1.0 - w) * std::min(1.0, tw));
                }
    }

    const Level& result = levels[0];  // `base` dangles: levels grew since
    size_t filled = 0;
    for (size_t i = 0; i < size(); ++i) {
        if (result.w[i] <= 0.0f) continue;
        glm::dvec3 v(result.x[3 * i], result.x[3 * i + 1], result.x[3 * i + 2]);
        if (log1p) v = glm::dvec3(std::expm1(v.x), std::expm1(v.y), std::expm1(v.z));
        if (state_[i] == State::kMeasured) {
            if (conf_[i] < 1.0f) set(i, v, conf_[i], State::kMeasured);
        } else {
            set(i, v, 0.0f, State::kFilled);
            ++filled;
        }
    }
    return filled;
}

Tabulated::Counts Tabulated::counts() const {
    Counts c;
    for (State s : state_) {
        if (s == State::kMeasured)
            ++c.measured;
        else if (s == State::kFilled)
            ++c.filled;
        else
            ++c.missing;
    }
    c.occupied = occupied_;
    return c;
}

}  // namespace sepal
