#include "bake/bake.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <unistd.h>

#include "brdf/brdf_capped.h"
#include "factor/factor_error.h"
#include "util/json.h"
#include "bake/plan.h"
#include "bake/quantize.h"

namespace sepal {
namespace {

sepal_param to_fmt(Param p) {
    switch (p) {
        case Param::IncidentView: return SEPAL_PARAM_IV;
        case Param::GsHalf: return SEPAL_PARAM_GS_HALF;
        case Param::ViewHalf: return SEPAL_PARAM_VH;
        case Param::Rusinkiewicz: return SEPAL_PARAM_RUSINKIEWICZ;
        default: return SEPAL_PARAM_ELEV_AZIM;
    }
}

const char* pass_op_name(uint16_t op) {
    return op == SEPAL_OP_PRODUCT ? "product" : op == SEPAL_OP_TEXTURE ? "texture" : "constant";
}

FactorOptions factor_options(const BakeOptions& o, Param param, HemiMap map, int res, Method method, int terms) {
    FactorOptions fo;
    fo.param = param;
    fo.map = map;
    fo.res = res;
    fo.terms = terms;
    fo.method = method;
    fo.colour = o.colour;
    fo.supersample = o.supersample;
    fo.threads = o.threads;
    fo.max_memory_mb = o.max_memory_mb;
    fo.matrix_error = false;  // unused here; for nd it would cost one more sampling pass
    return fo;
}

// Terms to factor for a search entry: the largest asked for, but no more than the sample
// matrix's rank can hold (1 at --res 1), so small resolutions still give their candidates.
int search_terms(Param param, HemiMap map, int res, int max_terms) {
    FactorOptions shape;
    shape.param = param;
    shape.map = map;
    shape.res = res;
    int rows = 0, cols = 0;
    matrix_shape(shape, &rows, &cols);
    return std::max(1, std::min(max_terms, std::min(rows, cols)));
}

std::string rank_note(const FactorOptions& fo, int k) {
    return "--terms " + std::to_string(k) + " exceeds the rank the sample matrix can have at --res " +
           std::to_string(fo.res) + " (at most " + std::to_string(fo.terms) + ")";
}

// The winner's factorization counts and every note, after make_asset added its own.
void record_counts(const FactorResult& r, int64_t capped, double reference_rms, BakeResult* out) {
    BakeCounts& c = out->counts;
    c.evaluations = r.evaluations;
    c.capped = capped;
    c.negative_clamped = r.clamped_negative;
    c.frame_fallbacks = r.frame_fallbacks;
    c.solver_fallbacks = r.solver_fallbacks;
    const InputCounts& in = c.input;
    if (in.nonfinite || in.negative || in.huge || in.missing) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "input: %lld NaN or inf, %lld negative, %lld beyond float range: %lld missing, "
                      "%lld cells filled by push-pull",
                      (long long)in.nonfinite, (long long)in.negative, (long long)in.huge, (long long)in.missing,
                      (long long)in.filled);
        out->notes.push_back(buf);
    }
    if (in.clamped) out->notes.push_back("input: " + std::to_string(in.clamped) + " values clamped into range");
    for (const std::string& n : r.notes) out->notes.push_back(n);
    if (c.all_zero)
        out->notes.push_back(reference_rms == 0
                                 ? "all-zero BRDF: f is 0 at every sample; the asset is one constant-zero pass "
                                   "(renders black)"
                                 : "the factors quantized to all zero (the BRDF is not): the asset renders black");
    else if (c.zero_textures)
        out->notes.push_back(std::to_string(c.zero_textures) + " textures are zero everywhere");
    if (c.quantize_clamped)
        out->notes.push_back(std::to_string(c.quantize_clamped) + " quantized codes clamped into range");
}

}  // namespace

void mark_front(std::vector<BakeCandidate>* candidates) {
    // O(n^2): searches hold at most a few hundred candidates.
    for (BakeCandidate& c : *candidates) {
        c.on_front = c.ok;
        if (!c.ok) continue;
        for (const BakeCandidate& d : *candidates)
            if (d.ok && d.ms <= c.ms && d.error_quantized <= c.error_quantized &&
                (d.ms < c.ms || d.error_quantized < c.error_quantized)) {
                c.on_front = false;
                break;
            }
    }
}

