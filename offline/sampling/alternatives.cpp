#include "sampling/alternatives.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <Eigen/Dense>
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wshadow"
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>
#pragma GCC diagnostic pop

#include <glm/geometric.hpp>

#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "sampling/metrics.h"
#include "spec/spec.h"
#include "util/parallel.h"
#include "util/progress.h"

namespace sepal {

using glm::dvec3;

namespace {

sepal_smp_lobe lobe(uint32_t type, double weight, std::initializer_list<double> p) {
    sepal_smp_lobe l{};
    l.type = type;
    l.weight = float(weight);
    int i = 0;
    for (double v : p) l.p[i++] = float(v);
    return l;
}

SamplerData lobes_sampler(std::vector<sepal_smp_lobe> lobes) {
    SamplerData d;
    d.kind = SEPAL_SAMPLER_LOBES;
    d.desc.lobe_count = uint32_t(lobes.size());
    d.lobes = std::move(lobes);
    return d;
}

// Parameters of an analytic model, read back from its canonical spec.
bool spec_values(const Brdf& brdf, std::string* model, std::vector<SpecItem>* items) {
    std::string err;
    return split_spec(brdf.spec(), model, items, &err);
}

double item_lum(const std::vector<SpecItem>& items, const std::string& key, double fallback) {
    for (const SpecItem& it : items) {
        if (it.key != key) continue;
        double v[3];
        int n = 0;
        size_t start = 0;
        while (n < 3) {
            const size_t slash = it.value.find('/', start);
            if (!parse_finite(it.value.substr(start, slash - start), &v[n])) return fallback;
            ++n;
            if (slash == std::string::npos) break;
            start = slash + 1;
        }
        return n == 3 ? luminance(dvec3(v[0], v[1], v[2])) : v[0];
    }
    return fallback;
}

std::vector<double> split_numbers(const std::string& s) {
    std::vector<double> out;
    size_t start = 0;
    for (;;) {
        const size_t slash = s.find('/', start);
        double v = 0;
        if (!parse_finite(s.substr(start, slash - start), &v)) return {};
        out.push_back(v);
        if (slash == std::string::npos) break;
        start = slash + 1;
    }
    return out;
}

// Lafortune lobes of a spec ("lobe=Cx/Cy/Cz/n[/w or /r/g/b]") and its rho_d.
std::vector<sepal_smp_lobe> lafortune_lobes(const std::vector<SpecItem>& items) {
    std::vector<sepal_smp_lobe> out{lobe(SEPAL_LOBE_COSINE, item_lum(items, "rho_d", 0.2), {})};
    for (const SpecItem& it : items) {
        if (it.key != "lobe") continue;
        const std::vector<double> v = split_numbers(it.value);
        if (v.size() < 4) continue;
        const double w = v.size() == 5 ? v[4] : v.size() == 7 ? luminance(dvec3(v[4], v[5], v[6])) : 1.0;
        out.push_back(lobe(SEPAL_LOBE_PHONG_AXIS, w, {v[0], v[1], v[2], v[3]}));
    }
    return out;
}

}  // namespace

SamplerData make_cosine_sampler() {
    SamplerData d;
    d.kind = SEPAL_SAMPLER_COSINE;
    return d;
}

bool make_analytic_sampler(const Brdf& brdf, SamplerData* out, std::string* err) {
    std::string model;
    std::vector<SpecItem> it;
    std::vector<sepal_smp_lobe> lobes;
    if (spec_values(brdf, &model, &it)) {
        const double rd = item_lum(it, "rho_d", 0.0), rs = item_lum(it, "rho_s", 0.0);
        if (model == "phong") {
            const double n = item_lum(it, "n", 30);
            lobes = {lobe(SEPAL_LOBE_COSINE, rd, {}),
                     lobe(SEPAL_LOBE_PHONG_AXIS, rs * (n + 2) / (2 * kPi), {-1, -1, 1, n})};
        } else if (model == "blinn") {
            const double n = item_lum(it, "n", 100);
            lobes = {lobe(SEPAL_LOBE_COSINE, rd, {}), lobe(SEPAL_LOBE_HALF_AS, rs, {n, n})};
        } else if (model == "lafortune") {
            lobes = lafortune_lobes(it);
        } else if (model == "ward" || model == "ward-duer") {
            lobes = {lobe(SEPAL_LOBE_COSINE, rd, {}),
                     lobe(SEPAL_LOBE_HALF_WARD, rs, {item_lum(it, "ax", 0.2), item_lum(it, "ay", 0.02)})};
        } else if (model == "cook-torrance") {
            const double m = item_lum(it, "m", 0.2);
            lobes = {lobe(SEPAL_LOBE_COSINE, item_lum(it, "d", 0.1) * item_lum(it, "Rd", 0.2), {}),
                     lobe(SEPAL_LOBE_HALF_WARD, item_lum(it, "s", 0.9) * item_lum(it, "F0", 0.2), {m, m})};
        } else if (model == "ashikhmin-shirley") {
            const double Rs = item_lum(it, "Rs", 0.05);
            lobes = {lobe(SEPAL_LOBE_COSINE, item_lum(it, "Rd", 0.5) * (1 - Rs), {}),
                     lobe(SEPAL_LOBE_HALF_AS, Rs, {item_lum(it, "nu", 100), item_lum(it, "nv", 10)})};
        }
    }
    if (lobes.empty()) {
        if (err)
            *err = "'" + brdf.model() +
                   "' has no analytic sampling lobe (phong, blinn, lafortune, ward, cook-torrance and "
                   "ashikhmin-shirley have one); use factored, lafortune, as, tabulated or cosine";
        return false;
    }
    for (sepal_smp_lobe& l : lobes) {
        // Clamp into the runtime's accepted ranges (a model may allow roughness 1e-4..1).
        if (l.type == SEPAL_LOBE_HALF_WARD)
            for (int k = 0; k < 2; ++k) l.p[k] = std::min(10.0f, std::max(1e-4f, l.p[k]));
        l.weight = std::max(0.0f, l.weight);
    }
    *out = lobes_sampler(std::move(lobes));
    refine_lobe_weights(brdf, out);
    return true;
}

void refine_lobe_weights(const Brdf& brdf, SamplerData* d, double floor) {
    if (d->kind != SEPAL_SAMPLER_LOBES || d->lobes.empty()) return;
    bool has_cosine = false;
    for (const sepal_smp_lobe& l : d->lobes) has_cosine = has_cosine || l.type == SEPAL_LOBE_COSINE;
    if (!has_cosine && d->lobes.size() < SEPAL_SMP_MAX_LOBES) {
        d->lobes.push_back(lobe(SEPAL_LOBE_COSINE, 0.0, {}));
        d->desc.lobe_count = uint32_t(d->lobes.size());
    }
    const size_t K = d->lobes.size();
    // Every lobe gets a start weight, so EM can move it.
    double wsum = 0;
    for (const sepal_smp_lobe& l : d->lobes) wsum += l.weight;
    for (sepal_smp_lobe& l : d->lobes)
        if (!(l.weight > 0)) l.weight = float(wsum > 0 ? 0.05 * wsum : 1.0);
    // One-lobe samplers give each lobe's own density.
    std::vector<Sampler> single(K);
    std::string err;
    for (size_t k = 0; k < K; ++k) {
        sepal_smp_lobe l = d->lobes[k];
        l.weight = 1.0f;
        if (!single[k].build(lobes_sampler({l}), &err)) return;
    }
    const std::vector<dvec3> views = judge_views(brdf.isotropic());
    const int N = 1024;
    for (int iter = 0; iter < 12; ++iter) {
        Sampler mix;
        if (!mix.build(*d, &err)) return;
        std::vector<double> num(K, 0.0), den(K, 0.0);
        for (size_t vi = 0; vi < views.size(); ++vi) {
            const float wo[3] = {float(views[vi].x), float(views[vi].y), float(views[vi].z)};
            sepal_sampler_view v;
            sepal_sampler_set_view(&mix.get(), wo, &v);
            std::vector<sepal_sampler_view> sv(K);
            for (size_t k = 0; k < K; ++k) sepal_sampler_set_view(&single[k].get(), wo, &sv[k]);
            Rng rng(1234 + vi);
            double area = 0;
            std::vector<double> acc(K, 0.0);
            for (int s = 0; s < N; ++s) {
                // Stratified in u0 (which picks the lobe), random in u1.
                const float u[2] = {float((s + rng.uniform()) / N), float(rng.uniform())};
                float wi[3], pdf;
                if (sepal_sampler_sample(&v, u, wi, &pdf) != 1) continue;
                const double y = luminance(brdf.eval(dvec3(wi[0], wi[1], wi[2]), views[vi])) * wi[2] / pdf;
                area += y;
                for (size_t k = 0; k < K; ++k)
                    acc[k] += y * v.weight[k] * sepal_sampler_pdf(&sv[k], wi) / pdf;
            }
            for (size_t k = 0; k < K; ++k) {
                num[k] += acc[k] / N;
                den[k] += area / N * v.weight[k];
            }
        }
        for (size_t k = 0; k < K; ++k)
            if (den[k] > 0) d->lobes[k].weight = float(d->lobes[k].weight * num[k] / den[k]);
        double total = 0;
        for (const sepal_smp_lobe& l : d->lobes) total += l.weight;
        if (!(total > 0) || !std::isfinite(total)) return;
        for (sepal_smp_lobe& l : d->lobes) l.weight = float(l.weight / total);
    }
    // The cosine lobe's share at every view >= floor.
    Sampler mix;
    if (!mix.build(*d, &err)) return;
    double need = 1.0;
    size_t cos_k = 0;
    for (size_t k = 0; k < K; ++k)
        if (d->lobes[k].type == SEPAL_LOBE_COSINE) cos_k = k;
    for (const dvec3& w : views) {
        const float wo[3] = {float(w.x), float(w.y), float(w.z)};
        sepal_sampler_view v;
        sepal_sampler_set_view(&mix.get(), wo, &v);
        const double share = v.weight[cos_k];
        if (share < floor && share < 1) need = std::max(need, floor / (1 - floor) * (1 - share) / std::max(share, 1e-12));
    }
    d->lobes[cos_k].weight = float(d->lobes[cos_k].weight * need);
}

// ---- fits -------------------------------------------------------------------------------
namespace {

struct FitPairs {
    std::vector<dvec3> wi, wo;
    std::vector<double> target, weight;  // f cos (luminance); 1/sqrt(density of the wi draw)
};

FitPairs fit_pairs(const Brdf& brdf) {
    FitPairs p;
    const int per_view = 256;
    Rng rng(99);
    for (const dvec3& wo : judge_views(brdf.isotropic())) {
        const dvec3 r = mirror_z(wo);
        dvec3 t = std::fabs(r.z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0);
        t = glm::normalize(t - r * glm::dot(r, t));
        const dvec3 s = glm::cross(r, t);
        const double n = 30;  // the mirror-lobe share of the draws
        for (int k = 0; k < per_view; ++k) {
            dvec3 wi;
            if (k % 2 == 0) {
                wi = rng.hemisphere();
            } else {
                const double c = std::pow(rng.uniform(), 1.0 / (n + 1)), sn = std::sqrt(std::max(0.0, 1 - c * c));
                const double phi = 2 * kPi * rng.uniform();
                wi = sn * std::cos(phi) * t + sn * std::sin(phi) * s + c * r;
            }
            if (!(wi.z > 1e-3)) continue;
            const double cm = glm::dot(wi, r);
            const double dens = 0.5 / (2 * kPi) + (cm > 0 ? 0.5 * (n + 1) / (2 * kPi) * std::pow(cm, n) : 0.0);
            p.wi.push_back(wi);
            p.wo.push_back(wo);
            p.target.push_back(luminance(brdf.eval(wi, wo)) * wi.z);
            p.weight.push_back(1.0 / std::sqrt(dens));
        }
    }
    return p;
}

using SpecFn = std::string (*)(const Eigen::VectorXd& x, bool isotropic);

struct Residuals {
    typedef double Scalar;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    typedef Eigen::VectorXd InputType;
    typedef Eigen::VectorXd ValueType;
    typedef Eigen::MatrixXd JacobianType;
    const FitPairs* pairs;
    SpecFn spec;
    bool isotropic;
    int n_inputs;
    mutable int evaluations = 0;
    int inputs() const { return n_inputs; }
    int values() const { return int(pairs->target.size()); }
    int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& fvec) const {
        ++evaluations;
        std::string err;
        std::unique_ptr<Brdf> m = make_brdf(spec(x, isotropic), &err);
        for (int i = 0; i < values(); ++i) {
            const double v = m ? luminance(m->eval(pairs->wi[size_t(i)], pairs->wo[size_t(i)])) * pairs->wi[size_t(i)].z
                               : 1e3;
            // Square roots (a Hellinger distance): the shape of a lobe counts, not only its
            // peak. A plain L2 fit of f cos gave a Lafortune sampler 1000x worse on
            // Cook-Torrance (its grazing peaks dominate the sum).
            const double r =
                (std::sqrt(std::max(0.0, v)) - std::sqrt(pairs->target[size_t(i)])) * pairs->weight[size_t(i)];
            fvec(i) = std::isfinite(r) ? r : 1e6;
        }
        return 0;
    }
};

double clampd(double x, double lo, double hi) { return std::min(hi, std::max(lo, x)); }
double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// x = [rho_d logit, per lobe: cx, (cy), log n, log w]; cz = 1 fixes the scale of C.
std::string lafortune_spec(const Eigen::VectorXd& x, bool iso) {
    const int per = iso ? 3 : 4;
    std::string s = "lafortune:rho_d=" + format_number(sigmoid(x(0)));
    for (int k = 0; (1 + k * per) < x.size(); ++k) {
        const int b = 1 + k * per;
        const double cx = clampd(x(b), -50, 50), cy = iso ? cx : clampd(x(b + 1), -50, 50);
        const double n = clampd(std::exp(x(b + per - 2)), 0, 1e4);
        // |C|^n <= 1e200 (the model's bound): shrink n where |C| is large.
        const double cmax = std::max({std::fabs(cx), std::fabs(cy), 1.0});
        const double nn = std::min(n, 200.0 / std::log10(std::max(cmax, 1.0 + 1e-12)));
        const double w = clampd(std::exp(x(b + per - 1)), 0, 1000);
        s += ",lobe=" + format_number(cx) + "/" + format_number(cy) + "/1/" + format_number(nn) + "/" +
             format_number(w);
    }
    return s;
}

// x = [Rd logit, Rs logit, log nu, (log nv)]
std::string as_spec(const Eigen::VectorXd& x, bool iso) {
    const double nu = clampd(std::exp(x(2)), 0, 1e5), nv = iso ? nu : clampd(std::exp(x(3)), 0, 1e5);
    return "ashikhmin-shirley:Rd=" + format_number(sigmoid(x(0))) + ",Rs=" + format_number(sigmoid(x(1))) +
           ",nu=" + format_number(nu) + ",nv=" + format_number(nv);
}

bool fit_best(const Brdf& brdf, SpecFn spec, const std::vector<Eigen::VectorXd>& starts, LobeFitReport* rep,
              std::string* err) {
    const FitPairs pairs = fit_pairs(brdf);
    double best = -1;
    std::string best_spec;
    int evals = 0;
    double tss = 0;
    for (size_t i = 0; i < pairs.target.size(); ++i) tss += pairs.target[i] * pairs.weight[i] * pairs.weight[i];
    for (const Eigen::VectorXd& x0 : starts) {
        Residuals f{&pairs, spec, brdf.isotropic(), int(x0.size())};
        Eigen::NumericalDiff<Residuals> nd(f);
        Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Residuals>> lm(nd);
        lm.parameters.maxfev = 150 * int(x0.size() + 1);
        Eigen::VectorXd x = x0;
        lm.minimize(x);
        Eigen::VectorXd fv(f.values());
        f(x, fv);
        evals += f.evaluations + lm.nfev;
        const double ss = fv.squaredNorm();
        if (best < 0 || ss < best) best = ss, best_spec = spec(x, brdf.isotropic());
    }
    if (best < 0) {
        if (err) *err = "model fit: no start converged";
        return false;
    }
    rep->spec = best_spec;
    rep->rms = std::sqrt(best / double(pairs.target.size()));
    rep->rms_relative = tss > 0 ? std::sqrt(best / tss) : 0.0;
    rep->evaluations = evals;
    return true;
}

}  // namespace

