// sepal factor: separable factors of a BRDF with the error per number of terms.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>

#include "brdf/brdf.h"
#include "cli/cli.h"
#include "factor/factor.h"
#include "factor/factor_error.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/plot.h"

namespace sepal {

namespace {
const char* kUsage =
    "usage: sepal factor SPEC [options]\n"
    "  --param P          gs-half (default) | iv | vh | rusinkiewicz | elev-azim\n"
    "  --map M            xy (default) | parabolic\n"
    "  --res N            texels per side of each factor, 1..256 (default 32)\n"
    "  --terms K          1..16 (default 4)\n"
    "  --method M         svd (default) | nd | nmf | acls\n"
    "  --colour C         rgb (per channel, default) | luminance (+ per-channel ratio)\n"
    "  --supersample S    S x S sub-samples per texel of each factor, 1..4 (default 1)\n"
    "  --p P              nd: the p-norm, 1..16 (default 2)\n"
    "  --svd-weighted     svd: fit valid entries by their weight (per term count)\n"
    "  --horizon-weight W weight of entries wholly below the horizon in weighted fits\n"
    "                     (nmf, acls, --svd-weighted), 0..1 (default 0.01)\n"
    "  --acls-constant    acls: term 1's half-angle factor held constant\n"
    "  --acls-monotonic   acls: half-angle factors non-increasing in theta_h\n"
    "  --iters N          nmf/acls/weighted svd: most iterations per term count\n"
    "  --tolerance T      nmf/acls/weighted svd: stop when the error falls by less\n"
    "  --max-memory MB    refuse matrix methods above this estimate (default 2048)\n"
    "  --threads T        worker threads, 0 = all cores (default 0); results do not depend on it\n"
    "  --report r.json    write every option, the errors and timings as JSON\n"
    "  --plot p.png       write the error against the number of terms as a plot\n"
    "  --export DIR       write the factors: g<k>.png / h<k>.png in false colour, .pfm floats\n";

bool parse_options(Args& a, FactorOptions* o, std::string* err) {
    auto fail = [&](const std::string& m) {
        *err = m;
        return false;
    };
    if (a.has("param") && !parse_param(a.get("param"), &o->param))
        return fail("--param '" + a.get("param") + "' is not gs-half, iv, vh, rusinkiewicz or elev-azim");
    if (a.has("map") && !parse_map(a.get("map"), &o->map))
        return fail("--map '" + a.get("map") + "' is not xy or parabolic");
    if (a.has("method") && !parse_method(a.get("method"), &o->method))
        return fail("--method '" + a.get("method") + "' is not svd, nd, nmf or acls");
    if (a.has("colour") && !parse_colour(a.get("colour"), &o->colour))
        return fail("--colour '" + a.get("colour") + "' is not rgb or luminance");
    struct IntOpt {
        const char* name;
        int* field;
    };
    o->terms = 4;
    for (IntOpt i : {IntOpt{"res", &o->res}, IntOpt{"terms", &o->terms},
                     IntOpt{"supersample", &o->supersample}, IntOpt{"iters", &o->iterations},
                     IntOpt{"threads", &o->threads}}) {
        if (!a.has(i.name)) continue;
        long v;
        if (!a.integer(i.name, &v)) return fail(a.error());
        if (v < -1000000 || v > 1000000) return fail(std::string("--") + i.name + " out of range");
        *i.field = int(v);
    }
    struct NumOpt {
        const char* name;
        double* field;
    };
    for (NumOpt n : {NumOpt{"p", &o->nd_p}, NumOpt{"tolerance", &o->tolerance},
                     NumOpt{"horizon-weight", &o->horizon_weight},
                     NumOpt{"max-memory", &o->max_memory_mb}}) {
        if (!a.has(n.name)) continue;
        if (!a.number(n.name, n.field)) return fail(a.error());
    }
    o->svd_weighted = a.has("svd-weighted");
    o->acls_constant = a.has("acls-constant");
    o->acls_monotonic = a.has("acls-monotonic");
    if (o->svd_weighted && o->method != Method::SVD) return fail("--svd-weighted needs --method svd");
    if (a.has("p") && o->method != Method::ND) return fail("--p needs --method nd");
    return validate_factor_options(*o, err);
}

// False colour: a perceptual-ish ramp for non-negative factors, blue-white-red for signed.
glm::dvec3 ramp(double t) {
    static const glm::dvec3 stops[] = {{0.05, 0.03, 0.20}, {0.35, 0.07, 0.50}, {0.75, 0.20, 0.35},
                                       {0.98, 0.55, 0.10}, {0.99, 0.95, 0.60}};
    t = std::clamp(t, 0.0, 1.0) * 4;
    const int i = std::min(3, int(t));
    return glm::mix(stops[i], stops[i + 1], t - i);
}
glm::dvec3 diverging(double t) {  // t in [-1, 1]
    t = std::clamp(t, -1.0, 1.0);
    const glm::dvec3 neg(0.15, 0.35, 0.80), mid(0.97), pos(0.80, 0.15, 0.12);
    return t < 0 ? glm::mix(mid, neg, -t) : glm::mix(mid, pos, t);
}

// One panel per channel, side by side, scaled up to about 256 pixels; texels outside the
// map's valid disk (filled from neighbours) are shown dimmed.
Image false_colour(const FactorTexture& t, const std::vector<uint8_t>& valid) {
    const int scale = std::max(1, 256 / t.n), side = t.n * scale, gap = 4;
    Image img(t.channels * side + (t.channels - 1) * gap, side, 3);
    std::fill(img.data.begin(), img.data.end(), 1.0f);
    double lo = 0, hi = 0;
    for (float v : t.data) lo = std::min(lo, double(v)), hi = std::max(hi, double(v));
    const bool signed_ = lo < 0;
    const double range = std::max(std::max(-lo, hi), 1e-30);
    for (int c = 0; c < t.channels; ++c)
        for (int j = 0; j < t.n; ++j)
            for (int i = 0; i < t.n; ++i) {
                const double v = t.at(i, j, c);
                glm::dvec3 col = signed_ ? diverging(v / range) : ramp(v / range);
                if (!valid[size_t(j) * t.n + i]) col = glm::mix(col, glm::dvec3(0.5), 0.6);
                for (int y = 0; y < scale; ++y)
                    for (int x = 0; x < scale; ++x)
                        for (int k = 0; k < 3; ++k)
                            img.at(c * (side + gap) + i * scale + x, j * scale + y, k) = float(col[k]);
            }
    return img;
}

bool export_factors(const std::string& dir, const Factored& f, std::string* err) {
    if (!make_dirs(dir, err)) return false;
    const std::vector<uint8_t> vg = valid_texels(f.param, f.map, 0, f.n);
    const std::vector<uint8_t> vh = valid_texels(f.param, f.map, 1, f.n);
    for (int k = 0; k < f.term_count(); ++k)
        for (int side = 0; side < 2; ++side) {
            const FactorTexture& t = side == 0 ? f.terms[size_t(k)].g : f.terms[size_t(k)].h;
            const std::string base = dir + "/" + (side == 0 ? "g" : "h") + std::to_string(k + 1);
            if (!write_png(base + ".png", false_colour(t, side == 0 ? vg : vh), err)) return false;
            Image raw(t.n, t.n, t.channels);
            raw.data = t.data;
            if (!write_pfm(base + ".pfm", raw, err)) return false;
        }
    JsonWriter j;
    j.begin_object()
        .key("source").value(f.source)
        .key("param").value(param_name(f.param))
        .key("map").value(f.param == Param::ElevAzim ? "angles" : map_name(f.map))
        .key("colour").value(colour_name(f.colour))
        .key("method").value(f.method)
        .key("n").value(f.n)
        .key("channels").value(f.channels)
        .key("terms").value(f.term_count())
        .key("non_negative").value(f.non_negative())
        .key("ratio").begin_array().value(f.ratio.x).value(f.ratio.y).value(f.ratio.z).end_array()
        .key("layout").value("row j = v, texel (i, j) centred at ((i + 0.5)/n, (j + 0.5)/n); "
                             "PNG and PFM rows are texture rows in that order")
        .end_object();
    return write_file_atomic(dir + "/factors.json", j.str().data(), j.str().size(), err);
}

void write_report(JsonWriter& j, const std::string& spec, const FactorOptions& o,
                  const FactorResult& r, const std::vector<TermError>& errors,
                  const ErrorEvaluator& ev) {
    j.begin_object();
    j.key("spec").value(spec).key("brdf").value(r.factored.source);
    j.key("options").begin_object()
        .key("param").value(param_name(o.param))
        .key("map").value(o.param == Param::ElevAzim ? "angles" : map_name(o.map))
        .key("res").value(o.res)
        .key("terms").value(o.terms)
        .key("method").value(method_name(o.method))
        .key("colour").value(colour_name(o.colour))
        .key("supersample").value(o.supersample)
        .key("nd_p").value(o.nd_p)
        .key("svd_weighted").value(o.svd_weighted)
        .key("horizon_weight").value(o.horizon_weight)
        .key("acls_constant").value(o.acls_constant)
        .key("acls_monotonic").value(o.acls_monotonic)
        .key("max_memory_mb").value(o.max_memory_mb)
        .end_object();
    j.key("matrix").begin_object()
        .key("rows").value(r.rows).key("cols").value(r.cols)
        .key("memory_mb").value(r.memory_mb)
        .key("evaluations").value(r.evaluations)
        .end_object();
    // Every clamp or fallback of the engine, zeros included (the notes say the same in words).
    j.key("counts").begin_object()
        .key("negative_clamped").value(int64_t(r.clamped_negative))
        .key("frame_fallbacks").value(r.frame_fallbacks)
        .key("solver_fallbacks").value(r.solver_fallbacks)
        .end_object();
    j.key("colour_ratio").begin_array().value(r.factored.ratio.x).value(r.factored.ratio.y)
        .value(r.factored.ratio.z).end_array();
    j.key("non_negative").value(r.factored.non_negative());
    j.key("metric").begin_object()
        .key("name").value("cosine-weighted RMS of the luminance, (f~ - f) cos(theta_i)")
        .key("mc_pairs").value(ev.options().mc_pairs)
        .key("mc_seed").value(int64_t(ev.options().seed))
        .key("dense_pairs").value(int64_t(ev.options().dense) * ev.options().dense *
                                  ev.options().dense * ev.options().dense)
        .key("reference_rms").value(ev.reference_rms())
        .end_object();
    j.key("errors").begin_array();
    for (const TermError& t : errors)
        j.begin_object()
            .key("terms").value(t.terms)
            .key("rms").value(t.e.rms)
            .key("relative").value(t.e.relative)
            .key("rms_rgb").value(t.e.rms_rgb)
            .key("dense_rms").value(t.e.dense_rms)
            .key("dense_relative").value(t.e.dense_relative)
            .key("matrix_rms").value(t.matrix_rms)
            .end_object();
    j.end_array();
    j.key("notes").begin_array();
    for (const std::string& n : r.notes) j.value(n);
    j.end_array();
    // Timings vary from run to run; everything above does not.
    j.key("timing").begin_object()
        .key("sample_seconds").value(r.sample_seconds)
        .key("factor_seconds").value(r.factor_seconds)
        .key("iterations").value(r.iterations)
        .end_object();
    j.end_object();
}
}  // namespace

int cmd_factor(const std::vector<std::string>& args, const CommandIO& io) {
    Args a(args,
           {"param", "map", "res", "terms", "method", "colour", "supersample", "p", "iters",
            "tolerance", "horizon-weight", "max-memory", "threads", "report", "plot", "export"},
           {"svd-weighted", "acls-constant", "acls-monotonic"});
    if (!a.ok() || a.positional().size() != 1) {
        std::fprintf(io.err, "sepal factor: %s\n%s",
                     a.ok() ? "expected one BRDF spec" : a.error().c_str(), kUsage);
        return kExitBadInput;
    }
    FactorOptions o;
    std::string err;
    if (!parse_options(a, &o, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    for (const char* name : {"report", "plot", "export"})
        if (a.has(name) && a.get(name).empty()) {
            std::fprintf(io.err, "sepal factor: --%s needs a path\n", name);
            return kExitBadInput;
        }
    o.progress = isatty(fileno(io.err)) != 0;
    const std::string spec = a.positional()[0];
    std::unique_ptr<Brdf> brdf = make_brdf(spec, &err);
    if (!brdf) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    FactorResult r;
    if (!factor_brdf(*brdf, o, &r, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    ErrorOptions eo;
    eo.threads = o.threads;
    ErrorEvaluator ev(*brdf, eo);
    if (!ev.init(&err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    const std::vector<TermError> errors = measure_terms(ev, r);

    std::fprintf(io.out, "factor %s\n", r.factored.source.c_str());
    std::fprintf(io.out, "  %s%s, %s map, %d x %d texels, %s, colour %s%s\n", param_name(o.param),
                 hardware_compatible(o.param) ? "" : " (per-pixel backends only)",
                 o.param == Param::ElevAzim ? "angle" : map_name(o.map), o.res, o.res,
                 method_name(o.method), colour_name(o.colour),
                 r.factored.non_negative() ? ", non-negative factors" : ", signed factors");
    if (o.colour == ColourMode::Luminance)
        std::fprintf(io.out, "  colour ratio %.6g %.6g %.6g\n", r.factored.ratio.x,
                     r.factored.ratio.y, r.factored.ratio.z);
    std::fprintf(io.out, "  matrix %d x %d, about %.0f MB; sampled in %.2f s, factored in %.2f s\n",
                 r.rows, r.cols, r.memory_mb, r.sample_seconds, r.factor_seconds);
    for (const std::string& n : r.notes) std::fprintf(io.out, "  note: %s\n", n.c_str());
    std::fprintf(io.out,
                 "  error: cosine-weighted RMS of the luminance over %d Monte Carlo pairs "
                 "(relative to %.6g) and over %d^4 dense pairs\n",
                 eo.mc_pairs, ev.reference_rms(), eo.dense);
    std::fprintf(io.out, "  %5s  %12s  %10s  %12s  %10s  %12s\n", "terms", "rms", "relative",
                 "dense rms", "dense rel", "matrix rms");
    for (const TermError& t : errors)
        std::fprintf(io.out, "  %5d  %12.6g  %10.6f  %12.6g  %10.6f  %12.6g\n", t.terms, t.e.rms,
                     t.e.relative, t.e.dense_rms, t.e.dense_relative, t.matrix_rms);

    if (a.has("report")) {
        JsonWriter j;
        write_report(j, spec, o, r, errors, ev);
        if (!write_file_atomic(a.get("report"), j.str().data(), j.str().size(), &err)) {
            std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
            return kExitBadInput;
        }
    }
    if (a.has("plot")) {
        PlotPanel p;
        p.title = r.factored.source.size() > 60 ? brdf->model() : r.factored.source;
        p.x_label = "terms";
        p.y_label = std::string("cos-weighted RMS, ") + method_name(o.method) + " " +
                    param_name(o.param) + " " + std::to_string(o.res) + "x" + std::to_string(o.res);
        PlotSeries mc{"Monte Carlo", {}, {}, plot_colour(0)}, dense{"dense", {}, {}, plot_colour(1)};
        for (const TermError& t : errors) {
            mc.x.push_back(t.terms), mc.y.push_back(t.e.rms);
            dense.x.push_back(t.terms), dense.y.push_back(t.e.dense_rms);
        }
        p.series = {mc, dense};
        if (!write_png(a.get("plot"), render_plot({p}, 1), &err)) {
            std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
            return kExitBadInput;
        }
    }
    if (a.has("export") && !export_factors(a.get("export"), r.factored, &err)) {
        std::fprintf(io.err, "sepal factor: %s\n", err.c_str());
        return kExitBadInput;
    }
    return kExitOk;
}

}  // namespace sepal
