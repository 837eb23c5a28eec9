// sepal-bench-sampling: the figures of factored importance sampling (Lawrence,
// Rusinkiewicz and Ramamoorthi 2004) beside the paper's.
//
//   build/bin/sepal-bench-sampling [all | table1 | table2 | rmse | speed | ablation | renders | axes]
//                                  [--out DIR] [--trials N] [--size N] [--only LABEL] [--quick]
//
// table1    the paper's Table 1: normalized MAE of the sampling factorization (luminance f cos
//           over 2^17 uniform pairs) at the paper's settings (resolution, J x K, its
//           parameterization, absolute phi, no Jacobian) and at sepal's defaults, beside a
//           best-fit Lafortune model's MAE and the paper's two figures; bytes, compression.
// table2    the paper's Tables 2 and 3: variance of the other strategies / variance of
//           factored, a sphere (N x N pixels, default 48) at 100 stratified spp, per-pixel
//           variance over --trials seeded renders (default 4) averaged over the sphere,
//           under a constant environment (Table 2) and the procedural sky (Table 3, for the
//           paper's beach probe); Unif. = cosine, Laf. = best-fit Lafortune, A&S = best-fit
//           Ashikhmin-Shirley, Mat. = tabulated CDFs at Matusik's 90 x 90 x 180 (isotropic
//           only, as in the paper), and the model's own lobe where it has one.
// rmse      RMSE against a 16384-spp reference vs spp (4..1024), log-log, for Cook-Torrance
//           and measured nickel: DIR/sampling-rmse.png.
// speed     ns per sample (sample + its pdf, through the C API, one thread's CPU time, median of 5 runs
//           of 2^20 samples, a new view every 64 samples as a pixel) and bytes per sampler.
// ablation  the design choices of the fit (absolute vs view phi, Jacobian, terms, defensive
//           share) by the relative variance of f cos / pdf at the judge views.
// renders   a contact sheet of 16-spp renders under the sky: DIR/sampling-renders.png.
// axes      (not in all) Poulin-Fournier's factored sampler about t in each coordinate
//           system (h fixed or view-turned, wi about the mirror axis) and view grid.
// Writes DIR/sampling.md (the tables) and DIR/sampling.json. --quick: small images, few
// trials, for a smoke run.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_cli.h"
#include "bench/quiet.h"
#include "bench/json_builder.h"
#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_util.h"
#include "sampling/alternatives.h"
#include "sampling/environment.h"
#include "sampling/factored_fit.h"
#include "sampling/mc_render.h"
#include "sampling/metrics.h"
#include "offline/sampling/sphere_scene.h"
#include "util/image.h"
#include "util/io.h"
#include "util/parallel.h"
#include "util/plot.h"

using namespace sepal;