bool fit_lafortune_sampler(const Brdf& brdf, int lobes, SamplerData* out, LobeFitReport* rep,
                           std::string* err) {
    if (lobes < 1 || lobes > 8) {
        if (err) *err = "lafortune fit: 1..8 lobes";
        return false;
    }
    const bool iso = brdf.isotropic();
    const int per = iso ? 3 : 4;
    // Starts: specular lobes of growing exponent; one with a retro-reflective lobe; one
    // with off-specular (|Cxy| > Cz) lobes.
    const double kind[3][3][2] = {{{-1, 10}, {-1, 100}, {-1, 1000}},
                                  {{-1, 30}, {1, 5}, {-1, 300}},
                                  {{-1.3, 5}, {-1.0, 60}, {-0.8, 600}}};
    std::vector<Eigen::VectorXd> starts;
    for (const auto& st : kind) {
        Eigen::VectorXd x(1 + per * lobes);
        x(0) = std::log(0.2 / 0.8);
        for (int k = 0; k < lobes; ++k) {
            const int b = 1 + k * per;
            x(b) = st[k % 3][0];
            if (!iso) x(b + 1) = st[k % 3][0];
            const double n = st[k % 3][1] * (k >= 3 ? 3.0 : 1.0);
            x(b + per - 2) = std::log(n);
            x(b + per - 1) = std::log(0.3 * (n + 2) / (2 * kPi));
        }
        starts.push_back(x);
    }
    LobeFitReport r;
    if (!fit_best(brdf, lafortune_spec, starts, &r, err)) return false;
    std::string model;
    std::vector<SpecItem> items;
    if (!split_spec(r.spec, &model, &items, err)) return false;
    *out = lobes_sampler(lafortune_lobes(items));
    refine_lobe_weights(brdf, out);
    if (rep) *rep = r;
    return true;
}

