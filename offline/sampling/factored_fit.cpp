#include "sampling/factored_fit.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>

#include <glm/geometric.hpp>

#include "bake/radiance.h"
#include "brdf/brdf_util.h"
#include "sampling/metrics.h"
#include "sampling/nmf_kl.h"
#include "util/parallel.h"
#include "util/progress.h"

namespace sepal {

using glm::dvec3;

namespace {
// The kinds of SampleAxis (sepal_smp_axis has the definitions): about t or s, turned with the
// view (half vector only), centred on the mirror cone (incident direction only).
bool about_t(SampleAxis a) { return a == SampleAxis::Tangent || a == SampleAxis::TangentView || a == SampleAxis::TangentMirror; }
bool about_s(SampleAxis a) {
    return a == SampleAxis::Bitangent || a == SampleAxis::BitangentView || a == SampleAxis::BitangentMirror;
}
bool view_axis(SampleAxis a) { return a == SampleAxis::TangentView || a == SampleAxis::BitangentView; }
bool mirror_axis(SampleAxis a) { return a == SampleAxis::TangentMirror || a == SampleAxis::BitangentMirror; }
}  // namespace

const char* sample_param_name(SampleParam p) {
    return p == SampleParam::Half ? "half" : p == SampleParam::Incident ? "incident" : "auto";
}
bool parse_sample_param(const std::string& s, SampleParam* p) {
    if (s == "auto") *p = SampleParam::Auto;
    else if (s == "half") *p = SampleParam::Half;
    else if (s == "incident") *p = SampleParam::Incident;
    else return false;
    return true;
}
const char* phi_frame_name(PhiFrame f) {
    return f == PhiFrame::Auto ? "auto" : f == PhiFrame::Absolute ? "absolute" : "view";
}
bool parse_phi_frame(const std::string& s, PhiFrame* f) {
    if (s == "auto") *f = PhiFrame::Auto;
    else if (s == "absolute") *f = PhiFrame::Absolute;
    else if (s == "view") *f = PhiFrame::View;
    else return false;
    return true;
}

const char* sample_axis_name(SampleAxis a) {
    switch (a) {
        case SampleAxis::Normal: return "n";
        case SampleAxis::Tangent: return "t";
        case SampleAxis::Bitangent: return "s";
        case SampleAxis::TangentView: return "t-view";
        case SampleAxis::BitangentView: return "s-view";
        case SampleAxis::TangentMirror: return "t-mirror";
        case SampleAxis::BitangentMirror: return "s-mirror";
        default: return "auto";
    }
}
bool parse_sample_axis(const std::string& s, SampleAxis* a) {
    if (s == "auto") *a = SampleAxis::Auto;
    else if (s == "n") *a = SampleAxis::Normal;
    else if (s == "t") *a = SampleAxis::Tangent;
    else if (s == "s") *a = SampleAxis::Bitangent;
    else if (s == "t-view") *a = SampleAxis::TangentView;
    else if (s == "s-view") *a = SampleAxis::BitangentView;
    else if (s == "t-mirror") *a = SampleAxis::TangentMirror;
    else if (s == "s-mirror") *a = SampleAxis::BitangentMirror;
    else return false;
    return true;
}

double luminance(const dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

std::vector<float> theta_bin_z_edges(int n, bool sqrt_theta) {
    std::vector<float> z(static_cast<size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        double t = double(i) / n;
        if (sqrt_theta) t *= t;
        z[size_t(i)] = float(std::cos(t * 0.5 * kPi));
    }
    z[0] = 1.0f;
    z[size_t(n)] = 0.0f;
    // Float resolution near z = 1 is 6e-8 (theta ~ 3e-4 rad): tiny polar bins of the sqrt
    // mapping are widened to the next representable value, so the edges strictly fall (the
    // fit uses these very floats).
    for (int i = 1; i < n; ++i) z[size_t(i)] = std::min(z[size_t(i)], std::nextafter(z[size_t(i) - 1], 0.0f));
    for (int i = n - 1; i > 0 && !(z[size_t(i)] > z[size_t(i) + 1]); --i) z[size_t(i)] = std::nextafter(z[size_t(i) + 1], 1.0f);
    return z;
}

std::vector<float> axis_bin_edges(int n, bool dense) {
    std::vector<float> c(static_cast<size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        double t = 1.0 - 2.0 * i / n;
        if (dense) t *= std::fabs(t);
        c[size_t(i)] = float(std::sin(t * 0.5 * kPi));
    }
    c[0] = 1.0f;
    c[size_t(n)] = -1.0f;
    for (int i = 1; i < n; ++i) c[size_t(i)] = std::min(c[size_t(i)], std::nextafter(c[size_t(i) - 1], -2.0f));
    for (int i = n - 1; i > 0 && !(c[size_t(i)] > c[size_t(i) + 1]); --i) c[size_t(i)] = std::nextafter(c[size_t(i) + 1], 2.0f);
    return c;
}

bool validate_factored_options(const FactoredOptions& o, std::string* err) {
    auto bad = [&](const std::string& m) {
        if (err) *err = m;
        return false;
    };
    if (o.n_theta_o < 0 || o.n_theta_o > SEPAL_SMP_MAX_VIEW_SIDE || o.n_phi_o < 0 ||
        o.n_phi_o > SEPAL_SMP_MAX_VIEW_SIDE)
        return bad("view grid " + std::to_string(o.n_theta_o) + "x" + std::to_string(o.n_phi_o) +
                   ": each side 1.." + std::to_string(SEPAL_SMP_MAX_VIEW_SIDE) + " (or 0: the default)");
    if (o.n_theta_p < 0 || o.n_theta_p > SEPAL_SMP_MAX_DIR_SIDE || o.n_phi_p < 0 ||
        o.n_phi_p > SEPAL_SMP_MAX_DIR_SIDE)
        return bad("direction bins " + std::to_string(o.n_theta_p) + "x" + std::to_string(o.n_phi_p) +
                   ": each side 1.." + std::to_string(SEPAL_SMP_MAX_DIR_SIDE));
    if (o.J < 0 || o.K < 0 || (o.J == 0) != (o.K == 0) || o.J * o.K > SEPAL_SMP_MAX_TERMS)
        return bad("terms " + std::to_string(o.J) + "x" + std::to_string(o.K) + ": J, K >= 1 and J K <= " +
                   std::to_string(SEPAL_SMP_MAX_TERMS) + " (or both 0: the default)");
    if (view_axis(o.axis) && o.param == SampleParam::Incident)
        return bad(std::string("axis ") + sample_axis_name(o.axis) + " is defined for the half vector only (param half or auto)");
    if (mirror_axis(o.axis) && o.param == SampleParam::Half)
        return bad(std::string("axis ") + sample_axis_name(o.axis) + " is defined for the incident direction only (param incident or auto)");
    if (o.supersample < 1 || o.supersample > 8) return bad("supersample " + std::to_string(o.supersample) + ": 1..8");
    if (o.iterations < 0 || o.iterations > 1000000) return bad("iterations: 0 (auto) or 1..1000000");
    if (!(o.defensive >= 0 && o.defensive <= 1)) return bad("defensive share: 0..1");
    if (!(o.tolerance >= 0 && o.tolerance < 1)) return bad("tolerance: 0..1");
    // The whole matrix and its reconstruction are held (doubles), plus the colour masses.
    const double entries = double(o.n_theta_o ? o.n_theta_o : 24) * (o.n_phi_o ? o.n_phi_o : 24) *
                           std::max(o.n_theta_p, 192) * std::max(o.n_phi_p, 96);
    if (entries * (8.0 * 3 + 4.0 * 3) > 8e9)
        return bad("the data matrix (" + std::to_string(int64_t(entries)) +
                   " entries) needs over 8 GB; fewer view or direction bins (FactoredOptions n_theta_o, n_phi_o, n_theta_p, n_phi_p)");
    return true;
}

namespace {

// Masses of every wp bin for one view: lum (rows) and, optionally, the three channels.
struct ViewColumn {
    std::vector<double> lum;
    std::vector<float> rgb;  // 3 * rows
};

}  // namespace

namespace {
bool fit_one(const Brdf& brdf, const FactoredOptions& opt, const glm::dvec3& diffuse, SamplerData* out,
             FactoredReport* rep, std::string* err);
FactoredOptions with_defaults(const Brdf& brdf, FactoredOptions o);
}  // namespace

bool fit_factored(const Brdf& brdf, const FactoredOptions& opt, SamplerData* out, FactoredReport* rep,
                  std::string* err) {
    if (!validate_factored_options(opt, err)) return false;
    // The Lambert floor, once for both parameterizations: the terms fit what is above it
    // (clamped at 0 where a noisy measured cell dips below the quantile), cosine samples
    // take its share per view.
    glm::dvec3 diffuse(0.0);
    if (opt.separate_diffuse) diffuse = estimate_diffuse(brdf, 0.005, opt.threads);
    if (!(diffuse.x >= 0 && diffuse.y >= 0 && diffuse.z >= 0 && diffuse.x <= SEPAL_SMP_MAX_DIFFUSE &&
          diffuse.y <= SEPAL_SMP_MAX_DIFFUSE && diffuse.z <= SEPAL_SMP_MAX_DIFFUSE))
        diffuse = glm::dvec3(0.0);
    std::vector<FactoredOptions> candidates;
    for (SampleParam p : {SampleParam::Half, SampleParam::Incident})
        for (SampleAxis a : {SampleAxis::Normal, SampleAxis::Tangent, SampleAxis::Bitangent, SampleAxis::TangentView,
                             SampleAxis::BitangentView, SampleAxis::TangentMirror, SampleAxis::BitangentMirror}) {
            // Auto leaves out wi about fixed t or s: a specular lobe moves with wo there, and
            // J terms cannot follow it (Poulin-Fournier: relative variance 0.97 vs 0.73 in
            // h); the mirror axes hold it still. It leaves out the view axes too: in coarse
            // fits they lost to h about fixed t or s on both Ward and Poulin-Fournier. The
            // view axes are defined for the half vector only, the mirror axes for wi.
            const bool fixed_axis = a == SampleAxis::Tangent || a == SampleAxis::Bitangent;
            const bool axis_ok = (opt.axis == SampleAxis::Auto
                                      ? a == SampleAxis::Normal ||
                                            (!brdf.isotropic() && fixed_axis && p == SampleParam::Half) ||
                                            (!brdf.isotropic() && mirror_axis(a) && p == SampleParam::Incident)
                                      : a == opt.axis) &&
                                 !(view_axis(a) && p != SampleParam::Half) &&
                                 !(mirror_axis(a) && p != SampleParam::Incident);
            if ((opt.param == SampleParam::Auto || opt.param == p) && axis_ok) {
                candidates.push_back(opt);
                candidates.back().param = p, candidates.back().axis = a;
            }
        }
    if (candidates.size() == 1) return fit_one(brdf, candidates[0], diffuse, out, rep, err);
    std::string coarse_note;
    if (candidates.size() > 2) {
        // More than two (an anisotropic BRDF with the axis on auto): rank them by coarse fits
        // (half the views and bins a side, 300 iterations) and fit the winner alone; a full
        // fit about t or s is minutes of KL-NMF.
        const std::vector<glm::dvec3> views = judge_views(brdf.isotropic());
        double best_var = -1;
        size_t best = 0;
        coarse_note = "auto (coarse fits):";
        for (size_t c = 0; c < candidates.size(); ++c) {
            FactoredOptions q = with_defaults(brdf, candidates[c]);
            q.n_theta_o = std::max(1, q.n_theta_o / 2), q.n_phi_o = std::max(1, q.n_phi_o / 2);
            q.n_theta_p = std::max(1, q.n_theta_p / 2), q.n_phi_p = std::max(1, q.n_phi_p / 2);
            q.iterations = std::min(q.iterations, 300), q.supersample = std::min(q.supersample, 2);
            q.colour = false;
            SamplerData d;
            FactoredReport r;
            Sampler sc;
            if (!fit_one(brdf, q, diffuse, &d, &r, err) || !sc.build(d, err)) return false;
            const double v = relative_variance(brdf, sc.get(), views, 4096, opt.seed);
            if (best_var < 0 || v < best_var) best_var = v, best = c;
            char part[96];
            std::snprintf(part, sizeof part, " %s/%s %.4g", r.param.c_str(), r.axis.c_str(), v);
            coarse_note += part;
        }
        if (!fit_one(brdf, candidates[best], diffuse, out, rep, err)) return false;
        if (rep) rep->notes.push_back(coarse_note + " (relative variance; the lowest is fitted: " + rep->param + "/" +
                                      rep->axis + ")");
        return true;
    }
    // Every candidate; the one with the lowest estimator variance wins. (Not the lowest KL
    // of the fit: each KL is measured on its own binning, and a coarse binning of a sharp
    // lobe fits its own coarse data well.)
    const std::vector<glm::dvec3> views = judge_views(brdf.isotropic());
    std::vector<SamplerData> data(candidates.size());
    std::vector<FactoredReport> reps(candidates.size());
    size_t best = 0;
    std::string note = "auto:";
    for (size_t c = 0; c < candidates.size(); ++c) {
        Sampler sc;
        if (!fit_one(brdf, candidates[c], diffuse, &data[c], &reps[c], err) || !sc.build(data[c], err)) return false;
        reps[c].relative_variance = relative_variance(brdf, sc.get(), views, 4096, opt.seed);
        if (reps[c].relative_variance < reps[best].relative_variance) best = c;
        char part[96];
        std::snprintf(part, sizeof part, " %s/%s %.4g", reps[c].param.c_str(), reps[c].axis.c_str(),
                      reps[c].relative_variance);
        note += part;
    }
    FactoredReport& r = reps[best];
    r.notes.push_back(note + " (relative variance; the lowest wins: " + r.param + "/" + r.axis + ")");
    r.sample_seconds = r.factor_seconds = 0, r.evaluations = 0;
    for (const FactoredReport& x : reps) {
        r.sample_seconds += x.sample_seconds;
        r.factor_seconds += x.factor_seconds;
        r.evaluations += x.evaluations;
    }
    *out = std::move(data[best]);
    if (rep) *rep = std::move(r);
    return true;
}

namespace {

// S x S sub-points of every wp bin (view-frame coordinates = local coordinates for the
// columns' wo, whose phi_o is 0 in the view frame), and each bin's solid angle (dOmega =
// dc1 dc2). c2 (phi_p, or the angle about t or s) spans [c2_lo, c2_lo + c2_span) in Pp bins.
void bin_points(SampleAxis axis, const std::vector<float>& z_edges, int Pp, int S, std::vector<dvec3>* points,
                std::vector<double>* solid) {
    const int Tp = int(z_edges.size()) - 1;
    const bool polar = axis == SampleAxis::Normal;
    const double c2_lo = polar ? 0.0 : -0.5 * kPi, c2_span = polar ? 2.0 * kPi : kPi;
    points->assign(size_t(Tp) * Pp * S * S, dvec3(0.0));
    solid->assign(size_t(Tp) * Pp, 0.0);
    for (int i = 0; i < Tp; ++i)
        for (int j = 0; j < Pp; ++j) {
            const int row = i * Pp + j;
            const double z0 = z_edges[size_t(i)], z1 = z_edges[size_t(i) + 1];
            (*solid)[size_t(row)] = (z0 - z1) * c2_span / Pp;
            for (int a = 0; a < S; ++a)
                for (int b = 0; b < S; ++b) {
                    const double c1 = z0 + (a + 0.5) / S * (z1 - z0);
                    const double c2 = c2_lo + (j + (b + 0.5) / S) * c2_span / Pp;
                    const double s = std::sqrt(std::max(0.0, 1.0 - c1 * c1));
                    const double sa = s * std::sin(c2), ca = s * std::cos(c2);
                    (*points)[(size_t(row) * S + a) * S + b] = about_t(axis)   ? dvec3(c1, sa, ca)
                                                               : about_s(axis) ? dvec3(sa, c1, ca)
                                                                                               : dvec3(ca, sa, c1);
                }
        }
}

// The stored sampler's own divergence from the data (both levels, float rounding), relative
// to the data's mass: KL is invariant under a change of variables, so this compares
// parameterizations.
double stored_kl(const SamplerData& d, const Eigen::MatrixXd& Y, int L, int Tp, int Pp) {
    const int rows = int(Y.rows()), cols = int(Y.cols());
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(rows, cols);
    for (int l = 0; l < L; ++l) {
        const float* uc = &d.u_cdf[size_t(l) * (Tp + 1)];
        const float* vc = &d.v_cdf[size_t(l) * (Pp + 1)];
        for (int i = 0; i < Tp; ++i)
            for (int p = 0; p < Pp; ++p) {
                const double m = double(uc[i + 1] - uc[i]) * double(vc[p + 1] - vc[p]);
                if (m > 0)
                    for (int c = 0; c < cols; ++c) X(i * Pp + p, c) += m * d.F[size_t(l) * cols + c];
            }
    }
    const double total = Y.sum();
    return total > 0 ? kl_divergence(Y, X) / total : 0.0;
}

// The colour factors of d from the columns' RGB and the luminance Y.
void fit_colour(const std::vector<ViewColumn>& columns, const Eigen::MatrixXd& Y, int Tp, int Pp, SamplerData* out) {
    SamplerData& d = *out;
    const int rows = int(Y.rows()), cols = int(Y.cols());
    // f_c / f_lum ~= a_c(wo) b_c(theta_p) c_c(phi_p): alternating closed-form updates, each
    // the KL-optimal factor given the others with the luminance mass as exposure.
    d.colour_a.assign(size_t(3) * cols, 1.0f);
    d.colour_b.assign(size_t(3) * Tp, 1.0f);
    d.colour_c.assign(size_t(3) * Pp, 1.0f);
    for (int ch = 0; ch < 3; ++ch) {
        std::vector<double> a(static_cast<size_t>(cols), 1.0), b(static_cast<size_t>(Tp), 1.0), cc(static_cast<size_t>(Pp), 1.0);
        auto channel = [&](int c, int row) { return double(columns[size_t(c)].rgb[size_t(row) * 3 + ch]); };
        for (int pass = 0; pass < 20; ++pass) {
            std::vector<double> num(static_cast<size_t>(cols), 0.0), den(static_cast<size_t>(cols), 0.0);
            for (int c = 0; c < cols; ++c)
                for (int row = 0; row < rows; ++row) {
                    num[size_t(c)] += channel(c, row);
                    den[size_t(c)] += Y(row, c) * b[size_t(row / Pp)] * cc[size_t(row % Pp)];
                }
            for (int c = 0; c < cols; ++c) a[size_t(c)] = den[size_t(c)] > 0 ? num[size_t(c)] / den[size_t(c)] : 1.0;
            std::vector<double> nb(static_cast<size_t>(Tp), 0.0), db(static_cast<size_t>(Tp), 0.0), nc(static_cast<size_t>(Pp), 0.0), dc(static_cast<size_t>(Pp), 0.0);
            for (int c = 0; c < cols; ++c)
                for (int row = 0; row < rows; ++row) {
                    nb[size_t(row / Pp)] += channel(c, row);
                    db[size_t(row / Pp)] += Y(row, c) * a[size_t(c)] * cc[size_t(row % Pp)];
                }
            for (int i = 0; i < Tp; ++i) b[size_t(i)] = db[size_t(i)] > 0 ? nb[size_t(i)] / db[size_t(i)] : 1.0;
            for (int c = 0; c < cols; ++c)
                for (int row = 0; row < rows; ++row) {
                    nc[size_t(row % Pp)] += channel(c, row);
                    dc[size_t(row % Pp)] += Y(row, c) * a[size_t(c)] * b[size_t(row / Pp)];
                }
            for (int p = 0; p < Pp; ++p) cc[size_t(p)] = dc[size_t(p)] > 0 ? nc[size_t(p)] / dc[size_t(p)] : 1.0;
        }
        for (int c = 0; c < cols; ++c) d.colour_a[size_t(ch) * cols + c] = float(a[size_t(c)]);
        for (int i = 0; i < Tp; ++i) d.colour_b[size_t(ch) * Tp + i] = float(b[size_t(i)]);
        for (int p = 0; p < Pp; ++p) d.colour_c[size_t(ch) * Pp + p] = float(cc[size_t(p)]);
    }
}

// When no bin saw anything above the Lambert part: true for a Lambert BRDF, but also for a
// lobe narrower than a bin (a near-mirror), which cosine samples would never find; false
// with the reason for the latter.
bool lobe_sampled(const Brdf& brdf, const glm::dvec3& diffuse, std::string* err) {
    const dvec3 albedo = directional_albedo(brdf, kPi / 6, 64);
    for (int c = 0; c < 3; ++c)
        if (albedo[c] > 1.01 * kPi * diffuse[c] + 1e-3) {
            char m[320];
            std::snprintf(m, sizeof m,
                          "factored sampler: %s has albedo %.3g at 30 degrees (channel %d) but its Lambert part "
                          "only %.3g: the rest is a lobe narrower than the sampler's bins, which it would never "
                          "sample; use --kind analytic (the model's own lobe) or lafortune",
                          brdf.spec().c_str(), albedo[c], c, kPi * diffuse[c]);
            if (err) *err = m;
            return false;
        }
    return true;
}

// One parameterization (opt.param is Half or Incident), the Lambert part already known.
// The options' automatic values (0) for this BRDF and axis (factored_fit.h says why).
FactoredOptions with_defaults(const Brdf& brdf, FactoredOptions o) {
    const bool iso = brdf.isotropic(), polar = o.axis == SampleAxis::Normal;
    const bool mirror = mirror_axis(o.axis);
    if (o.n_theta_o == 0) o.n_theta_o = mirror ? 20 : 16;
    if (o.n_phi_o == 0) o.n_phi_o = mirror ? 24 : 16;
    if (o.n_theta_p == 0) o.n_theta_p = polar ? 64 : 192;
    if (o.n_phi_p == 0) o.n_phi_p = !polar ? 96 : iso ? 16 : 64;
    if (o.J == 0) o.J = !polar ? 16 : iso ? 4 : 2, o.K = !polar ? 1 : iso ? 2 : 4;
    if (o.iterations == 0) o.iterations = polar ? 2000 : 500;
    return o;
}

// One view's column: the masses of every wp bin (luminance and, with o.colour, RGB) for
// the view wo, from bin_points' S x S points; *failure names a non-finite BRDF value.
void sample_column(const Brdf& brdf, const FactoredOptions& o, const glm::dvec3& diffuse, const dvec3& wo,
                   double theta_o, const std::vector<float>& z_edges, const std::vector<dvec3>& points,
                   const std::vector<double>& solid, ViewColumn* column, std::string* failure) {
    const int Pp = o.n_phi_p, S = o.supersample, rows = (int(z_edges.size()) - 1) * Pp;
    const bool colour = o.colour;
    // The view axes: bin_points' wp are in the view frame, turned by -b about the axis
    // (sepal_smp_axis); turn them back by b.
    const bool turn_t = o.axis == SampleAxis::TangentView, turn = view_axis(o.axis);
    const double b = turn ? 0.5 * std::atan2(turn_t ? wo.y : wo.x, wo.z) : 0.0;
    const double cb = std::cos(b), sb = std::sin(b);
    // The mirror axes: bin_points' c1 is the mirror-centred one; a = wi.t or wi.s comes
    // from it as the runtime's from_mirror has it, and each bin's solid angle is its
    // (c1, c2) area times da/dc1 (1 - m above the cone, 1 + m below).
    const bool mirror_t = o.axis == SampleAxis::TangentMirror, mirror = mirror_axis(o.axis);
    const double m = mirror ? std::clamp(-(mirror_t ? wo.x : wo.y), -0.999, 0.999) : 0.0;
    ViewColumn& col = *column;
    col.lum.assign(size_t(rows), 0.0);
    if (colour) col.rgb.assign(size_t(rows) * 3, 0.0f);
    for (int row = 0; row < rows && failure->empty(); ++row) {
        dvec3 sum(0.0);
        for (int s = 0; s < S * S; ++s) {
            dvec3 wp = points[size_t(row) * S * S + s];
            if (mirror) {
                double& c1 = mirror_t ? wp.x : wp.y;
                const double r0 = std::sqrt(std::max(0.0, 1.0 - c1 * c1));
                c1 = std::clamp(m + c1 * (c1 >= 0 ? 1.0 - m : 1.0 + m), -1.0, 1.0);
                const double k = r0 > 0 ? std::sqrt(std::max(0.0, 1.0 - c1 * c1)) / r0 : 0.0;
                (mirror_t ? wp.y : wp.x) *= k;
                wp.z *= k;
            }
            if (turn) {
                double& p = turn_t ? wp.y : wp.x;
                const double q = p;
                p = cb * q + sb * wp.z;
                wp.z = cb * wp.z - sb * q;
            }
            dvec3 wi = wp;
            double jac = 1.0;
            if (o.param == SampleParam::Half) {
                const double d = glm::dot(wo, wp);
                wi = 2.0 * d * wp - wo;
                if (o.jacobian) jac = 4.0 * std::fabs(d);
            }
            if (!(wi.z > 0)) continue;
            wi = glm::normalize(wi);
            const dvec3 f = glm::max(brdf.eval(wi, wo) - diffuse, dvec3(0.0));
            if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) {
                *failure = "the BRDF returned a non-finite value at theta_i " +
                           std::to_string(rad2deg(std::acos(wi.z))) + ", theta_o " +
                           std::to_string(rad2deg(theta_o)) + " degrees";
                break;
            }
            sum += f * (wi.z * jac);
        }
        double scale = solid[size_t(row)] / (S * S);
        if (mirror) scale *= 0.5 * (z_edges[size_t(row / Pp)] + z_edges[size_t(row / Pp) + 1]) >= 0 ? 1.0 - m : 1.0 + m;
        col.lum[size_t(row)] = std::max(0.0, luminance(sum)) * scale;
        if (colour)
            for (int ch = 0; ch < 3; ++ch) col.rgb[size_t(row) * 3 + ch] = float(std::max(0.0, sum[ch]) * scale);
    }
}

bool fit_one(const Brdf& brdf, const FactoredOptions& opt, const glm::dvec3& diffuse, SamplerData* out,
             FactoredReport* rep, std::string* err) {
    FactoredOptions o = with_defaults(brdf, opt);
    const bool polar = o.axis == SampleAxis::Normal;
    // Angles about t or s turn with the surface: only the absolute frame keeps them.
    const bool view_frame = polar && (o.phi == PhiFrame::View || (o.phi == PhiFrame::Auto && brdf.isotropic()));
    if (view_frame) o.n_phi_o = 1;
    const bool colour = o.colour;
    FactoredReport r;
    r.param = sample_param_name(o.param);
    r.axis = sample_axis_name(o.axis);
    r.phi_frame = view_frame ? "view" : "absolute";
    r.n_theta_o = o.n_theta_o, r.n_phi_o = o.n_phi_o, r.n_theta_p = o.n_theta_p, r.n_phi_p = o.n_phi_p;
    r.J = o.J, r.K = o.K;

    const int Tp = o.n_theta_p, Pp = o.n_phi_p, To = o.n_theta_o, Po = o.n_phi_o, S = o.supersample;
    const int rows = Tp * Pp, cols = To * Po;
    const std::vector<float> z_edges = polar ? theta_bin_z_edges(Tp, o.sqrt_theta) : axis_bin_edges(Tp, o.sqrt_theta);
    std::vector<dvec3> points;
    std::vector<double> solid;
    bin_points(o.axis, z_edges, Pp, S, &points, &solid);

    const auto t0 = std::chrono::steady_clock::now();
    std::vector<ViewColumn> columns(static_cast<size_t>(cols));
    std::vector<std::string> failures(static_cast<size_t>(cols));
    {
        Progress progress(o.progress, "sepal sampler: sampling", size_t(cols));
        parallel_for(size_t(cols), o.threads, [&](size_t c) {
            const int io = int(c) / Po, jo = int(c) % Po;
            const double theta_o = (io + 0.5) / To * 0.5 * kPi;
            const double phi_o = view_frame ? 0.0 : (jo + 0.5) / Po * 2.0 * kPi;
            const dvec3 wo = dir_from_angles(theta_o, phi_o);
            sample_column(brdf, o, diffuse, wo, theta_o, z_edges, points, solid, &columns[c], &failures[c]);
            progress.advance();
        });
    }
    for (const std::string& f : failures)
        if (!f.empty()) {
            if (err) *err = f;
            return false;
        }
    r.evaluations = int64_t(rows) * cols * S * S;
    const auto t1 = std::chrono::steady_clock::now();
    r.sample_seconds = std::chrono::duration<double>(t1 - t0).count();

    Eigen::MatrixXd Y(rows, cols);
    for (int c = 0; c < cols; ++c)
        for (int row = 0; row < rows; ++row) Y(row, c) = columns[size_t(c)].lum[size_t(row)];
    NmfKlOptions no;
    no.max_iterations = o.iterations;
    no.tolerance = o.tolerance;
    no.seed = o.seed;
    no.threads = o.threads;
    NmfKl level1;
    nmf_kl(Y, o.J, no, &level1);
    r.kl_level1 = level1.relative;
    r.iterations1 = level1.iterations;

    const int L = o.J * o.K;
    SamplerData d;
    d.kind = SEPAL_SAMPLER_FACTORED;
    d.desc.param = o.param == SampleParam::Half ? SEPAL_SMP_PARAM_HALF : SEPAL_SMP_PARAM_INCIDENT;
    d.desc.phi_frame = view_frame ? SEPAL_SMP_PHI_VIEW : SEPAL_SMP_PHI_ABSOLUTE;
    d.desc.axis = o.axis == SampleAxis::Tangent         ? SEPAL_SMP_AXIS_T
                  : o.axis == SampleAxis::Bitangent     ? SEPAL_SMP_AXIS_S
                  : o.axis == SampleAxis::TangentView   ? SEPAL_SMP_AXIS_T_VIEW
                  : o.axis == SampleAxis::BitangentView ? SEPAL_SMP_AXIS_S_VIEW
                  : o.axis == SampleAxis::TangentMirror ? SEPAL_SMP_AXIS_T_MIRROR
                  : o.axis == SampleAxis::BitangentMirror ? SEPAL_SMP_AXIS_S_MIRROR
                                                    : SEPAL_SMP_AXIS_N;
    d.desc.n_theta_o = uint32_t(To), d.desc.n_phi_o = uint32_t(Po);
    d.desc.n_theta_p = uint32_t(Tp), d.desc.n_phi_p = uint32_t(Pp);
    d.desc.terms = uint32_t(L);
    d.desc.colour = colour ? 1 : 0;
    d.desc.defensive = float(o.defensive);
    d.desc.jacobian = o.jacobian ? 1 : 0;
    for (int c = 0; c < 3; ++c) d.desc.diffuse[c] = float(diffuse[c]);
    d.z_edges = z_edges;
    d.F.assign(size_t(L) * cols, 0.0f);
    d.u_cdf.assign(size_t(L) * (Tp + 1), 0.0f);
    d.v_cdf.assign(size_t(L) * (Pp + 1), 0.0f);
    double kl2 = 0, mass1 = 0;
    int it2 = 0;
    for (int j = 0; j < o.J; ++j) {
        Eigen::MatrixXd G(Tp, Pp);
        for (int i = 0; i < Tp; ++i)
            for (int p = 0; p < Pp; ++p) G(i, p) = level1.W(i * Pp + p, j);
        NmfKl level2;
        NmfKlOptions no2 = no;
        no2.seed = o.seed + 1000 + uint64_t(j);
        nmf_kl(G, o.K, no2, &level2);
        kl2 += level2.divergence;
        mass1 += G.sum();
        it2 = std::max(it2, level2.iterations);
        for (int k = 0; k < o.K; ++k) {
            const int l = j * o.K + k;
            std::vector<double> um(static_cast<size_t>(Tp)), vm(static_cast<size_t>(Pp));
            for (int i = 0; i < Tp; ++i) um[size_t(i)] = level2.W(i, k);
            for (int p = 0; p < Pp; ++p) vm[size_t(p)] = level2.H(k, p);
            const double su = masses_to_cdf(um.data(), Tp, &d.u_cdf[size_t(l) * (Tp + 1)]);
            const double sv = masses_to_cdf(vm.data(), Pp, &d.v_cdf[size_t(l) * (Pp + 1)]);
            for (int c = 0; c < cols; ++c)
                d.F[size_t(l) * cols + c] = float(std::max(0.0, level1.H(j, c) * su * sv));
        }
    }
    r.kl_level2 = mass1 > 0 ? kl2 / mass1 : 0.0;
    r.iterations2 = it2;
    r.kl_total = stored_kl(d, Y, L, Tp, Pp);

    if (colour) fit_colour(columns, Y, Tp, Pp, &d);
    r.factor_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    r.dense_bytes = double(rows) * cols * 4.0;
    std::vector<uint8_t> bytes;
    if (!encode_sampler(d, &bytes, err)) return false;
    r.sampler_bytes = bytes.size();
    bool any = false;
    for (float f : d.F) any = any || f > 0;
    if (!any && !lobe_sampled(brdf, diffuse, err)) return false;
    if (!any)
        r.notes.push_back(diffuse != dvec3(0.0) ? "the BRDF is its Lambert part: cosine sampling, exact for it"
                                                : "the BRDF is 0 everywhere sampled: the sampler falls back to cosine sampling");
    *out = std::move(d);
    if (rep) *rep = std::move(r);
    return true;
}

}  // namespace

}  // namespace sepal