namespace {

struct Config {
    std::string out = "build/bench";
    int trials = 4, size = 48, spp = 100;
    bool quick = false;
    std::string only;  // --only: materials whose label contains this
};

bool skip(const Config& c, const std::string& label) {
    return !c.only.empty() && label.find(c.only) == std::string::npos;
}

bool tty() { return isatty(fileno(stderr)) != 0; }
void note(const std::string& s) {
    if (tty()) std::fprintf(stderr, "\r%-78s", s.c_str());
}
void note_done() {
    if (tty()) std::fprintf(stderr, "\r%-78s\r", "");
}

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// This thread's CPU time: the per-sample costs are measured with it, so other processes on
// a shared machine do not inflate them (cache sharing still can).
double cpu_now() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string shared_path(const std::string& rel) { return std::string(SEPAL_SOURCE_DIR) + "/" + rel; }

std::unique_ptr<Brdf> need_brdf(const std::string& spec) {
    std::string err;
    std::unique_ptr<Brdf> b = make_brdf(spec, &err);
    if (!b) {
        std::fprintf(stderr, "sepal-bench-sampling: %s\n", err.c_str());
        std::exit(2);
    }
    return b;
}

// A material with the paper's row, where it has one.
struct Material {
    std::string label, spec;
    // Table 1 (paper): resolution, J, K, param; MAE factored and Lafortune; compression.
    int p_theta_p = 32, p_phi_p = 16, p_J = 3, p_K = 1;
    SampleParam p_param = SampleParam::Half;
    double p_mae = -1, p_laf = -1;
    const char* p_compression = "n/a";
    // Tables 2 and 3 (paper): Unif., Laf., A&S, Mat. (-1: not in the paper or n/a).
    double t2[4] = {-1, -1, -1, -1}, t3[4] = {-1, -1, -1, -1};
    int lafortune_lobes = 2;
};

void set4(double* dst, double a, double b, double c, double d) {
    dst[0] = a, dst[1] = b, dst[2] = c, dst[3] = d;
}

const std::vector<Material>& materials() {
    static std::vector<Material> m;
    if (!m.empty()) return m;
    Material ct{"Cook-Torrance", "cook-torrance"};
    ct.p_J = 4, ct.p_mae = 0.192, ct.p_laf = 0.632, ct.lafortune_lobes = 3;
    set4(ct.t2, 16.38, 13.27, 3.53, 0.75);
    set4(ct.t3, 25.79, 10.28, 2.23, 0.75);
    m.push_back(ct);
    Material ward{"Ward", "ward:rho_d=0.1,rho_s=1.2,ax=0.2,ay=0.02"};
    ward.p_theta_p = 100, ward.p_phi_p = 100, ward.p_J = 2, ward.p_K = 4, ward.p_mae = 0.094, ward.p_laf = 1.092;
    m.push_back(ward);
    Material pf{"Poulin-Fournier", "poulin-fournier"};
    pf.p_param = SampleParam::Incident, pf.p_mae = 0.142, pf.p_laf = 0.348;
    set4(pf.t2, 5.86, 1.85, 6.11, -1);
    set4(pf.t3, 1.40, 1.09, 1.53, -1);
    m.push_back(pf);
    Material hl{"Hapke-Lommel", "hapke-lommel"};
    hl.p_param = SampleParam::Incident, hl.p_mae = 0.186, hl.p_laf = 0.464;
    set4(hl.t2, 3.32, 2.14, 11.61, 1.99);
    set4(hl.t3, 0.89, 1.61, 1.87, 1.00);
    m.push_back(hl);
    Material ni{"Nickel (MERL nbrdf)", "nbrdf:nickel"};
    ni.p_theta_p = 128, ni.p_J = 2, ni.p_mae = 0.201, ni.p_laf = 0.643, ni.p_compression = "230:1";
    set4(ni.t2, 306.17, 11.52, 2.17, 1.66);
    set4(ni.t3, 572.76, 3.45, 2.17, 4.80);
    m.push_back(ni);
    Material pl{"Plastic (red-specular-plastic)", "nbrdf:red-specular-plastic"};
    pl.p_theta_p = 128, pl.p_J = 3, pl.p_mae = 0.266, pl.p_laf = 0.874, pl.p_compression = "200:1";
    set4(pl.t2, 157.12, 14.40, 1.34, 18.53);
    set4(pl.t3, 381.94, 21.60, 1.67, 55.64);
    m.push_back(pl);
    Material mb{"Metallic blue (blue-metallic-paint)", "nbrdf:blue-metallic-paint"};
    mb.p_theta_p = 128, mb.p_J = 4, mb.p_mae = 0.118, mb.p_laf = 0.464, mb.p_compression = "180:1";
    set4(mb.t2, 8.88, 6.73, 6.75, 0.44);
    set4(mb.t3, 9.17, 5.96, 5.71, 0.55);
    m.push_back(mb);
    m.push_back(Material{"Gold paint (MERL nbrdf)", "nbrdf:gold-paint"});
    for (const char* c : {"cayman", "garnet_red", "krylon_blue"})
        m.push_back(Material{std::string("Cornell ") + c, shared_path(std::string("fixtures/cornell/") + c + ".brdf")});
    return m;
}

std::string fmt(double v, const char* f = "%.3f") {
    if (v < 0 || !std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

struct Output {
    std::string md;
    JsonBuilder json;
    void line(const std::string& s) {
        std::printf("%s\n", s.c_str());
        std::fflush(stdout);
        md += s + "\n";
    }
};

// ---- samplers of a material -----------------------------------------------------------------
// The fits are most of the bench's time and the sections share them (table 1's two fits are the
// ablation's first and fifth; the defaults serve tables 2 and 3, rmse, speed and the bytes
// table): each is made once per run, as is the Lafortune fit (lafortune_fitted). `kind` names the options: "default" (FactoredOptions{}) or
// "paper" (paper_options).
struct Fit {
    bool ok = false;
    SamplerData data;
    FactoredReport report;
    std::string err;
    double seconds = 0;
};

FactoredOptions paper_options(const Material& m) {
    FactoredOptions o;
    o.n_theta_p = m.p_theta_p, o.n_phi_p = m.p_phi_p, o.J = m.p_J, o.K = m.p_K;
    o.param = m.p_param, o.phi = PhiFrame::Absolute, o.jacobian = false, o.axis = SampleAxis::Normal;
    o.separate_diffuse = false;
    if (m.p_theta_p * m.p_phi_p > 4000) o.supersample = 2;
    return o;
}

const Fit& fitted(const Brdf& b, const Material& m, const std::string& kind) {
    static std::map<std::string, Fit> memo;
    const std::string key = m.label + "/" + kind;
    auto it = memo.find(key);
    if (it != memo.end()) return it->second;
    Fit f;
    const double t0 = now();
    f.ok = fit_factored(b, kind == "paper" ? paper_options(m) : FactoredOptions{}, &f.data, &f.report, &f.err);
    f.seconds = now() - t0;
    return memo[key] = f;
}

// The Lafortune sampler fit (table 1's Laf. column and the strategies' "lafortune"), once
// per material and run like the factored fits.
struct LobeFit {
    bool ok = false;
    SamplerData data;
    LobeFitReport report;
};

const LobeFit& lafortune_fitted(const Brdf& b, const Material& m) {
    static std::map<std::string, LobeFit> memo;
    auto it = memo.find(m.label);
    if (it != memo.end()) return it->second;
    LobeFit f;
    std::string err;
    f.ok = fit_lafortune_sampler(b, m.lafortune_lobes, &f.data, &f.report, &err);
    return memo[m.label] = f;
}

struct Strategies {
    std::map<std::string, SamplerData> data;
    std::map<std::string, std::string> fit_spec;  // lafortune, as: the fitted model
    FactoredReport factored;
};

Strategies make_strategies(const Brdf& b, const Material& m, bool tabulated) {
    Strategies s;
    std::string err;
    SamplerData d;
    const Fit& fo = fitted(b, m, "default");
    if (!fo.ok) std::fprintf(stderr, "factored: %s\n", fo.err.c_str());
    else s.data["factored"] = fo.data, s.factored = fo.report;
    s.data["cosine"] = make_cosine_sampler();
    LobeFitReport rep;
    if (const LobeFit& lf = lafortune_fitted(b, m); lf.ok) {
        s.data["lafortune"] = lf.data;
        s.fit_spec["lafortune"] = lf.report.spec;
    }
    if (fit_as_sampler(b, &d, &rep, &err)) {
        s.data["as"] = d;
        s.fit_spec["as"] = rep.spec;
    }
    if (make_analytic_sampler(b, &d, &err)) s.data["analytic"] = d;
    if (tabulated && b.isotropic()) {
        TabulatedOptions to;
        to.n_theta_o = 90, to.n_theta_i = 90, to.n_phi_i = 180;  // Matusik's resolution
        if (make_tabulated_sampler(b, to, &d, &err)) s.data["tabulated"] = d;
    }
    return s;
}

const Strategies& build_strategies(const Brdf& b, const Material& m, bool tabulated) {
    static std::map<std::string, Strategies> memo;
    const std::string key = m.label + (tabulated ? "/tabulated" : "");
    auto it = memo.find(key);
    return it != memo.end() ? it->second : memo[key] = make_strategies(b, m, tabulated);
}

using sepal_test::SphereScene;

// The run's environments, each made once with its light sampler (MIS): table 2 alone
// renders 240 times under the sky, and each build is 2 M radiance lookups. Addresses are
// stable for the whole run, so render() finds an environment's sampler by its address.
struct Lit {
    std::unique_ptr<Environment> env;
    std::unique_ptr<EnvironmentSampler> light;  // null for a constant environment (no MIS)
};
std::map<std::string, Lit>& lits() {
    static std::map<std::string, Lit> memo;
    return memo;
}
const Environment& environment(const std::string& spec) {
    Lit& l = lits()[spec];
    if (!l.env) {
        std::string err;
        l.env = make_environment(spec, &err);
        if (l.env && !l.env->constant(nullptr)) {
            l.light = std::make_unique<EnvironmentSampler>();
            if (!l.light->build(*l.env, kMcLightWidth, kMcLightHeight, &err)) l.env.reset();
        }
        if (!l.env) {
            std::fprintf(stderr, "sepal-bench-sampling: %s\n", err.c_str());
            std::exit(2);
        }
    }
    return *l.env;
}
const EnvironmentSampler* light_of(const Environment& env) {
    for (const auto& [spec, l] : lits())
        if (l.env.get() == &env) return l.light.get();
    return nullptr;  // not one of ours: render_mc builds its own
}

McResult render(const Brdf& b, const Sampler& s, const Environment& env, int size, int spp, uint64_t seed) {
    static SphereScene sc(96);
    std::string err;
    McOptions o;
    o.spp = spp;
    o.seed = seed;
    o.light = light_of(env);
    McResult r;
    if (!render_mc(b, s.get(), env, sc.scene, sc.mesh, size, size, o, &r, &err)) {
        std::fprintf(stderr, "sepal-bench-sampling: %s\n", err.c_str());
        std::exit(2);
    }
    return r;
}

double variance_of(const Brdf& b, const SamplerData& d, const Environment& env, const Config& c) {
    Sampler s;
    std::string err;
    if (!s.build(d, &err)) return -1;
    std::vector<Image> images;
    std::vector<uint8_t> mask;
    for (int t = 0; t < c.trials; ++t) {
        McResult r = render(b, s, env, c.size, c.spp, 1000 + uint64_t(t));
        images.push_back(std::move(r.image));
        mask = r.shaded;
    }
    return image_variance(images, mask);
}

// Table 1's normalized MAE of a factored sampler's reconstruction (2^17 pairs uniform in
// solid angle), and in *angles the same over pairs uniform in angles.
double factored_mae(const Brdf& b, const SamplerData& d, double* angles) {
    Sampler s;
    std::string err;
    s.build(d, &err);
    const ApproxFn approx = [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
        sepal_sampler_view v;
        sepal_sampler_set_view(&s.get(), w, &v);
        return factored_lum(v, wi);
    };
    *angles = normalized_mae(b, approx, 1 << 17, 7, PairDensity::Angles);
    return normalized_mae(b, approx, 1 << 17, 7);
}

// ---- table 1 -----------------------------------------------------------------------------
void table1(const Config& c, Output* out) {
    out->line("\n## Table 1: accuracy of the sampling factorization (normalized MAE of f cos, luminance)\n");
    out->line("MAE over 2^17 uniform (wi, wo) pairs. *paper settings*: the paper's resolution, J x K, its "
              "parameterization, absolute phi, no Jacobian. *sepal*: the defaults (16 x 16 views, 64 sqrt-spaced "
              "theta bins x 16 phi bins and 4 x 2 terms for isotropic BRDFs; anisotropic ones: param and axis auto, "
              "64 phi bins and 2 x 4 terms about the normal, 192 x 96 bins and 16 x 1 terms about t or s (h) or "
              "their mirror axes (wi, 20 x 24 views); "
              "view-relative phi for isotropic BRDFs, Jacobian). MAE (angles): the same over pairs uniform in "
              "(theta_i, phi_i, theta_o, phi_o), the other reading of the paper's \"dense set of samples of the 4D "
              "domain\". Laf.: our best-fit Lafortune (3 lobes for Cook-Torrance, else 2). Compression: the dense "
              "data matrix Y (float) / the sampler file.\n");
    out->line("| BRDF | settings | resolution (to x po x tp x pp) | J x K | param | bytes | compression | MAE | "
              "MAE (angles) | paper MAE | Laf. MAE | paper Laf. |");
    out->line("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    out->json.key("table1").begin_array();
    for (const Material& m : materials()) {
        if (c.quick && m.label != "Cook-Torrance" && m.label != "Hapke-Lommel") continue;
        if (skip(c, m.label)) continue;
        note("table1: " + m.label);
        auto b = need_brdf(m.spec);
        std::string err;
        const LobeFit& lf = lafortune_fitted(*b, m);
        const LobeFitReport& laf = lf.report;
        double laf_mae = -1;
        if (lf.ok) {
            auto lm = need_brdf(laf.spec);
            laf_mae = normalized_mae(*b, [&](const glm::dvec3& wi, const glm::dvec3& wo) {
                return luminance(lm->eval(wi, wo)) * wi.z;
            }, 1 << 17, 7);
        }
        for (int variant = 0; variant < 2; ++variant) {
            const Fit& fit = fitted(*b, m, variant == 0 ? "paper" : "default");
            if (!fit.ok) {
                std::fprintf(stderr, "%s: %s\n", m.label.c_str(), fit.err.c_str());
                continue;
            }
            const FactoredReport& rep = fit.report;
            const double secs = fit.seconds;
            double mae_angles = 0;
            const double mae = factored_mae(*b, fit.data, &mae_angles);
            char res[64], terms[32];
            std::snprintf(res, sizeof res, "%d x %d x %d x %d", rep.n_theta_o, rep.n_phi_o, rep.n_theta_p, rep.n_phi_p);
            std::snprintf(terms, sizeof terms, "%d x %d = %d", rep.J, rep.K, rep.J * rep.K);
            const double compression = rep.dense_bytes / double(rep.sampler_bytes);
            out->line("| " + m.label + " | " + (variant ? "sepal" : "paper settings") + " | " + res + " | " + terms +
                      " | " + rep.param + (rep.axis == "n" ? "" : " about " + rep.axis) +
                      (variant ? "" : ", absolute, no Jacobian") + " | " + std::to_string(rep.sampler_bytes) + " | " +
                      fmt(compression, "%.0f:1") + " (paper " + m.p_compression + ") | " + fmt(mae) + " | " +
                      fmt(mae_angles) + " | " + fmt(m.p_mae) + " | " + fmt(laf_mae) + " | " +
                      fmt(m.p_laf) + " |");
            out->json.begin_object()
                .key("brdf").value(m.label).key("spec").value(m.spec)
                .key("settings").value(variant ? "sepal" : "paper")
                .key("resolution").value(res).key("J").value(rep.J).key("K").value(rep.K)
                .key("param").value(rep.param).key("axis").value(rep.axis).key("phi_frame").value(rep.phi_frame)
                .key("bytes").value(int64_t(rep.sampler_bytes)).key("compression").value(compression)
                .key("mae").value(mae).key("mae_angles").value(mae_angles).key("paper_mae").value(m.p_mae)
                .key("lafortune_mae").value(laf_mae).key("paper_lafortune_mae").value(m.p_laf)
                .key("lafortune_spec").value(laf.spec).key("fit_seconds").value(secs)
                .key("kl_total").value(rep.kl_total)
                .end_object();
        }
    }
    out->json.end_array();
    note_done();
}

// ---- tables 2 and 3 ------------------------------------------------------------------------------
void table23(const Config& c, Output* out) {
    std::string err;
    const Environment& constant = environment("constant");
    const Environment& sky = environment("sky");
    const char* cols[] = {"cosine", "lafortune", "as", "tabulated", "analytic"};
    struct Row {
        std::string label;
        double ratio[2][5];
        double var_factored[2];
        const Material* m;
    };
    std::vector<Row> rows;
    for (const Material& m : materials()) {
        if (m.label == "Ward") continue;  // not in the paper's Tables 2 and 3
        if (c.quick && m.label != "Cook-Torrance" && m.label != "Hapke-Lommel") continue;
        if (skip(c, m.label)) continue;
        note("tables 2, 3: fitting " + m.label);
        auto b = need_brdf(m.spec);
        const Strategies& s = build_strategies(*b, m, true);
        Row r{m.label, {}, {0, 0}, &m};
        for (int e = 0; e < 2; ++e) {
            const Environment& env = e == 0 ? constant : sky;
            note("tables 2, 3: rendering " + m.label + (e ? " (sky)" : " (constant)"));
            const double vf = variance_of(*b, s.data.at("factored"), env, c);
            r.var_factored[e] = vf;
            for (int k = 0; k < 5; ++k) {
                auto it = s.data.find(cols[k]);
                r.ratio[e][k] = it == s.data.end() || !(vf > 0) ? -1 : variance_of(*b, it->second, env, c) / vf;
            }
        }
        rows.push_back(r);
    }
    note_done();
    out->json.key("tables23").begin_array();
    for (int e = 0; e < 2; ++e) {
        out->line(e == 0 ? "\n## Table 2: variance of each strategy / variance of factored, constant environment"
                         : "\n## Table 3: the same under the procedural sky (the paper: the beach probe); every "
                           "strategy with light samples (MIS, balance heuristic), as a path tracer draws it");
        out->line("\n" + std::to_string(c.size) + " x " + std::to_string(c.size) + " sphere, " +
                  std::to_string(c.spp) + " stratified spp, per-pixel variance over " + std::to_string(c.trials) +
                  " seeded renders, averaged over the sphere. Ours / the paper's. Analytic: the model's own lobe.\n");
        out->line("| BRDF | Unif. | Laf. | A&S | Mat. | analytic | variance of factored |");
        out->line("| --- | --- | --- | --- | --- | --- | --- |");
        for (const Row& r : rows) {
            const double* paper = e == 0 ? r.m->t2 : r.m->t3;
            std::string line = "| " + r.label + " |";
            for (int k = 0; k < 4; ++k) line += " " + fmt(r.ratio[e][k], "%.2f") + " / " + fmt(paper[k], "%.2f") + " |";
            line += " " + fmt(r.ratio[e][4], "%.2f") + " | " + fmt(r.var_factored[e], "%.3g") + " |";
            out->line(line);
            out->json.begin_object().key("brdf").value(r.label).key("environment").value(e ? "sky" : "constant");
            for (int k = 0; k < 5; ++k) out->json.key(cols[k]).value(r.ratio[e][k]);
            for (int k = 0; k < 4; ++k) out->json.key(std::string("paper_") + cols[k]).value(paper[k]);
            out->json.key("variance_factored").value(r.var_factored[e]).end_object();
        }
    }
    out->json.end_array();
}

// ---- rmse ------------------------------------------------------------------------------------------
void rmse(const Config& c, Output* out) {
    std::string err;
    const Environment& constant = environment("constant");
    const int size = c.quick ? 16 : 32, ref_spp = c.quick ? 1024 : 16384;
    const std::vector<int> spps = c.quick ? std::vector<int>{4, 16, 64} : std::vector<int>{4, 16, 64, 256, 1024};
    std::vector<PlotPanel> panels;
    out->line("\n## RMSE against a " + std::to_string(ref_spp) + "-spp factored reference (constant environment, " +
              std::to_string(size) + " x " + std::to_string(size) + " sphere, stratified)\n");
    out->json.key("rmse").begin_array();
    for (const Material& m : materials()) {
        if (m.label != "Cook-Torrance" && m.label != "Nickel (MERL nbrdf)") continue;
        note("rmse: " + m.label);
        auto b = need_brdf(m.spec);
        const Strategies& s = build_strategies(*b, m, !c.quick);
        Sampler fs;
        fs.build(s.data.at("factored"), &err);
        const McResult ref = render(*b, fs, constant, size, ref_spp, 99);
        PlotPanel p;
        p.title = m.label;
        p.x_label = "samples per pixel";
        p.y_label = "RMSE";
        p.log_x = true;
        std::string head = "| " + m.label + " |", rule = "| --- |";
        for (int spp : spps) head += " " + std::to_string(spp) + " spp |", rule += " --- |";
        out->line(head);
        out->line(rule);
        for (const auto& [name, d] : s.data) {
            Sampler smp;
            smp.build(d, &err);
            // One colour per strategy in every panel.
            const char* order[] = {"factored", "cosine", "analytic", "lafortune", "as", "tabulated"};
            const int colour = int(std::find(std::begin(order), std::end(order), name) - std::begin(order));
            PlotSeries series{name, {}, {}, plot_colour(colour)};
            std::string line = "| " + name + " |";
            out->json.begin_object().key("brdf").value(m.label).key("sampler").value(name).key("spp").begin_array();
            for (int spp : spps) out->json.value(spp);
            out->json.end_array().key("rmse").begin_array();
            for (int spp : spps) {
                const McResult r = render(*b, smp, constant, size, spp, 7);
                const double e = std::sqrt(image_mse(r.image, ref.image, ref.shaded));
                series.x.push_back(spp);
                series.y.push_back(e);
                line += " " + fmt(e, "%.4g") + " |";
                out->json.value(e);
            }
            out->json.end_array().end_object();
            out->line(line);
            p.series.push_back(series);
        }
        panels.push_back(p);
    }
    out->json.end_array();
    note_done();
    const std::string path = c.out + "/sampling-rmse.png";
    if (write_png(path, render_plot(panels, 2), &err)) out->line("\nplot: " + path);
}

// ---- speed ---------------------------------------------------------------------------------------
void speed(const Config& c, Output* out) {
    const Material& m = materials().front();  // Cook-Torrance, table 2's strategies
    auto b = need_brdf(m.spec);
    note("speed: fitting");
    const Strategies& s = build_strategies(*b, m, true);
    note_done();
    out->line("\n## Speed and size: ns per sample (sample + its pdf through the C API, one thread's CPU time, "
              "median of 5 runs of 2^20 samples, a new view every 64 samples), Cook-Torrance\n");
    out->line("| sampler | ns per sample | ns per view set-up | bytes |");
    out->line("| --- | --- | --- | --- |");
    out->json.key("speed").begin_array();
    const int n = c.quick ? (1 << 16) : (1 << 20);
    // Cook-Torrance's strategies, then the default factored samplers of the anisotropic
    // materials (binned about t or s, 16 terms: the mixture's pdf sums every term).
    std::vector<std::pair<std::string, SamplerData>> timed(s.data.begin(), s.data.end());
    for (const Material& mat : materials()) {
        if (c.quick || (mat.label != "Ward" && mat.label != "Poulin-Fournier")) continue;
        note("speed: fitting " + mat.label);
        const Fit& fit = fitted(*need_brdf(mat.spec), mat, "default");
        if (fit.ok) timed.emplace_back("factored, " + mat.label + " (" + fit.report.param + " about " + fit.report.axis +
                                       ", " + std::to_string(fit.report.J * fit.report.K) + " terms)", fit.data);
    }
    note_done();
    for (const auto& [name, d] : timed) {
        Sampler smp;
        std::string err;
        smp.build(d, &err);
        std::vector<double> per_sample, per_view;
        BenchQuiet quiet;  // CPU time, but caches are shared: the other bench lane waits
        for (int run = 0; run < 5; ++run) {
            SplitMix64 rng(run);
            std::vector<float> u(size_t(n) * 2);
            for (float& x : u) x = float(rng.uniform());
            std::vector<float> wos(size_t(n / 64) * 3);
            for (int i = 0; i < n / 64; ++i) {
                const glm::dvec3 w = dir_from_angles(std::acos(rng.uniform()), 2 * kPi * rng.uniform());
                wos[size_t(i) * 3] = float(w.x), wos[size_t(i) * 3 + 1] = float(w.y), wos[size_t(i) * 3 + 2] = float(w.z);
            }
            double sink = 0;
            sepal_sampler_view v;
            const double t0 = cpu_now();
            for (int i = 0; i < n / 64; ++i) sepal_sampler_set_view(&smp.get(), &wos[size_t(i) * 3], &v);
            const double t1 = cpu_now();
            for (int i = 0; i < n; ++i) {
                if (i % 64 == 0) sepal_sampler_set_view(&smp.get(), &wos[size_t(i / 64) * 3], &v);
                float wi[3], pdf;
                sepal_sampler_sample(&v, &u[size_t(i) * 2], wi, &pdf);
                sink += pdf;
            }
            const double t2 = cpu_now();
            per_view.push_back((t1 - t0) / (n / 64) * 1e9);
            per_sample.push_back(((t2 - t1) - (t1 - t0)) / n * 1e9);
            if (sink == 12345.678) std::printf("!");
        }
        std::sort(per_sample.begin(), per_sample.end());
        std::sort(per_view.begin(), per_view.end());
        out->line("| " + name + " | " + fmt(per_sample[2], "%.0f") + " | " + fmt(per_view[2], "%.0f") + " | " +
                  std::to_string(smp.bytes()) + " |");
        out->json.begin_object().key("sampler").value(name).key("ns_per_sample").value(per_sample[2])
            .key("ns_per_view").value(per_view[2]).key("bytes").value(int64_t(smp.bytes())).end_object();
    }
    out->json.end_array();
    // Bytes of the default factored sampler of every material (the < 64 KB budget).
    out->line("\n| material | factored sampler bytes (defaults) | param | axis | phi |");
    out->line("| --- | --- | --- | --- | --- |");
    out->json.key("bytes").begin_array();
    for (const Material& mat : materials()) {
        if (c.quick && mat.label != "Cook-Torrance") continue;
        note("bytes: " + mat.label);
        auto bb = need_brdf(mat.spec);
        const Fit& fit = fitted(*bb, mat, "default");
        if (!fit.ok) continue;
        const FactoredReport& rep = fit.report;
        out->line("| " + mat.label + " | " + std::to_string(rep.sampler_bytes) + " | " + rep.param + " | " + rep.axis +
                  " | " + rep.phi_frame + " |");
        out->json.begin_object().key("brdf").value(mat.label).key("bytes").value(int64_t(rep.sampler_bytes)).end_object();
    }
    out->json.end_array();
    note_done();
}

// ---- ablation ------------------------------------------------------------------------------------
void ablation(const Config& c, Output* out) {
    out->line("\n## Design choices: relative variance of f cos / pdf (mean over the judge views; lower is better)\n");
    out->line("| BRDF | paper (absolute phi, no Jacobian, paper J x K) | + view phi | + Jacobian | + 4 x 2 terms "
              "| + Lambert part | + axis auto (sepal) | defensive 0 | defensive 0.1 | cosine |");
    out->line("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    out->json.key("ablation").begin_array();
    for (const Material& m : materials()) {
        if (m.label != "Cook-Torrance" && m.label != "Hapke-Lommel" && m.label != "Nickel (MERL nbrdf)" &&
            m.label != "Ward" && m.label != "Cornell garnet_red")
            continue;
        if (c.quick && m.label != "Cook-Torrance") continue;
        note("ablation: " + m.label);
        auto b = need_brdf(m.spec);
        const std::vector<glm::dvec3> views = judge_views(b->isotropic());
        auto rv_of = [&](const SamplerData& d) {
            Sampler s;
            std::string err;
            s.build(d, &err);
            return relative_variance(*b, s.get(), views, 8192, 3);
        };
        auto rv_fit = [&](const Fit& f) { return f.ok ? rv_of(f.data) : -1.0; };
        auto rv = [&](const FactoredOptions& o) {
            SamplerData d;
            std::string err;
            return fit_factored(*b, o, &d, nullptr, &err) ? rv_of(d) : -1.0;
        };
        FactoredOptions o = paper_options(m);
        std::vector<double> v;
        v.push_back(rv_fit(fitted(*b, m, "paper")));
        o.phi = PhiFrame::Auto;
        // Anisotropic BRDFs keep absolute phi under Auto: the same fit as the paper column.
        v.push_back(b->isotropic() ? rv(o) : v.back());
        o.jacobian = true;
        v.push_back(rv(o));
        FactoredOptions d;
        d.separate_diffuse = false, d.axis = SampleAxis::Normal;
        v.push_back(rv(d));
        const Fit& def = fitted(*b, m, "default");
        d.separate_diffuse = true;
        // Isotropic BRDFs are binned about the normal only: the same fit as the defaults.
        v.push_back(b->isotropic() ? rv_fit(def) : rv(d));
        v.push_back(rv_fit(def));
        // The defensive share is a mixing weight in the sampler's header, not an input of
        // the fit (factored_fit.cpp only copies it): the default fit with the share changed.
        for (float share : {0.0f, 0.1f}) {
            SamplerData sd = def.data;
            sd.desc.defensive = share;
            v.push_back(def.ok ? rv_of(sd) : -1.0);
        }
        Sampler cs;
        std::string err;
        cs.build(make_cosine_sampler(), &err);
        v.push_back(relative_variance(*b, cs.get(), views, 8192, 3));
        std::string line = "| " + m.label + " |";
        out->json.begin_object().key("brdf").value(m.label).key("relative_variance").begin_array();
        for (double x : v) {
            line += " " + fmt(x, "%.4g") + " |";
            out->json.value(x);
        }
        out->json.end_array().end_object();
        out->line(line);
    }
    out->json.end_array();
    note_done();
}

// ---- axes ------------------------------------------------------------------------------------------
// Poulin-Fournier's factored sampler in each coordinate system about its cylinders' axis t,
// at the default bins and terms: what the mirror axes and their view grid buy. Not part of
// `all` (five fits of about two minutes each).
void axes(const Config& c, Output* out) {
    const Material* pf = nullptr;
    for (const Material& m : materials())
        if (m.label == "Poulin-Fournier") pf = &m;
    auto b = need_brdf(pf->spec);
    out->line("\n## Poulin-Fournier about its cylinders' axis t (192 x 96 bins, 16 x 1 terms, 500 NMF iterations)\n");
    out->line("| wp | coordinates | views | MAE | MAE (angles) | relative variance | bytes | fit s |");
    out->line("| --- | --- | --- | --- | --- | --- | --- | --- |");
    struct Variant {
        SampleParam param;
        SampleAxis axis;
        int views_theta, views_phi;
    };
    const Variant variants[] = {{SampleParam::Half, SampleAxis::Tangent, 16, 16},
                                {SampleParam::Half, SampleAxis::TangentView, 16, 16},
                                {SampleParam::Incident, SampleAxis::TangentMirror, 16, 16},
                                {SampleParam::Incident, SampleAxis::TangentMirror, 24, 20},
                                {SampleParam::Incident, SampleAxis::TangentMirror, 20, 24}};
    out->json.key("axes").begin_array();
    for (const Variant& v : variants) {
        if (c.quick && v.views_theta != 16) continue;
        note(std::string("axes: ") + sample_axis_name(v.axis));
        FactoredOptions o;
        o.param = v.param, o.axis = v.axis, o.n_theta_o = v.views_theta, o.n_phi_o = v.views_phi;
        SamplerData d;
        FactoredReport rep;
        std::string err;
        const double t0 = now();
        if (!fit_factored(*b, o, &d, &rep, &err)) {
            std::fprintf(stderr, "axes: %s\n", err.c_str());
            continue;
        }
        const double secs = now() - t0;
        Sampler s;
        s.build(d, &err);
        double mae_angles = 0;
        const double mae = factored_mae(*b, d, &mae_angles);
        const double rv = relative_variance(*b, s.get(), judge_views(false), 8192, 3);
        const std::string views = std::to_string(v.views_theta) + " x " + std::to_string(v.views_phi);
        out->line("| " + rep.param + " | " + rep.axis + " | " + views + " | " + fmt(mae) + " | " + fmt(mae_angles) + " | " +
                  fmt(rv, "%.4g") + " | " + std::to_string(rep.sampler_bytes) + " | " + fmt(secs, "%.0f") + " |");
        out->json.begin_object().key("param").value(rep.param).key("axis").value(rep.axis).key("views").value(views)
            .key("mae").value(mae).key("mae_angles").value(mae_angles).key("relative_variance").value(rv)
            .key("bytes").value(int64_t(rep.sampler_bytes)).key("fit_seconds").value(secs).end_object();
    }
    out->json.end_array();
    note_done();
}

// ---- renders ---------------------------------------------------------------------------------------
void renders(const Config& c, Output* out) {
    std::string err;
    const Environment& sky = environment("sky");
    const int size = c.quick ? 48 : 128, spp = 16;
    const char* names[] = {"factored", "cosine", "lafortune", "as"};
    std::vector<const Material*> mats;
    for (const Material& m : materials())
        if (m.label == "Cook-Torrance" || m.label == "Nickel (MERL nbrdf)" || m.label == "Gold paint (MERL nbrdf)")
            mats.push_back(&m);
    const int label_h = 14;
    Image sheet(int(4 * size), int(mats.size()) * (size + label_h) + label_h, 3);
    std::fill(sheet.data.begin(), sheet.data.end(), 1.0f);
    for (int k = 0; k < 4; ++k) draw_text(&sheet, k * size + 4, 3, names[k], glm::dvec3(0), 1);
    for (size_t row = 0; row < mats.size(); ++row) {
        note("renders: " + mats[row]->label);
        auto b = need_brdf(mats[row]->spec);
        const Strategies& s = build_strategies(*b, *mats[row], true);  // table 2's
        for (int k = 0; k < 4; ++k) {
            auto it = s.data.find(names[k]);
            if (it == s.data.end()) continue;
            Sampler smp;
            smp.build(it->second, &err);
            const McResult r = render(*b, smp, sky, size, spp, 3);
            const int y0 = label_h + int(row) * (size + label_h);
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x)
                    for (int ch = 0; ch < 3; ++ch) {
                        // A simple exposure and the sRGB curve, for looking at.
                        const float v = std::min(1.0f, r.image.at(x, y, ch) * 0.8f);
                        sheet.at(k * size + x, y0 + y, ch) = std::pow(v, 1.0f / 2.2f);
                    }
        }
        draw_text(&sheet, 4, label_h + int(row) * (size + label_h) + size + 2, mats[row]->label, glm::dvec3(0), 1);
    }
    note_done();
    const std::string path = c.out + "/sampling-renders.png";
    if (write_png(path, sheet, &err))
        out->line("\nrenders (" + std::to_string(spp) + " spp, procedural sky, columns: factored, cosine, "
                  "Lafortune fit, A&S fit): " + path);
}

}  // namespace

int main(int argc, char** argv) {
    Config c;
    std::string what = "all";
    BenchCli cli("sepal-bench-sampling", "Factored importance sampling (Lawrence 2004): tables, RMSE, speed, renders.");
    cli.app.add_option("WHAT", what, "all, table1, table2, rmse, speed, ablation, renders, or axes (not in all)")
        ->check(CLI::IsMember({"all", "table1", "table2", "rmse", "speed", "ablation", "renders", "axes"}))
        ->capture_default_str();
    cli.app.add_option("--trials", c.trials, "trials per estimate (>= 2)")->check(CLI::Range(2, 100000))->capture_default_str();
    cli.app.add_option("--size", c.size, "image side (>= 8)")->check(CLI::Range(8, 4096))->capture_default_str();
    cli.app.add_option("--only", c.only, "one material label");
    cli.app.add_flag("--quick", c.quick, "a small run");
    if (const int code = cli.parse(argc, argv); code >= 0) return code;
    c.out = cli.out;
    if (c.quick) c.size = std::min(c.size, 24), c.trials = 2;
    std::string err;
    Output out;
    out.line("# sepal-bench-sampling " + what + (c.quick ? " (quick)" : "") + ", " +
             std::to_string(default_threads()) + " threads");
    out.json.begin_object().key("bench").value("sampling").key("quick").value(c.quick);
    const double t0 = now();
    // Each section's wall time (they share fits, so a section run alone costs more), for the
    // make-bench budget.
    std::vector<std::pair<std::string, double>> times;
    auto section = [&](const char* name, void (*run)(const Config&, Output*)) {
        if (what != "all" && what != name) return;
        const double s0 = now();
        run(c, &out);
        times.emplace_back(name, now() - s0);
        std::fprintf(stderr, "sepal-bench-sampling: %s %.0f s\n", name, times.back().second);
    };
    section("table1", table1);
    section("table2", table23);
    section("ablation", ablation);
    section("speed", speed);
    section("rmse", rmse);
    section("renders", renders);
    if (what == "axes") section("axes", axes);
    out.json.key("section_seconds").begin_object();
    for (const auto& [name, secs] : times) out.json.key(name).value(secs);
    out.json.end_object();
    out.json.key("seconds").value(now() - t0).end_object();
    const std::string suffix = what == "all" ? "" : "-" + what;
    if (!write_file_atomic(c.out + "/sampling" + suffix + ".md", out.md.data(), out.md.size(), &err) ||
        !write_file_atomic(c.out + "/sampling" + suffix + ".json", out.json.str().data(), out.json.str().size(), &err)) {
        std::fprintf(stderr, "sepal-bench-sampling: %s\n", err.c_str());
        return 2;
    }
    std::printf("\nwrote %s/sampling%s.md and .json (%.0f s)\n", c.out.c_str(), suffix.c_str(), now() - t0);
    return 0;
}