bool fit_as_sampler(const Brdf& brdf, SamplerData* out, LobeFitReport* rep, std::string* err) {
    const bool iso = brdf.isotropic();
    std::vector<Eigen::VectorXd> starts;
    for (double n : {10.0, 100.0, 1000.0}) {
        Eigen::VectorXd x(iso ? 3 : 4);
        x(0) = 0.0, x(1) = std::log(0.1 / 0.9), x(2) = std::log(n);
        if (!iso) x(3) = std::log(n);
        starts.push_back(x);
    }
    LobeFitReport r;
    if (!fit_best(brdf, as_spec, starts, &r, err)) return false;
    std::unique_ptr<Brdf> m = make_brdf(r.spec, err);
    if (!m || !make_analytic_sampler(*m, out, err)) return false;
    refine_lobe_weights(brdf, out);  // the weights for the BRDF itself, not the fit
    if (rep) *rep = r;
    return true;
}

// ---- tabulated --------------------------------------------------------------------------------
bool make_tabulated_sampler(const Brdf& brdf, const TabulatedOptions& opt, SamplerData* out, std::string* err) {
    TabulatedOptions o = opt;
    const bool view_frame = o.phi == PhiFrame::View || (o.phi == PhiFrame::Auto && brdf.isotropic());
    if (view_frame) o.n_phi_o = 1;
    if (o.n_theta_o < 1 || o.n_theta_o > SEPAL_SMP_MAX_VIEW_SIDE || o.n_phi_o < 1 ||
        o.n_phi_o > SEPAL_SMP_MAX_VIEW_SIDE || o.n_theta_i < 1 || o.n_theta_i > SEPAL_SMP_MAX_DIR_SIDE ||
        o.n_phi_i < 1 || o.n_phi_i > SEPAL_SMP_MAX_DIR_SIDE || o.supersample < 1 || o.supersample > 8 ||
        !(o.defensive >= 0 && o.defensive <= 1)) {
        if (err) *err = "tabulated sampler: views 1..128 per side, bins 1..1024 per side, supersample 1..8, defensive 0..1";
        return false;
    }
    const int To = o.n_theta_o, Po = o.n_phi_o, Ti = o.n_theta_i, Pi = o.n_phi_i, S = o.supersample;
    SamplerData d;
    d.kind = SEPAL_SAMPLER_TABULATED;
    d.desc.phi_frame = view_frame ? SEPAL_SMP_PHI_VIEW : SEPAL_SMP_PHI_ABSOLUTE;
    d.desc.n_theta_o = uint32_t(To), d.desc.n_phi_o = uint32_t(Po);
    d.desc.n_theta_p = uint32_t(Ti), d.desc.n_phi_p = uint32_t(Pi);
    d.desc.defensive = float(o.defensive);
    d.z_edges = theta_bin_z_edges(Ti, false);
    const size_t per_view = size_t(Ti + 1) + size_t(Ti) * (Pi + 1);
    uint64_t offsets[SEPAL_SMP_ARRAY_COUNT];
    const uint64_t bytes = sepal_sampler_layout(d.kind, &d.desc, offsets, nullptr);
    if (bytes == 0 || bytes > SEPAL_SMP_MAX_FILE_BYTES) {
        if (err)
            *err = "tabulated sampler: " + std::to_string(bytes) + " bytes is over the format's limit of " +
                   std::to_string(SEPAL_SMP_MAX_FILE_BYTES) + " (an anisotropic BRDF needs a table per view azimuth); " +
                   "use --kind factored";
        return false;
    }
    d.tables.assign(per_view * To * Po, 0.0f);
    std::vector<std::string> failures(static_cast<size_t>(To * Po));
    Progress progress(o.progress, "sepal sampler: tabulating", size_t(To * Po));
    parallel_for(size_t(To * Po), o.threads, [&](size_t view) {
        const int io = int(view) / Po, jo = int(view) % Po;
        const dvec3 wo = dir_from_angles((io + 0.5) / To * 0.5 * kPi, view_frame ? 0.0 : (jo + 0.5) / Po * 2 * kPi);
        std::vector<double> mass(static_cast<size_t>(Ti) * Pi), row(static_cast<size_t>(Ti));
        for (int i = 0; i < Ti; ++i) {
            const double z0 = d.z_edges[size_t(i)], z1 = d.z_edges[size_t(i) + 1];
            const double solid = (z0 - z1) * 2 * kPi / Pi;
            for (int j = 0; j < Pi; ++j) {
                double sum = 0;
                for (int a = 0; a < S; ++a)
                    for (int b = 0; b < S; ++b) {
                        const double z = z0 + (a + 0.5) / S * (z1 - z0), phi = (j + (b + 0.5) / S) * 2 * kPi / Pi;
                        const double s = std::sqrt(std::max(0.0, 1 - z * z));
                        const dvec3 wi(s * std::cos(phi), s * std::sin(phi), z);
                        const double f = luminance(brdf.eval(wi, wo));
                        if (!std::isfinite(f)) failures[view] = "the BRDF returned a non-finite value";
                        else sum += std::max(0.0, f) * z;
                    }
                mass[size_t(i) * Pi + j] = sum / (S * S) * solid;
                row[size_t(i)] += mass[size_t(i) * Pi + j];
            }
        }
        float* t = &d.tables[view * per_view];
        masses_to_cdf(row.data(), Ti, t);
        for (int i = 0; i < Ti; ++i) masses_to_cdf(&mass[size_t(i) * Pi], Pi, t + (Ti + 1) + size_t(i) * (Pi + 1));
        progress.advance();
    });
    for (const std::string& f : failures)
        if (!f.empty()) {
            if (err) *err = f;
            return false;
        }
    *out = std::move(d);
    return true;
}

}  // namespace sepal