int choose_winner(std::vector<BakeCandidate>* candidates, const BakeOptions& o) {
    int best = -1;
    for (size_t i = 0; i < candidates->size(); ++i) {
        BakeCandidate& c = (*candidates)[i];
        c.meets = c.ok && (o.max_error < 0 || c.error_quantized <= o.max_error) &&
                  (o.max_passes < 0 || c.passes <= o.max_passes) && (o.max_bytes < 0 || c.bytes <= o.max_bytes);
        if (!c.meets) continue;
        if (best < 0) {
            best = int(i);
            continue;
        }
        // With an error budget, the fastest predicted frame; without, the most accurate.
        const BakeCandidate& b = (*candidates)[size_t(best)];
        const bool better = o.max_error >= 0 ? std::make_tuple(c.ms, c.error_quantized, c.bytes) <
                                                   std::make_tuple(b.ms, b.error_quantized, b.bytes)
                                             : std::make_tuple(c.error_quantized, c.ms, c.bytes) <
                                                   std::make_tuple(b.error_quantized, b.ms, b.bytes);
        if (better) best = int(i);
    }
    return best;
}

std::string BakeCandidate::label() const {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s/%s %d %s x%d %db", param_name(param), map_name(map), res, method_name(method),
                  terms, bits);
    return buf;
}

bool make_asset(const Factored& f, int terms, const QuantizeOptions& q, AssetData* out, std::string* err,
                BakeCounts* counts) {
    if (terms < 1 || terms > f.term_count() || terms > SEPAL_FMT_MAX_TERMS) {
        if (err) *err = "bake: " + std::to_string(terms) + " terms asked of a " + std::to_string(f.term_count()) + "-term factorization";
        return false;
    }
    AssetData a;
    a.material.param = to_fmt(f.param);
    a.material.map = f.map == HemiMap::XY ? SEPAL_MAP_XY : SEPAL_MAP_PARABOLIC;
    a.material.color_mode = f.colour == ColourMode::PerChannel ? SEPAL_COLOR_PER_CHANNEL : SEPAL_COLOR_LUMINANCE;
    a.material.terms = uint32_t(terms);
    a.material.channels = uint32_t(f.channels);
    for (int c = 0; c < 3; ++c) a.material.ratio[c] = float(f.ratio[c]);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    a.material.error_quantized = a.material.error_float = a.material.error_relative = nan;
    for (int k = 0; k < terms; ++k)
        for (int role = 0; role < 2; ++role) {
            const FactorTexture& src = role == 0 ? f.terms[size_t(k)].g : f.terms[size_t(k)].h;
            AssetTexture t;
            QuantizeStats qs;
            if (!quantize_texture(src.data.data(), src.n, src.channels, q, &t, err, &qs)) return false;
            t.desc.role = uint32_t(role);
            t.desc.term = uint32_t(k);
            a.textures.push_back(std::move(t));
            if (counts) {
                counts->zero_textures += qs.all_zero ? 1 : 0;
                counts->zero_scale_channels += qs.zero_scale_channels;
                counts->quantize_clamped += qs.clamped;
            }
        }
    // All zero (a black material): the constant-zero plan rather than a refusal.
    if (!build_plan(&a, err, /*allow_all_zero=*/true)) return false;
    if (counts) counts->all_zero = plan_all_zero(a);
    *out = std::move(a);
    return true;
}

Factored dequantize(const AssetData& a, const Factored& like) {
    Factored f = like;
    f.terms.resize(a.material.terms);
    for (const AssetTexture& t : a.textures) {
        FactorTexture& dst = t.desc.role == SEPAL_ROLE_G ? f.terms[t.desc.term].g : f.terms[t.desc.term].h;
        dst = FactorTexture(int(t.desc.width), int(t.desc.channels));
        dst.data = dequantize_level0(t);
    }
    return f;
}

std::string asset_manifest(const AssetData& a, const std::string& spec, const std::string& method, int res,
                           const std::string& bake_key) {
    static const char* kParams[] = {"iv", "gs-half", "vh", "rusinkiewicz", "elev-azim"};
    Json j;
    j["format"] = "sepal asset 1.0";
    if (!bake_key.empty()) j["bake_key"] = bake_key;
    j["spec"] = spec;
    j["method"] = method;
    j["parameterization"] = kParams[a.material.param % 5];
    j["map"] = a.material.map == SEPAL_MAP_XY ? "xy" : "parabolic";
    j["colour"] = a.material.color_mode == SEPAL_COLOR_PER_CHANNEL ? "rgb" : "luminance";
    j["resolution"] = res;
    j["terms"] = int(a.material.terms);
    j["ratio"] = Json::array();
    for (float r : a.material.ratio) j["ratio"].push_back(double(r));
    j["errors"] = {{"float_rms", double(a.material.error_float)},
                   {"quantized_rms", double(a.material.error_quantized)},
                   {"quantized_relative", double(a.material.error_relative)}};
    j["textures"] = Json::array();
    for (size_t i = 0; i < a.textures.size(); ++i) {
        const sepal_fmt_texture& d = a.textures[i].desc;
        Json t = {{"index", int(i)}, {"term", int(d.term)}, {"role", d.role == SEPAL_ROLE_G ? "G" : "H"},
                  {"size", int(d.width)}, {"levels", int(d.levels)}, {"channels", int(d.channels)},
                  {"bits", int(d.bits)}};
        t["scale"] = Json::array();
        t["bias"] = Json::array();
        for (uint32_t c = 0; c < d.channels; ++c) {
            t["scale"].push_back(double(d.scale[c]));
            t["bias"].push_back(double(d.bias[c]));
        }
        j["textures"].push_back(std::move(t));
    }
    Json passes = Json::array();
    for (const sepal_fmt_pass& p : a.passes) {
        Json q = {{"op", pass_op_name(p.op)}, {"blend", p.blend == SEPAL_BLEND_ADD ? "add" : "subtract"}};
        if (p.tex0 != SEPAL_FMT_NO_TEXTURE) q["tex0"] = int(p.tex0);
        if (p.tex1 != SEPAL_FMT_NO_TEXTURE) q["tex1"] = int(p.tex1);
        q["color"] = Json::array();
        for (float c : p.color) q["color"].push_back(double(c));
        passes.push_back(std::move(q));
    }
    j["plan"] = {{"doublings", int(a.plan.doublings)},
                 {"peak_partial_sum", double(a.plan.peak_partial_sum)},
                 {"passes", std::move(passes)}};
    return dump_json(j);
}

bool bake(const Brdf& brdf, const BakeOptions& o, BakeResult* out, std::string* err) {
    const auto start = std::chrono::steady_clock::now();
    *out = BakeResult{};
    if (o.params.empty() || o.maps.empty() || o.resolutions.empty() || o.terms.empty() || o.methods.empty()) {
        if (err) *err = "bake: an empty search list";
        return false;
    }
    const size_t searches = o.params.size() * o.maps.size() * o.resolutions.size() * o.methods.size();
    if (searches > 64) {
        if (err) *err = "bake: " + std::to_string(searches) + " factorizations to search; at most 64 (narrow a list)";
        return false;
    }
    int max_terms = 0;
    for (int k : o.terms) {
        if (k < 1 || k > SEPAL_FMT_MAX_TERMS) {
            if (err) *err = "bake: --terms " + std::to_string(k) + " outside 1.." + std::to_string(SEPAL_FMT_MAX_TERMS);
            return false;
        }
        max_terms = std::max(max_terms, k);
    }
    for (int b : o.bits)
        if (b != 8 && b != 16) {
            if (err) *err = "bake: --bits " + std::to_string(b) + ": 8 or 16";
            return false;
        }
    if (o.bits.empty()) {
        if (err) *err = "bake: an empty search list";
        return false;
    }
    out->cost = o.cost;
    if (out->cost.backend.empty() && !default_cost_model("gles1", &out->cost, err)) return false;
    const CostModel& cost = out->cost;
    for (int r : o.resolutions)
        if (r < 1 || r > 256 || (r & (r - 1))) {
            if (err) *err = "bake: --res " + std::to_string(r) + ": a power of two in 1..256 (GL ES 1.1 textures)";
            return false;
        }
    out->counts.input = brdf.input_counts();
    // The factors see the capped BRDF; every error is measured against the original.
    const CappedBrdf capped(brdf, o.cap);
    const Brdf& source = o.cap > 0 ? static_cast<const Brdf&>(capped) : brdf;
    ErrorOptions eo;
    eo.dense = 0;  // the Monte Carlo metric ranks candidates; the dense one is for reports
    eo.threads = o.threads;
    ErrorEvaluator ev(brdf, eo);
    if (!ev.init(err)) return false;
    const bool show = o.progress && isatty(2);
    size_t done = 0;
    for (Param param : o.params)
        for (HemiMap map : o.maps)
            for (int res : o.resolutions)
                for (Method method : o.methods) {
                    const FactorOptions fo = factor_options(o, param, map, res, method, search_terms(param, map, res, max_terms));
                    ++done;
                    if (show)
                        std::fprintf(stderr, "\rbake: factoring %zu/%zu: %s/%s %d %s x%d   ", done, searches,
                                     param_name(param), map_name(map), res, method_name(method), max_terms);
                    FactorResult r;
                    std::string ferr;
                    const bool factored = factor_brdf(source, fo, &r, &ferr);
                    for (int k : o.terms)
                        for (int bits : o.bits) {
                            BakeCandidate c;
                            c.param = param;
                            c.map = map;
                            c.res = res;
                            c.terms = k;
                            c.bits = bits;
                            c.method = method;
                            if (!factored || k > fo.terms) {
                                c.note = factored ? rank_note(fo, k) : ferr;
                                out->candidates.push_back(std::move(c));
                                continue;
                            }
                            const Factored& f = r.by_terms[size_t(k - 1)];
                            c.error_float = ev.measure(f).relative;
                            AssetData a;
                            std::vector<uint8_t> bytes;
                            std::string aerr;
                            QuantizeOptions q;
                            q.bits = bits;
                            q.mips = o.mips;
                            if (!make_asset(f, k, q, &a, &aerr) || !encode_asset(a, &bytes, &aerr)) {
                                c.note = aerr;
                                out->candidates.push_back(std::move(c));
                                continue;
                            }
                            const ApproxError qe = ev.measure(dequantize(a, f));
                            c.ok = true;
                            c.error_quantized = qe.relative;
                            c.rms_quantized = qe.rms;
                            c.passes = int(a.passes.size());
                            c.doublings = int(a.plan.doublings);
                            c.non_negative = f.non_negative();
                            c.bytes = int64_t(bytes.size());
                            c.ms = cost.predict(c.passes, c.terms, c.bytes);
                            if (o.keep_assets) {
                                a.material.error_float = float(c.error_float * ev.reference_rms());
                                a.material.error_quantized = float(c.rms_quantized);
                                a.material.error_relative = float(c.error_quantized);
                                a.meta = asset_manifest(a, brdf.spec(), method_name(method), res, o.key);
                                c.asset = std::move(a);
                            }
                            out->candidates.push_back(std::move(c));
                        }
                }
    if (show) std::fprintf(stderr, "\r%80s\r", "");
    const int best = choose_winner(&out->candidates, o);
    mark_front(&out->candidates);
    out->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out->capped_share = capped.share();
    if (best < 0) {
        double closest = std::numeric_limits<double>::infinity();
        std::string label;
        for (const BakeCandidate& c : out->candidates)
            if (c.ok && c.error_quantized < closest) closest = c.error_quantized, label = c.label();
        if (err && label.empty()) {
            // Not one candidate could be made: say why (the first reason; all are listed).
            for (const BakeCandidate& c : out->candidates)
                if (!c.ok) {
                    *err = "bake: every candidate failed; " + c.label() + ": " + c.note;
                    break;
                }
        } else if (err) {
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "bake: no candidate meets the budgets (lowest error %.4g, %s); allow more terms, "
                          "a higher --res, --bits 16, or loosen --max-error/--max-passes/--max-bytes",
                          closest, label.c_str());
            *err = buf;
        }
        return false;
    }
    out->winner = best;
    const BakeCandidate& w = out->candidates[size_t(best)];
    char why[256];
    if (o.max_error >= 0)
        std::snprintf(why, sizeof why, "%s: the fastest predicted frame (%.2f ms on %s, %d pass%s per light) with error %.4g <= %.4g",
                      w.label().c_str(), w.ms, cost.backend.c_str(), w.passes, w.passes == 1 ? "" : "es",
                      w.error_quantized, o.max_error);
    else
        std::snprintf(why, sizeof why, "%s: the lowest error (%.4g) within the budgets (no --max-error given)",
                      w.label().c_str(), w.error_quantized);
    out->why = why;
    // A winner that misses half of f (relative cosine-weighted RMS >= 0.5) is still the best
    // of the search, but a user should hear it: sharp lobes below the texel size, grazing
    // peaks, or a --cap account for it (README "Extremes").
    if (w.error_quantized >= 0.5) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "the winner's relative error is %.3g (>= 0.5): f has detail the factors do not hold (lobes "
                      "narrower than a texel at %dx%d, grazing peaks%s); try a higher --res or --param iv, and look at "
                      "a render",
                      w.error_quantized, w.res, w.res, o.cap > 0 ? ", or the --cap" : "");
        out->notes.push_back(buf);
    }
    if (o.keep_assets) {
        out->asset = w.asset;
        return true;
    }
    // Rebuild the winner (one more factorization: cheaper than keeping every candidate).
    // It runs alone, so the cap's counter moves by exactly the asset's clamps.
    const FactorOptions fo = factor_options(o, w.param, w.map, w.res, w.method, search_terms(w.param, w.map, w.res, max_terms));
    FactorResult r;
    const int64_t capped_before = capped.capped();
    if (!factor_brdf(source, fo, &r, err)) return false;
    const Factored& f = r.by_terms[size_t(w.terms - 1)];
    QuantizeOptions q;
    q.bits = w.bits;
    q.mips = o.mips;
    if (!make_asset(f, w.terms, q, &out->asset, err, &out->counts)) return false;
    record_counts(r, capped.capped() - capped_before, ev.reference_rms(), out);
    out->asset.material.error_float = float(w.error_float * ev.reference_rms());
    out->asset.material.error_quantized = float(w.rms_quantized);
    out->asset.material.error_relative = float(w.error_quantized);
    out->asset.meta = asset_manifest(out->asset, brdf.spec(), method_name(w.method), w.res, o.key);
    return true;
}

}  // namespace sepal
