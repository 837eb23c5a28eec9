#include "bake/bake.h"
#include "bake/devices.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <unistd.h>

#include <glm/geometric.hpp>

#include "brdf/brdf_capped.h"
#include "brdf/brdf_util.h"
#include "factor/factor_error.h"
#include "util/json.h"
#include "bake/plan.h"
#include "bake/quantize.h"
#include "bake/radiance.h"
#include "util/parallel.h"
#include "sepal/sepal_asset.h"

namespace sepal {
namespace {

sepal_param to_fmt(Param p) {
    switch (p) {
        case Param::IncidentView: return SEPAL_PARAM_IV;
        case Param::GsHalf: return SEPAL_PARAM_GS_HALF;
        case Param::ViewHalf: return SEPAL_PARAM_VH;
        case Param::Rusinkiewicz: return SEPAL_PARAM_RUSINKIEWICZ;
        case Param::Axis: return SEPAL_PARAM_AXIS;
        case Param::GsMirror: return SEPAL_PARAM_GS_MIRROR;
        default: return SEPAL_PARAM_ELEV_AZIM;
    }
}

FactorOptions factor_options(const BakeOptions& o, Param param, HemiMap map, int res, int res_h, Method method,
                             int terms) {
    FactorOptions fo;
    fo.param = param;
    fo.map = map;
    fo.res = res;
    fo.res_h = res_h == res ? 0 : res_h;
    fo.terms = terms;
    fo.method = method;
    fo.colour = o.colour;
    fo.supersample = o.supersample;
    fo.threads = o.threads;
    fo.max_memory_mb = o.max_memory_mb;
    // The bake's own default for HALS (acls): 12 iterations per term count reach what the
    // multiplicative rule (nmf) reaches in 100 (measured on the README's materials).
    fo.iterations = o.iterations > 0 ? o.iterations : method == Method::ACLS ? 12 : 0;
    fo.matrix_error = false;  // unused here; for nd it would cost one more sampling pass
    return fo;
}

// Terms to factor for a search entry: the largest asked for, but no more than the sample
// matrix's rank can hold (1 at --res 1), so small resolutions still give their candidates.
int search_terms(Param param, HemiMap map, int res, int res_h, int max_terms) {
    FactorOptions shape;
    shape.param = param;
    shape.map = map;
    shape.res = res;
    shape.res_h = res_h == res ? 0 : res_h;
    int rows = 0, cols = 0;
    matrix_shape(shape, &rows, &cols);
    return std::max(1, std::min(max_terms, std::min(rows, cols)));
}

std::string rank_note(const FactorOptions& fo, int k) {
    return "--terms " + std::to_string(k) + " exceeds the rank the sample matrix can have at --res " +
           std::to_string(fo.res) + (fo.res_h > 0 ? "/" + std::to_string(fo.res_h) : std::string()) + " (at most " +
           std::to_string(fo.terms) + ")";
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

const std::vector<BakeMethod>& bake_methods() {
    // The one table of methods the bake searches; a new factorization is one more row.
    static const std::vector<BakeMethod> table = {
        {"acls", Method::ACLS, true, true},
        // wsvd: the SVD fitted to the entries above the horizon only; plain svd spends its
        // rank on the horizon's edge (Lambert: 22% error plain, 0.9% weighted, 32x32 gs-half).
        {"wsvd", Method::WSVD, false, true},
        {"svd", Method::SVD, false, false},
        {"nmf", Method::NMF, true, false},
        {"nd", Method::ND, false, false},
        // McCool, Ang and Ahmad 2001: p(wi) q(h) p(wo) fitted in log space (vh, parabolic, a
        // reciprocal material of format 2.1); positive factors, one pass per term.
        {"homomorphic", Method::Homomorphic, true, true},
    };
    return table;
}

bool method_allowed(Method m, Target t) {
    for (const BakeMethod& row : bake_methods())
        if (row.method == m) return row.non_negative || t == Target::Cpu;
    return false;
}

namespace {
// Image error in one number that grows with error (for fronts and tuples): -PSNR.
double image_error(const BakeCandidate& c) { return -c.psnr; }
bool budgeted(const BakeOptions& o) { return o.min_psnr >= 0 || o.max_error >= 0; }
// The direction-space metric decides the front only when it is the one budget given.
double front_error(const BakeCandidate& c, const BakeOptions& o) {
    return o.max_error >= 0 && o.min_psnr < 0 ? c.error_quantized : image_error(c);
}
}  // namespace

void mark_front(std::vector<BakeCandidate>* candidates, const BakeOptions& o) {
    // O(n^2): searches hold at most a few hundred candidates.
    for (BakeCandidate& c : *candidates) {
        c.on_front = c.ok && !c.coarse;
        if (!c.on_front) continue;
        for (const BakeCandidate& d : *candidates)
            if (d.ok && !d.coarse && d.ms <= c.ms && front_error(d, o) <= front_error(c, o) &&
                (d.ms < c.ms || front_error(d, o) < front_error(c, o))) {
                c.on_front = false;
                break;
            }
    }
}

double BakeCandidate::worst_view() const {
    return psnr_views.empty() ? psnr : *std::min_element(psnr_views.begin(), psnr_views.end());
}

// A candidate the winner and the fine judge weigh: encoded, past the coarse stage and within the budgets
// that do not read the image (bytes, passes).
bool rankable(const BakeCandidate& c, const BakeOptions& o) {
    return c.ok && !c.coarse && (o.max_passes < 0 || c.passes <= o.max_passes) &&
           (o.max_bytes < 0 || c.bytes <= o.max_bytes);
}

int choose_winner(std::vector<BakeCandidate>* candidates, const BakeOptions& o) {
    // The image figure less bytes_db per doubling of the asset's bytes.
    auto worth = [&o](const BakeCandidate& c) { return c.psnr - o.bytes_db * std::log2(double(std::max<int64_t>(c.bytes, 1))); };
    // Without budgets, candidates whose every view reaches goal_worst_db come first, when any
    // does: the asset is judged condition by condition, and a pooled figure hides the rim
    // light's view.
    auto holds = [&o](const BakeCandidate& c) { return o.goal_worst_db <= 0 || c.worst_view() >= o.goal_worst_db; };
    bool any_holds = false;
    for (BakeCandidate& c : *candidates) {
        c.meets = rankable(c, o) && !c.unranked && (o.max_error < 0 || c.error_quantized <= o.max_error) &&
                  (o.min_psnr < 0 || c.psnr >= o.min_psnr);
        any_holds = any_holds || (c.meets && holds(c));
    }
    auto eligible = [&](const BakeCandidate& c) { return c.meets && (budgeted(o) || !any_holds || holds(c)); };
    int best = -1;
    for (size_t i = 0; i < candidates->size(); ++i) {
        const BakeCandidate& c = (*candidates)[i];
        if (!eligible(c)) continue;
        if (best < 0) {
            best = int(i);
            continue;
        }
        // With an error budget, the fastest predicted frame, then the lower error of the
        // budget's kind (--max-error alone: direction space, as before the image judge);
        // without, the best image.
        const BakeCandidate& b = (*candidates)[size_t(best)];
        const bool better = budgeted(o) ? std::make_tuple(c.ms, front_error(c, o), c.bytes) <
                                              std::make_tuple(b.ms, front_error(b, o), b.bytes)
                                        : worth(c) > worth(b);
        if (better) best = int(i);
    }
    if (best < 0 || budgeted(o)) return best;
    // Within tie_db of the best worth: the fewest passes, then the fewest bytes, then the
    // better image.
    const double top = worth((*candidates)[size_t(best)]);
    for (size_t i = 0; i < candidates->size(); ++i) {
        const BakeCandidate& c = (*candidates)[i];
        const BakeCandidate& b = (*candidates)[size_t(best)];
        if (eligible(c) && worth(c) >= top - o.tie_db &&
            std::make_tuple(c.passes, c.bytes, image_error(c)) < std::make_tuple(b.passes, b.bytes, image_error(b)))
            best = int(i);
    }
    return best;
}

std::string BakeCandidate::label() const {
    char buf[112], size[32];
    if (res_h > 0 && res_h != res) std::snprintf(size, sizeof size, "%d/%d", res, res_h);
    else std::snprintf(size, sizeof size, "%d", res);
    std::snprintf(buf, sizeof buf, "%s/%s %s %s x%d %db", param_name(param), map_name(map), size, method_name(method),
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
    if (f.form == Form::Reciprocal) {
        if (f.radiance) {
            if (err) *err = "bake: reciprocal (homomorphic) factors are factors of f, not radiance factors";
            return false;
        }
        a.material.flags = SEPAL_MATERIAL_RECIPROCAL;
    }
    if (f.radiance) {
        a.material.flags = SEPAL_MATERIAL_RADIANCE;
        a.material.horizon = float(f.horizon);
        for (int c = 0; c < 3; ++c) a.material.diffuse[c] = float(f.diffuse[c]);
        if (f.diffuse_side >= 2 && (f.diffuse.x > 0 || f.diffuse.y > 0 || f.diffuse.z > 0)) {
            a.diffuse_side = uint32_t(f.diffuse_side);
            a.diffuse_profile = f.diffuse_profile;
        }
    }
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

std::string asset_manifest(const AssetData& a, const std::string& spec, const std::string& method,
                           const std::string& bake_key, const ManifestFit* fit) {
    // Provenance only, compact: the textures, scales, plan and errors are in the binary
    // chunks (sepal inspect prints them), and every byte of META ships with the material
    // (an 8 KB asset had 2.2 KB of indented JSON repeating them).
    Json j;
    j["spec"] = spec;
    j["method"] = method;
    if (!bake_key.empty()) j["bake_key"] = bake_key;
    if (fit) {
        // What the factors hold and the image that chose them (radiance.h, image_score.h).
        j["fit"] = {{"quantity", a.material.flags & SEPAL_MATERIAL_RADIANCE ? "radiance" : "brdf"},
                    {"white_level", fit->white},
                    {"target", fit->target},
                    {"psnr", std::round(fit->psnr * 100.0) / 100.0},
                    {"views", fit->views}};
        if (!fit->light_range.empty()) {
            char held[16], worst[16];
            std::snprintf(held, sizeof held, "%7.2f", fit->held_out_psnr);
            std::snprintf(worst, sizeof worst, "%7.2f", fit->held_out_worst);
            j["fit"]["light_range"] = fit->light_range;
            j["fit"]["held_out_psnr"] = held;
            j["fit"]["held_out_worst"] = worst;
        }
    }
    return dump_json_compact(j);
}

namespace {

// One factorization of the search and what its candidates need to know about it.
struct Factorization {
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 0;
    Method method = Method::NMF;
    bool coarse = false;
    FactorOptions fo;
    bool ok = false;
    std::string err;
    FactorResult result;
    int64_t capped = 0;  // evaluations the cap (or the radiance fit's white level) changed
};

// Terms of the bake's homomorphic candidates: the paper's single product. A sum of two
// (backfitting, homomorphic.h) is allowed by the format and `sepal factor`, but its second
// term's factors span too much for 8 bits (plans past 16 doublings on ward, 32x32).
constexpr int kBakeHomomorphicTerms = 1;

// The device profile the bake judges on (devices.h): "default" unless named.
const DeviceProfile& bake_profile(const BakeOptions& o) {
    const DeviceProfile* p = find_device_profile(o.profile.empty() ? "default" : o.profile);
    return p ? *p : default_device_profile();
}
bool custom_profile(const BakeOptions& o) { return !o.profile.empty() && o.profile != "default"; }
// What the candidates are judged on: "gles1", or "gles1:mali400" with a device profile.
std::string judged_on(const BakeOptions& o) {
    return custom_profile(o) ? std::string(target_name(o.target)) + ":" + o.profile : target_name(o.target);
}

// The judge's framebuffer and capability mask: the profile's (8 bits, mask 0 by default).
// A judge that ranks candidates (ranking) on a profile with framebuffer objects takes the
// 8-bit sum itself: the runtime writes it to the profile's framebuffer once, and that one
// rounding is every candidate's alike. Judged after it, the rounding's noise compressed the
// candidates' differences below tie_db, and the fewest passes won where they held worse
// (lafortune 2 lobes on mali400: 2 passes, 46.1 dB held out on 565, where the 5-pass asset
// drawn on 565 holds 48.1 against a limit of 48.7). Without them every pass rounds to the
// profile's bits, which the candidates' plans decide: judged so.
void configure_judge(const BakeOptions& o, ImageJudge* judge, bool ranking) {
    const ProfileLimits l = profile_limits(bake_profile(o));
    const int eight[3] = {8, 8, 8};
    judge->set_framebuffer(ranking && l.fbo ? eight : l.bits,
                           (l.blend_subtract ? 0u : uint32_t(SEPAL_MASK_BLEND_SUBTRACT)) |
                               (l.fbo ? 0u : uint32_t(SEPAL_MASK_FBO)));
}

// The bake's note on the device profile it judged for (custom_profile(o) only).
std::string profile_note(const BakeOptions& o) {
    const sepal_fmt_profile f = profile_record(bake_profile(o));
    char note[320];
    std::snprintf(note, sizeof note,
                  "device profile %s: judged at %u/%u/%u framebuffer bits (%s), textures at or under %u, %s; "
                  "recorded in the asset (its PROF chunk, format 2.4 on)",
                  f.name, f.red_bits, f.green_bits, f.blue_bits,
                  profile_limits(bake_profile(o)).fbo ? "ranked on the 8-bit sum written to them once"
                                                      : "every pass rounded to them",
                  f.max_texture_size,
                  (f.flags & SEPAL_PROFILE_BLEND_SUBTRACT) ? "blend subtraction" : "subtraction by inversion");
    return note;
}

// The profile's record (format 2.4) on an asset baked for one other than the default, before
// it is encoded (its bytes count it).
void stamp_profile(const BakeOptions& o, AssetData* a) {
    if (!custom_profile(o)) return;
    a->has_profile = true;
    a->profile = profile_record(bake_profile(o));
}

// Holds the search to the profile's texture limit: listed resolutions above it are refused,
// the ladder's rungs and the other fixed sides are clamped to it.
bool apply_profile(BakeOptions* o, std::string* err) {
    if (!custom_profile(*o)) return true;
    const DeviceProfile* p = find_device_profile(o->profile);
    if (!p) {
        if (err) *err = "bake: unknown device profile '" + o->profile + "' (profiles: " + device_profile_names() + ")";
        return false;
    }
    if (o->target != Target::Gles1) {
        if (err) *err = std::string("bake: device profiles are for gles1 (--target gles1:") + p->name + "), not " +
                        target_name(o->target);
        return false;
    }
    const int limit = profile_limits(*p).texture_limit;
    for (const std::vector<int>* list : {&o->resolutions, &o->smooth_resolutions})
        for (int r : *list)
            if (r > limit) {
                if (err)
                    *err = "bake: --res " + std::to_string(r) + " is over profile " + p->name + "'s texture limit " +
                           std::to_string(limit);
                return false;
            }
    for (auto& rung : o->ladder) rung.first = std::min(rung.first, limit), rung.second = std::min(rung.second, limit);
    o->ladder.erase(std::unique(o->ladder.begin(), o->ladder.end()), o->ladder.end());
    o->ladder_iv = std::min(o->ladder_iv, limit);
    o->small_rung = std::min(o->small_rung, limit);
    o->finer_other = std::min(o->finer_other, limit);
    o->coarse_res = std::min(o->coarse_res, limit);
    return true;
}

// The META a candidate ships with: its bytes count in BakeCandidate::bytes (--max-bytes is
// the file's size).
std::string shipped_manifest(const BakeCandidate& c, const std::string& spec, const BakeOptions& o,
                             const BakeResult& r) {
    ManifestFit fit;
    fit.white = r.white;
    if (!r.held_out_psnr_views.empty()) {
        fit.held_out_psnr = r.held_out_psnr;
        fit.held_out_worst = *std::min_element(r.held_out_psnr_views.begin(), r.held_out_psnr_views.end());
    }
    fit.target = judged_on(o);
    fit.psnr = c.psnr;
    fit.views = r.views;
    if (o.radiance) fit.light_range = describe_light_range(o.light_range);
    return asset_manifest(c.asset, spec, method_name(c.method), o.key, &fit);
}

// The light range's header fields (format 2.3) on a radiance asset, before it is encoded
// (its bytes count them).
void stamp_light_range(const BakeOptions& o, const BakeResult& r, AssetData* a) {
    if (!o.radiance) return;
    sepal_fmt_material& m = a->material;
    m.white_level = float(r.white);
    m.irradiance_min = float(r.irradiance_min);
    m.irradiance_max = float(std::max(r.irradiance_min, range_irradiance_max(o.light_range)));
    m.cone_degrees = float(o.light_range.cone_degrees);
    m.max_lights = uint32_t(o.light_range.max_lights);
}

class Search {
  public:
    // source: what the factors see; plain: f itself (capped at --cap), what homomorphic
    // factors fit (they are factors of f, not radiance factors).
    Search(const Brdf& brdf, const BakeOptions& o, BakeResult* out, const Brdf& source, const Brdf& plain,
           const ErrorEvaluator& ev, std::function<int64_t()> capped_count)
        : brdf_(brdf), o_(o), out_(out), source_(source), plain_(plain), ev_(ev), capped_count_(std::move(capped_count)) {}

    BakeResult* result() const { return out_; }

    // Best PSNR of the candidates appended since `first`.
    double best_since(size_t first) const {
        double b = -1e30;
        for (size_t c = first; c < out_->candidates.size(); ++c)
            if (out_->candidates[c].ok) b = std::max(b, out_->candidates[c].psnr);
        return b;
    }

    // The ladder from its first rung (best: that rung's best PSNR): each rung while the last
    // gained climb_db, then the other factor finer on the rung reached. It holds the view
    // (vh) or the light in the half-angle frame (gs-half), whose grazing end is the rim
    // highlight of a light behind the object. Not above a 64-texel sharp factor: at 128 x 32
    // the sample matrix and its weighted fit cost several times the rest of the bake.
    // Returns the rung the climb reached (0: it stayed on the first).
    size_t climb(Param param, HemiMap map, Method method, double best, const std::vector<int>& terms,
                 const ImageJudge& judge) {
        size_t reached = 0;
        for (size_t r = 1; r < o_.ladder.size(); ++r) {
            const size_t first = out_->candidates.size();
            run(param, map, o_.ladder[r].first, o_.ladder[r].second, method, terms, false, judge);
            const double b = best_since(first);
            const bool gained = b >= best + o_.climb_db;
            best = std::max(best, b);
            if (!gained) break;
            reached = r;
        }
        if (sharp_factor(param) >= 0 && o_.ladder[reached].second < o_.finer_other && o_.ladder[reached].first <= 64)
            run(param, map, o_.ladder[reached].first, o_.finer_other, method, terms, false, judge);
        return reached;
    }

    // Factors one (param, map, res, method) with up to max_terms terms and appends its
    // candidates (every listed term count and depth), judged on `judge`.
    // res: the sharp factor's side (param.h's sharp_factor; both sides for iv); res_other: the
    // other factor's.
    void run(Param param, HemiMap map, int res, int res_other, Method method, const std::vector<int>& terms,
             bool coarse, const ImageJudge& judge) {
        const int max_terms = *std::max_element(terms.begin(), terms.end());
        const int sharp = sharp_factor(param);
        // Homomorphic: p and q share the half-angle factor's resolution, at most
        // SEPAL_FMT_MAX_RECIPROCAL_TERMS terms.
        const bool homomorphic = method == Method::Homomorphic;
        const int res_g = homomorphic ? res : sharp == 1 ? res_other : res, res_h = sharp == 0 ? res_other : res;
        Factorization fz;
        fz.param = param, fz.map = map, fz.res = res_g, fz.method = method, fz.coarse = coarse;
        fz.fo = factor_options(o_, param, map, res_g, res_h, method,
                               homomorphic ? std::min(max_terms, kBakeHomomorphicTerms)
                                           : search_terms(param, map, res_g, res_h, max_terms));
        if (o_.progress && isatty(2))
            std::fprintf(stderr, "\rbake: factoring %s/%s %d/%d %s x%d%s        ", param_name(param), map_name(map),
                         res_g, res_h, method_name(method), fz.fo.terms, coarse ? " (coarse)" : "");
        const int64_t before = capped_count_();
        const auto t0 = std::chrono::steady_clock::now();
        // Homomorphic factors hold f: capped where f cos theta_i is white under every light of the range
        // (the radiance fit's white level), so p and q keep their 8 bits for what shows.
        if (homomorphic && o_.radiance) fz.fo.homomorphic.white = out_->white;
        if (!homomorphic && o_.radiance && o_.fit_weight == BakeOptions::FitWeight::Display) {
            const double emax = range_irradiance_max(o_.light_range);
            fz.fo.value_weight = [emax](const glm::dvec3& v) { return display_weight(v, emax); };
        }
        // Under the horizon window an error in the factors shows times w(cos theta_i): weighed
        // by w^2, the fit minimizes the drawn error as it did without the window (a floor, as
        // for entries below the horizon, keeps the band's entries in the solve).
        if (!homomorphic && o_.radiance && out_->horizon > 0) {
            const double c0 = out_->horizon;
            fz.fo.confidence = [c0](const glm::dvec3& wi, const glm::dvec3&) {
                const double w = sepal_horizon_window(float(c0), float(wi.z));
                return std::max(w * w, 0.01);
            };
        }
        fz.ok = factor_brdf(homomorphic ? plain_ : source_, fz.fo, &fz.result, &fz.err);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        fz.capped = capped_count_() - before;
        if (fz.ok && !homomorphic)
            for (Factored& f : fz.result.by_terms) {
                f.radiance = o_.radiance;
                f.horizon = out_->horizon;
                f.diffuse = out_->diffuse.scale;
                f.diffuse_side = out_->diffuse.side;
                f.diffuse_profile = out_->diffuse.profile;
            }
        const size_t first = out_->candidates.size();
        for (int k : terms)
            for (int bits : o_.bits) {
                if (coarse && bits != o_.bits[0]) continue;
                if (homomorphic && k > kBakeHomomorphicTerms) continue;  // not searched: no row
                BakeCandidate c;
                c.param = param;
                c.map = map;
                c.res = res_g;
                c.res_h = res_h;
                c.terms = k;
                c.bits = bits;
                c.method = method;
                c.coarse = coarse;
                c.factor_seconds = seconds;
                if (!fz.ok || k > fz.fo.terms) {
                    c.note = fz.ok ? rank_note(fz.fo, k) : fz.err;
                    out_->candidates.push_back(std::move(c));
                    continue;
                }
                const Factored& f = fz.result.by_terms[size_t(k - 1)];
                QuantizeOptions q;
                q.bits = bits;
                q.mips = o_.mips;
                std::vector<uint8_t> bytes;
                const bool made = make_asset(f, k, q, &c.asset, &c.note);
                if (made) stamp_light_range(o_, *out_, &c.asset), stamp_profile(o_, &c.asset);
                if (!made || !encode_asset(c.asset, &bytes, &c.note)) {
                    out_->candidates.push_back(std::move(c));
                    continue;
                }
                c.ok = true;
                c.passes = int(c.asset.passes.size());
                c.non_negative = f.non_negative();
                c.bytes = int64_t(bytes.size());
                c.ms = out_->cost.predict(c.passes, c.terms, c.bytes);
                bytes_.push_back(std::move(bytes));
                owner_.push_back(factorizations_.size());
                out_->candidates.push_back(std::move(c));
                index_.push_back(out_->candidates.size() - 1);
            }
        // Judge and measure this factorization's candidates.
        std::vector<size_t> mine;
        for (size_t i = 0; i < index_.size(); ++i)
            if (index_[i] >= first) mine.push_back(i);
        judge_images(mine, judge);
        for (size_t j = 0; j < mine.size(); ++j) {
            BakeCandidate& c = out_->candidates[index_[mine[j]]];
            if (!c.ok) continue;
            const Factored& f = fz.result.by_terms[size_t(c.terms - 1)];
            c.error_float = ev_.measure(f).relative;
            const ApproxError qe = ev_.measure(dequantize(c.asset, f));
            c.error_quantized = qe.relative;
            c.rms_quantized = qe.rms;
            if (!c.coarse) {
                // What ships: the same chunks and the manifest with this image's figure.
                c.asset.meta = shipped_manifest(c, brdf_.spec(), o_, *out_);
                std::vector<uint8_t> shipped;
                if (encode_asset(c.asset, &shipped, &c.note)) {
                    c.bytes = int64_t(shipped.size());
                    c.ms = out_->cost.predict(c.passes, c.terms, c.bytes);
                }
            }
            // The asset stays for the winner (no second factorization); the coarse stage's
            // are never shipped.
            if (c.coarse) c.asset = AssetData{};
        }
        factorizations_.push_back(std::move(fz));
    }

    // The encoded candidates (not the coarse stage's) with a figure of at least `floor`
    // judged again on `judge` (their images only: the direction-space figures and the bytes
    // stay); the others become unranked.
    void rejudge(const ImageJudge& judge, double floor) {
        std::vector<size_t> mine;
        for (size_t i = 0; i < index_.size(); ++i) {
            BakeCandidate& c = out_->candidates[index_[i]];
            if (!c.ok || c.coarse) continue;
            if (rankable(c, o_) && c.psnr >= floor) mine.push_back(i);
            else c.unranked = true;
        }
        judge_images(mine, judge);
    }

    // The factorization a candidate came from.
    const Factorization* factorization_of(size_t candidate) const {
        for (size_t i = 0; i < index_.size(); ++i)
            if (index_[i] == candidate) return &factorizations_[owner_[i]];
        return nullptr;
    }

  private:
    // The encoded candidates `mine` (indices into bytes_) judged on `judge`: their image
    // figures, or ok = false with the judge's error. Images in parallel, each independent and
    // single-threaded, so the result does not depend on the threads.
    void judge_images(const std::vector<size_t>& mine, const ImageJudge& judge) {
        std::vector<std::string> errors(mine.size());
        std::vector<ImageScore> scores(mine.size());
        parallel_for(mine.size(), o_.threads, [&](size_t j) {
            judge.score(bytes_[mine[j]], o_.target, &scores[j], &errors[j]);
        });
        for (size_t j = 0; j < mine.size(); ++j) {
            BakeCandidate& c = out_->candidates[index_[mine[j]]];
            if (!errors[j].empty()) {
                c.ok = false;
                c.note = errors[j];
                continue;
            }
            c.psnr = scores[j].psnr;
            c.psnr_views = scores[j].per_view;
            c.doublings = scores[j].doublings;
        }
    }

    const Brdf& brdf_;
    const BakeOptions& o_;
    BakeResult* out_;
    const Brdf& source_;
    const Brdf& plain_;
    const ErrorEvaluator& ev_;
    std::function<int64_t()> capped_count_;
    std::vector<Factorization> factorizations_;
    std::vector<std::vector<uint8_t>> bytes_;  // per encoded candidate
    std::vector<size_t> owner_, index_;         // its factorization, its candidate index
};

// The winner (out->asset) on the held-out conditions: the figure the bake reports first.
bool held_out(const Brdf& brdf, const BakeOptions& o, BakeResult* out, std::string* err) {
    const std::vector<LightCondition> conditions = held_out_conditions(o.light_range);
    std::vector<BakeView> views;
    ImageJudge judge;
    std::vector<uint8_t> bytes;
    ImageScore s;
    if (!condition_views(conditions, &views, err) || !judge.init(brdf, views, out->judge_size, o.threads, err))
        return false;
    configure_judge(o, &judge, false);
    if (!encode_asset(out->asset, &bytes, err) || !judge.score(bytes, o.target, &s, err)) return false;
    out->held_out_psnr = s.psnr;
    out->held_out_psnr_views = s.per_view;
    out->held_out_share16 = s.share_over16;
    // The flags reproduce the figure: the judge's size, not sepal render's default 512.
    const std::string size = " --size " + std::to_string(out->judge_size) + "x" + std::to_string(out->judge_size);
    for (const LightCondition& c : conditions) {
        out->held_out_views.push_back(c.name);
        out->held_out_flags.push_back(c.flags() + size);
    }
    return true;
}

constexpr int kMaxJudgeSize = 2048;

// The best figure of the ranked candidates, and whether one with a sharp factor of
// fine_judge_texels or more is within fine_judge_db of it (BakeOptions::fine_judge_texels).
bool fine_judge_needed(const std::vector<BakeCandidate>& candidates, const BakeOptions& o, double* best) {
    if (o.fine_judge_texels <= 0 || 2 * o.judge_size > kMaxJudgeSize) return false;
    *best = -1e30;
    for (const BakeCandidate& c : candidates)
        if (rankable(c, o)) *best = std::max(*best, c.psnr);
    for (const BakeCandidate& c : candidates) {
        if (!rankable(c, o) || c.psnr < *best - o.fine_judge_db) continue;
        const int sharp = sharp_factor(c.param);
        const int texels = sharp == 0 ? c.res : sharp == 1 ? c.res_h : std::max(c.res, c.res_h);
        if (texels >= o.fine_judge_texels) return true;
    }
    return false;
}

// The front-runners judged again at twice the judge's size when one needs it (above), the
// rest unranked; sets out->judge_size to the size the winner is chosen at.
bool fine_judge(const Brdf& brdf, const BakeOptions& o, const std::vector<BakeView>& views, Search& search,
                BakeResult* out, std::string* err) {
    out->judge_size = o.judge_size;
    double best = 0;
    if (!fine_judge_needed(out->candidates, o, &best)) return true;
    const int size = 2 * o.judge_size;
    if (o.progress && isatty(2)) std::fprintf(stderr, "\rbake: judging again at %dx%d        ", size, size);
    ImageJudge fine;
    if (!fine.init(brdf, views, size, o.threads, err)) return false;
    configure_judge(o, &fine, true);
    search.rejudge(fine, best - o.fine_keep_db);
    out->judge_size = size;
    char note[240];
    std::snprintf(note, sizeof note, "judged at %dx%d: a candidate within %.2g dB of the best has a sharp factor of %d "
                  "or more texels a side, finer than %dx%d images resolve; the candidates within %.2g dB of the best "
                  "judged again and ranked", size, size, o.fine_judge_db, o.fine_judge_texels, o.judge_size,
                  o.judge_size, o.fine_keep_db);
    out->notes.push_back(note);
    return true;
}

bool validate_options(const BakeOptions& o, const std::vector<Method>& methods, int* max_terms, std::string* err) {
    auto fail = [&](const std::string& m) {
        if (err) *err = "bake: " + m;
        return false;
    };
    if (o.params.empty() || o.maps.empty() || o.terms.empty() || methods.empty() || o.bits.empty())
        return fail("an empty search list");
    const size_t searches = o.params.size() * o.maps.size() * std::max<size_t>(1, o.resolutions.size()) * methods.size();
    if (searches > 64)
        return fail(std::to_string(searches) + " factorizations to search; at most 64 (narrow a list)");
    *max_terms = 0;
    for (int k : o.terms) {
        if (k < 1 || k > SEPAL_FMT_MAX_TERMS)
            return fail("--terms " + std::to_string(k) + " outside 1.." + std::to_string(SEPAL_FMT_MAX_TERMS));
        *max_terms = std::max(*max_terms, k);
    }
    for (int b : o.bits)
        if (b != 8 && b != 16) return fail("--bits " + std::to_string(b) + ": 8 or 16");
    std::vector<int> all = o.resolutions;
    all.insert(all.end(), o.smooth_resolutions.begin(), o.smooth_resolutions.end());
    if (o.resolutions.empty()) {
        if (o.ladder.empty()) return fail("an empty resolution ladder");
        all.push_back(o.ladder_iv);
        all.push_back(o.small_rung);
        for (const auto& r : o.ladder) all.push_back(r.first), all.push_back(r.second);
    }
    for (int r : all)
        if (r < 1 || r > 256 || (r & (r - 1)))
            return fail("--res " + std::to_string(r) + ": a power of two in 1..256 (GL ES 1.1 textures)");
    if (o.target != Target::Cpu)
        for (Param p : o.params)
            if (!hardware_compatible(p))
                return fail(std::string("--param ") + param_name(p) + " needs per-pixel coordinates: --target cpu");
    if (o.judge_size < 8 || o.judge_size > kMaxJudgeSize ||
        (o.coarse_res > 0 && (o.coarse_size < 8 || o.coarse_size > kMaxJudgeSize)))
        return fail("judged images must be 8..2048 pixels per side");
    if (!(o.horizon >= 0 && o.horizon <= 1))
        return fail("--horizon " + std::to_string(o.horizon) + " outside 0..1 (a cosine; 0: none)");
    return true;
}

}  // namespace

double colour_residual(const Brdf& f) {
    Rng rng(0xc01005u);
    std::vector<glm::dvec3> values;
    values.reserve(4096);
    double ll = 0;
    glm::dvec3 cl(0.0);
    for (int i = 0; i < 4096; ++i) {
        const glm::dvec3 wi = rng.hemisphere(), wo = rng.hemisphere();
        const glm::dvec3 c = f.eval(wi, wo);
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) continue;
        const double l = luminance(c);
        ll += l * l;
        cl += c * l;
        values.push_back(c);
    }
    if (!(ll > 0)) return 0.0;  // black (or nothing finite): any ratio holds it
    const glm::dvec3 ratio = cl / ll;
    double residual = 0, total = 0;
    for (const glm::dvec3& c : values) {
        const glm::dvec3 d = c - ratio * luminance(c);
        residual += glm::dot(d, d);
        total += glm::dot(c, c);
    }
    return std::sqrt(residual / total);
}

namespace {

using Pair = std::tuple<Param, HemiMap, Method>;

// The coarse stage: every (param, map, method) at coarse_res, ranked (all_pairs), and the
// best few kept (pairs).
void coarse_stage(Search& search, const BakeOptions& o, int max_terms, const ImageJudge& coarse_judge,
                  std::vector<Pair>* pairs_out, std::vector<Pair>* all_pairs) {
    std::vector<Pair>& pairs = *pairs_out;
    BakeResult* out = search.result();
    std::vector<double> best(pairs.size(), -1e30);
    for (size_t i = 0; i < pairs.size(); ++i) {
        const size_t first = out->candidates.size();
        std::vector<int> coarse_terms;
        for (int k : o.terms)
            if (k <= o.coarse_terms) coarse_terms.push_back(k);
        if (coarse_terms.empty()) coarse_terms.push_back(std::min(max_terms, o.coarse_terms));
        search.run(std::get<0>(pairs[i]), std::get<1>(pairs[i]), o.coarse_res, o.coarse_res, std::get<2>(pairs[i]),
                   coarse_terms, true, coarse_judge);
        for (size_t c = first; c < out->candidates.size(); ++c)
            if (out->candidates[c].ok) best[i] = std::max(best[i], out->candidates[c].psnr);
    }
    std::vector<size_t> order(pairs.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return best[a] > best[b]; });
    // Two families, each keeping its best and those within keep_db of it (at most keep):
    // Kautz-McCool's parameterizations with homomorphic, and axis, which is kept only
    // within keep_db of the best overall. At 16 texels axis's rank does not predict its
    // rank against the half-angle ones on the ladder (blinn: axis led the coarse stage by
    // 1.8 dB and took a half-angle pair's place, 49.4 -> 46.4 dB; gs-half wins at 64/16).
    auto is_axis = [](const std::tuple<Param, HemiMap, Method>& q) { return std::get<0>(q) == Param::Axis; };
    double family_best[2] = {-1e30, -1e30};
    for (size_t i : order) family_best[is_axis(pairs[i])] = std::max(family_best[is_axis(pairs[i])], best[i]);
    int family_kept[2] = {0, 0};
    std::vector<std::tuple<Param, HemiMap, Method>> kept, ranked;
    for (size_t i : order) {
        ranked.push_back(pairs[i]);
        const int f = is_axis(pairs[i]);
        if (family_kept[f] < std::max(1, o.keep) && best[i] > -1e30 && best[i] >= family_best[f] - o.keep_db &&
            (f == 0 || best[i] >= best[order[0]] - o.keep_db)) {
            kept.push_back(pairs[i]);
            ++family_kept[f];
        }
    }
    *all_pairs = ranked;
    if (!kept.empty()) pairs = kept;
}

// Listed resolutions: every one (the grid), no climbing.
void grid(Search& search, const BakeOptions& o, const std::vector<int>& terms, const ImageJudge& judge,
          const std::vector<Pair>& pairs) {
    for (const auto& p : pairs)
        for (int res : o.resolutions) {
            // The sharp factor (half-angle, axis's G) at res with the other one at each of smooth_resolutions not
            // above it (or at res too); iv's two factors always alike.
            std::vector<int> others = {res};
            if (!o.smooth_resolutions.empty() && sharp_factor(std::get<0>(p)) >= 0) {
                others.clear();
                for (int r : o.smooth_resolutions)
                    if (r <= res) others.push_back(r);
            }
            for (int other : others)
                search.run(std::get<0>(p), std::get<1>(p), res, other, std::get<2>(p), terms, false, judge);
        }
}

// The ladder: every kept pair on its first rung; the best one with a sharp factor
// (half-angle, axis's G) climbs while a rung gains climb_db (a sharper lobe needs a finer
// sharp factor; iv has no such factor and stays on its rung); the runner-up within
// second_climb_db of it tries the finer other factor on the first rung. Returns both (the
// pairs more_terms extends).
std::vector<Pair> ladder(Search& search, const BakeOptions& o, const std::vector<int>& terms, const ImageJudge& judge,
                         std::vector<Pair> pairs, const std::vector<Pair>& all_pairs) {
    BakeResult* out = search.result();
    auto best_since = [&search](size_t first) { return search.best_since(first); };
    // The climber: the best pair with a sharp factor on the first rung, a sum-of-products one
    // (its term count grows on the way) before a homomorphic one (one product).
    auto climber_rank = [](const std::tuple<Param, HemiMap, Method>& q) {
        return sharp_factor(std::get<0>(q)) < 0 ? 0 : std::get<2>(q) == Method::Homomorphic ? 1 : 2;
    };
    double top = -1e30;
    int top_pair = -1, top_rank = 0;
    std::vector<double> rung_best(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) {
        const Param param = std::get<0>(pairs[i]);
        const bool sharp = sharp_factor(param) >= 0;
        const auto rung = sharp ? o.ladder[0] : std::make_pair(o.ladder_iv, o.ladder_iv);
        const size_t first = out->candidates.size();
        search.run(param, std::get<1>(pairs[i]), rung.first, rung.second, std::get<2>(pairs[i]), terms, false, judge);
        rung_best[i] = best_since(first);
        const int rank = climber_rank(pairs[i]);
        if (rank > 0 && (rank > top_rank || (rank == top_rank && rung_best[i] > top)))
            top = rung_best[i], top_pair = int(i), top_rank = rank;
    }
    // A sum-of-products half-angle pair always reaches the first rung: the coarse stage's
    // 16 texels resolve no narrow lobe (ward's ay = 0.02 is 22.9-26 dB in every
    // parameterization there, axis or iv ahead), and only a half-angle factor resolves a
    // narrow isotropic lobe on the finer rungs (ward: gs-half 128/8 39.8 dB, axis 25.7).
    auto half_sop = [](const std::tuple<Param, HemiMap, Method>& q) {
        return half_angle_factor(std::get<0>(q)) >= 0 && std::get<2>(q) != Method::Homomorphic;
    };
    if (o.coarse_res > 0 && std::none_of(pairs.begin(), pairs.end(), half_sop))
        for (const auto& q : all_pairs)
            if (half_sop(q)) {
                pairs.push_back(q);
                const size_t first = out->candidates.size();
                search.run(std::get<0>(q), std::get<1>(q), o.ladder[0].first, o.ladder[0].second, std::get<2>(q),
                           terms, false, judge);
                rung_best.push_back(best_since(first));
                if (top_rank < 2 || rung_best.back() > top)
                    top = rung_best.back(), top_pair = int(pairs.size() - 1), top_rank = 2;
                break;
            }
    // A narrow isotropic lobe is resolved only by a half-angle factor on the finer rungs:
    // within tie_db of axis on the first rung the half-angle pair climbs (phong n=1000
    // under the 8:1 range: axis 29.44 dB against vh 29.35, axis 64/16 29.9 dB, vh 8/128
    // 39.0). Further behind it does not (lafortune: axis 42.79, gs-half 42.45; climbed,
    // gs-half 128/8 won by 0.9 dB at 7 times the bytes).
    auto best_half = [&]() {  // the half-angle sum-of-products pair best on the first rung, or -1
        int half = -1;
        for (size_t i = 0; i < pairs.size(); ++i)
            if (half_sop(pairs[i]) && (half < 0 || rung_best[i] > rung_best[size_t(half)])) half = int(i);
        return half;
    };
    if (top_pair >= 0 && std::get<0>(pairs[size_t(top_pair)]) == Param::Axis) {
        const int half = best_half();
        if (half >= 0 && rung_best[size_t(half)] >= top - o.tie_db) top_pair = half;
    }
    // The first rung does not settle which half-angle pair wins once both factors are finer:
    // ward-duer's vh led gs-half there by 0.5 dB, and at 32/32 with eight terms gs-half led
    // by 1.0 dB in training and by 1.3 dB in its worst held-out condition (37.6 -> 38.9 dB).
    // So when the climber is a half-angle pair that stayed on the first rung, the other
    // half-angle pair within second_climb_db of it there tries the finer other factor too
    // (only that: its own climb cost cayman's bake 5 s and changed no winner).
    std::vector<Pair> climbers;
    if (top_pair >= 0) {
        const Pair top = pairs[size_t(top_pair)];
        climbers.push_back(top);
        const size_t reached =
            search.climb(std::get<0>(top), std::get<1>(top), std::get<2>(top), rung_best[size_t(top_pair)], terms, judge);
        int second = -1;
        for (size_t i = 0; reached == 0 && half_sop(top) && i < pairs.size(); ++i)
            if (half_sop(pairs[i]) && std::get<0>(pairs[i]) != std::get<0>(top) &&
                rung_best[i] >= rung_best[size_t(top_pair)] - o.second_climb_db &&
                (second < 0 || rung_best[i] > rung_best[size_t(second)]))
                second = int(i);
        if (second >= 0 && o.ladder[0].second < o.finer_other) {
            const Pair& p = pairs[size_t(second)];
            climbers.push_back(p);
            search.run(std::get<0>(p), std::get<1>(p), o.ladder[0].first, o.finer_other, std::get<2>(p), terms, false,
                       judge);
        }
        // gs-mirror holds a lobe about the mirror direction in one product (phong n=1000: 1
        // term at 16/64, 43.3 dB, where vh took 8 terms at 8/128 for 39.4) and a half-angle
        // lobe only roughly, yet on the first rung it can lead the half-angle pairs of a
        // narrow half-angle lobe that only their finer rungs resolve (ward: gs-mirror climbed
        // to 16/32 x6, 29.9 dB, where gs-half reaches 45.7 at 128/8). So when it climbs, the
        // best half-angle pair climbs too.
        if (std::get<0>(top) == Param::GsMirror) {
            const int half = best_half();
            if (half >= 0) {
                const Pair& p = pairs[size_t(half)];
                climbers.push_back(p);
                search.climb(std::get<0>(p), std::get<1>(p), std::get<2>(p), rung_best[size_t(half)], terms, judge);
            }
        }
    }
    if (o.max_bytes > 0)
        for (const auto& q : pairs)
            search.run(std::get<0>(q), std::get<1>(q), o.small_rung, o.small_rung, std::get<2>(q), terms, false,
                       judge);
    return climbers;
}

// More terms, while the largest term count still paid: the best candidate's configuration
// with each of more_terms (a new factorization, warm-started term by term as always), and
// the best configuration of each other pair that climbed (a pair behind at four terms may
// lead at eight: ward-duer's gs-half 32/32, 43.1 -> 45.0 dB, against vh's 43.5 -> 43.8).
void more_terms(Search& search, const BakeOptions& o, const std::vector<int>& terms, const ImageJudge& judge,
                const std::vector<Pair>& climbers) {
    BakeResult* out = search.result();
    std::vector<BakeCandidate> bests;
    const int w = choose_winner(&out->candidates, o);
    if (w >= 0) bests.push_back(out->candidates[size_t(w)]);
    for (const Pair& p : climbers) {
        if (!bests.empty() && std::get<0>(p) == bests[0].param) continue;
        std::vector<BakeCandidate> own;
        for (const BakeCandidate& c : out->candidates)
            if (c.ok && !c.coarse && c.param == std::get<0>(p) && c.map == std::get<1>(p) && c.method == std::get<2>(p))
                own.push_back(c);
        // Only a contender: within second_climb_db of the winner before more terms.
        const int b = choose_winner(&own, o);
        if (b >= 0 && (bests.empty() || own[size_t(b)].psnr >= bests[0].psnr - o.second_climb_db))
            bests.push_back(own[size_t(b)]);
    }
    for (const BakeCandidate& b : bests) {
        double previous = -1e30;
        for (const BakeCandidate& c : out->candidates)
            if (c.ok && !c.coarse && c.param == b.param && c.map == b.map && c.res == b.res &&
                c.res_h == b.res_h && c.method == b.method && c.terms == terms.back() - 1)
                previous = c.psnr;
        double at_max = -1e30;
        for (const BakeCandidate& c : out->candidates)
            if (c.ok && !c.coarse && c.param == b.param && c.map == b.map && c.res == b.res &&
                c.res_h == b.res_h && c.method == b.method && c.terms == terms.back())
                at_max = c.psnr;
        const bool short_of_goal = b.psnr < o.goal_db || (o.goal_worst_db > 0 && b.worst_view() < o.goal_worst_db);
        if (short_of_goal && at_max >= previous + o.more_terms_db && at_max >= b.psnr - o.tie_db) {
            const int sharp = sharp_factor(b.param);
            const int res = sharp == 1 ? b.res_h : b.res, other = sharp == 1 ? b.res : b.res_h;
            std::vector<int> more;
            for (int k : o.more_terms)
                if (k > terms.back() && k <= SEPAL_FMT_MAX_TERMS) more.push_back(k);
            if (!more.empty()) search.run(b.param, b.map, res, other, b.method, more, false, judge);
        }
    }
}

// Why no candidate won: every one failed (the first reason; all are listed), or none met
// the budgets.
std::string no_winner(const std::vector<BakeCandidate>& candidates, const BakeOptions& o) {
    double closest = -1e30;
    std::string label;
    for (const BakeCandidate& c : candidates)
        if (c.ok && !c.coarse && c.psnr > closest) closest = c.psnr, label = c.label();
    if (label.empty()) {
        for (const BakeCandidate& c : candidates)
            if (!c.ok) return "bake: every candidate failed; " + c.label() + ": " + c.note;
        return "bake: no candidate";
    }
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "bake: no candidate meets the budgets (best image %.2f dB on %s, %s); allow more terms, "
                  "a higher --res, or loosen --min-psnr/--max-error/--max-passes/--max-bytes",
                  closest, judged_on(o).c_str(), label.c_str());
    return buf;
}

// Why the winner won, and a note when it misses half of f in direction space.
void winner_notes(const BakeCandidate& w, const BakeOptions& o, size_t views, BakeResult* out) {
    char why[320];
    if (budgeted(o)) {
        std::snprintf(why, sizeof why, "%s: the fastest predicted frame (%.2f ms on %s, %d pass%s per light) at %.2f dB on %s%s",
                      w.label().c_str(), w.ms, out->cost.backend.c_str(), w.passes, w.passes == 1 ? "" : "es", w.psnr,
                      judged_on(o).c_str(), o.min_psnr >= 0 ? "" : " within --max-error");
    } else {
        // Says which candidates it was chosen among (choose_winner's rule).
        char among[96] = "";
        if (o.goal_worst_db > 0)
            std::snprintf(among, sizeof among, w.worst_view() >= o.goal_worst_db ? "; among those with every view >= %.3g dB"
                                                                               : "; no candidate has every view >= %.3g dB",
                          o.goal_worst_db);
        std::snprintf(why, sizeof why, "%s: the best image on %s (%.2f dB over %zu views, the worst %.2f dB%s; within %.2g dB "
                      "of the best, the fewest passes, then bytes)",
                      w.label().c_str(), judged_on(o).c_str(), w.psnr, views, w.worst_view(), among, o.tie_db);
    }
    out->why = why;
    // A winner that misses half of f in direction space (relative cosine-weighted RMS >= 0.5)
    // may still be the best image, but a user should hear it: sharp lobes below the texel
    // size, grazing peaks, or a cap account for it (README "Extremes").
    if (w.error_quantized >= 0.5) {
        char buf[360];
        std::snprintf(buf, sizeof buf,
                      "the winner's relative error is %.3g (>= 0.5) over uniform direction pairs: f has detail the "
                      "factors do not hold (lobes narrower than a texel, grazing peaks%s); the image figure is %.2f dB",
                      w.error_quantized, o.radiance || o.cap > 0 ? ", or the white level or --cap" : "", w.psnr);
        out->notes.push_back(buf);
    }
}

// The radiance fit's note: the cap's share of the samples and the diffuse part.
void radiance_note(const RadianceBrdf& radiance, BakeResult* out) {
    char note[320];
    char cap[96] = "not capped";
    if (out->white > 0)
        std::snprintf(cap, sizeof cap, "capped at %.3g/sr (white under every light of the range), %.3g%% of the samples",
                      out->white,
                      radiance.evaluations() ? 100.0 * double(radiance.capped()) / double(radiance.evaluations()) : 0.0);
    std::snprintf(note, sizeof note, "radiance fit: f cos(theta_i) %s; diffuse part %.3g %.3g %.3g /sr%s drawn untextured",
                  cap,
                  out->diffuse.scale.x, out->diffuse.scale.y, out->diffuse.scale.z,
                  out->diffuse.side ? " at most, a profile over the two cosines," : "");
    out->notes.push_back(note);
    out->capped_share = radiance.evaluations() ? double(radiance.capped()) / double(radiance.evaluations()) : 0.0;
}

}  // namespace

bool bake(const Brdf& brdf, const BakeOptions& options, BakeResult* out, std::string* err) {
    const auto start = std::chrono::steady_clock::now();
    *out = BakeResult{};
    // Term counts left empty: 1..4, climbing to more below the goal.
    BakeOptions o = options;
    const bool auto_terms = o.terms.empty();
    if (auto_terms) o.terms = {1, 2, 3, 4};
    o.climb_terms = o.climb_terms && auto_terms;
    out->target = o.target;
    out->target_label = judged_on(o);
    std::vector<Method> methods = o.methods;
    if (methods.empty())
        for (const BakeMethod& row : bake_methods())
            if (row.default_method && method_allowed(row.method, o.target)) methods.push_back(row.method);
    int max_terms = 0;
    if (!apply_profile(&o, err) || !validate_options(o, methods, &max_terms, err)) return false;
    out->cost = o.cost;
    if (out->cost.backend.empty() && !default_cost_model("gles1", &out->cost, err)) return false;
    out->counts.input = brdf.input_counts();
    // Asked for by name only: the default search never gives an 8-bit target bias passes.
    for (Method m : methods)
        if (!method_allowed(m, o.target))
            out->notes.push_back(std::string("--method ") + method_name(m) + " gives signed factors: on " +
                                 target_name(o.target) + " they need bias passes, whose partial sums the 8-bit "
                                 "framebuffer rounds (compare the PSNR column)");
    // The judges: exact references of the training views (the range's conditions, or the
    // given views), small ones for the coarse stage; the held-out views judge the winner.
    if (!validate_light_range(o.light_range, err)) return false;
    std::vector<BakeView> views = o.views;
    if (views.empty() && !condition_views(training_conditions(o.light_range), &views, err)) return false;
    for (const BakeView& v : views) out->views.push_back(v.name);
    const int finest = o.resolutions.empty() ? std::min(o.ladder_iv, o.ladder[0].first)
                                             : *std::min_element(o.resolutions.begin(), o.resolutions.end());
    const bool coarse = o.coarse_res > 0 && o.params.size() * o.maps.size() * methods.size() > 1 && finest > o.coarse_res &&
                        !(methods.size() == 1 && methods[0] == Method::Homomorphic);
    ImageJudge judge, coarse_judge;
    if (!judge.init(brdf, views, o.judge_size, o.threads, err)) return false;
    if (coarse && !coarse_judge.init(brdf, views, o.coarse_size, o.threads, err)) return false;
    configure_judge(o, &judge, true);
    configure_judge(o, &coarse_judge, true);
    // What the factors see: f capped at --cap, and for the radiance fit f cos(theta_i) capped
    // at the views' white level minus the diffuse part. Every error is measured against the
    // original BRDF.
    const CappedBrdf capped(brdf, o.cap);
    const Brdf& base = o.cap > 0 ? static_cast<const Brdf&>(capped) : brdf;
    if (o.radiance) {
        // The white level follows from the dimmest light (with given views, the dimmer of
        // theirs and the range's): 1.25 / its irradiance, so a light at the bound still shows
        // the cap above white where the mesh is up to 12% farther from it than its centre.
        double dimmest = range_irradiance_min(o.light_range);
        if (!o.views.empty() && judge.min_irradiance() > 0) dimmest = std::min(dimmest, judge.min_irradiance());
        out->white = o.white > 0 ? o.white : o.white < 0 ? 0.0 : 1.25 / dimmest;
        out->irradiance_min = o.white > 0 ? 1.0 / o.white : o.white < 0 ? 0.0 : dimmest;
        if (o.diffuse_given) out->diffuse.scale = o.diffuse;
        else if (o.diffuse_side > 0) out->diffuse = estimate_diffuse_profile(base, o.diffuse_side, o.threads);
        else out->diffuse.scale = estimate_diffuse(base, o.diffuse_quantile, o.threads);
    }
    out->horizon = o.radiance ? o.horizon : 0.0;
    RadianceTarget rt;
    rt.white = out->white;
    rt.diffuse = out->diffuse;
    rt.horizon = out->horizon;
    const RadianceBrdf radiance(base, rt);
    const Brdf& source = o.radiance ? static_cast<const Brdf&>(radiance) : base;
    {
        // The colour mode from what the factors hold, probed through copies so that the
        // probe's evaluations stay out of the cap counters the report gives.
        const CappedBrdf capped_probe(brdf, o.cap);
        const Brdf& base_probe = o.cap > 0 ? static_cast<const Brdf&>(capped_probe) : brdf;
        const RadianceBrdf radiance_probe(base_probe, rt);
        out->colour_residual = colour_residual(o.radiance ? static_cast<const Brdf&>(radiance_probe) : base_probe);
        if (o.colour_auto) {
            o.colour = out->colour_residual <= kColourSeparable ? ColourMode::Luminance : ColourMode::PerChannel;
            char note[200];
            std::snprintf(note, sizeof note, "colour: %s (auto): f's colour %s one ratio times its luminance "
                          "(relative residual %.2g, luminance at or below %.0e)",
                          colour_name(o.colour), o.colour == ColourMode::Luminance ? "is" : "is not",
                          out->colour_residual, kColourSeparable);
            out->notes.push_back(note);
        }
        out->colour = o.colour;
    }
    ErrorOptions eo;
    eo.dense = 0;  // the Monte Carlo metric is the diagnostic; the dense one is for reports
    eo.threads = o.threads;
    ErrorEvaluator ev(brdf, eo);
    if (!ev.init(err)) return false;
    Search search(brdf, o, out, source, base, ev, [&]() { return capped.capped() + radiance.capped(); });
    // Coarse: every (param, map, method) at coarse_res; keep the best few. Homomorphic has its
    // own (vh, parabolic): one pair, whatever the lists.
    std::vector<Pair> pairs;
    for (Param param : o.params)
        for (HemiMap map : o.maps)
            for (Method method : methods)
                if (method != Method::Homomorphic) pairs.push_back({param, map, method});
    for (Method method : methods)
        if (method == Method::Homomorphic) pairs.push_back({Param::ViewHalf, HemiMap::Parabolic, method});
    std::vector<Pair> all_pairs = pairs;  // by coarse rank
    if (coarse) coarse_stage(search, o, max_terms, coarse_judge, &pairs, &all_pairs);
    std::vector<int> terms = o.terms;
    std::sort(terms.begin(), terms.end());
    terms.erase(std::unique(terms.begin(), terms.end()), terms.end());
    std::vector<Pair> climbers;
    if (!o.resolutions.empty()) grid(search, o, terms, judge, pairs);
    else climbers = ladder(search, o, terms, judge, pairs, all_pairs);
    if (o.climb_terms && !o.more_terms.empty()) more_terms(search, o, terms, judge, climbers);
    if (!fine_judge(brdf, o, views, search, out, err)) return false;
    if (o.progress && isatty(2)) std::fprintf(stderr, "\r%80s\r", "");
    const int best = choose_winner(&out->candidates, o);
    mark_front(&out->candidates, o);
    out->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out->capped_share = capped.share();
    if (best < 0) {
        if (err) *err = no_winner(out->candidates, o);
        return false;
    }
    out->winner = best;
    BakeCandidate& w = out->candidates[size_t(best)];
    winner_notes(w, o, views.size(), out);
    if (custom_profile(o)) out->notes.push_back(profile_note(o));
    // The winner's counts: its factorization's, and its textures' and plan's (made again:
    // cheap and deterministic).
    const Factorization* fz = search.factorization_of(size_t(best));
    if (fz) {
        QuantizeOptions q;
        q.bits = w.bits;
        q.mips = o.mips;
        AssetData again;
        std::string aerr;
        if (make_asset(fz->result.by_terms[size_t(w.terms - 1)], w.terms, q, &again, &aerr, &out->counts))
            record_counts(fz->result, fz->capped, ev.reference_rms(), out);
    }
    if (o.radiance) radiance_note(radiance, out);
    out->asset = w.asset;
    if (o.held_out && !held_out(brdf, o, out, err)) return false;
    out->asset.material.error_float = float(w.error_float * ev.reference_rms());
    out->asset.material.error_quantized = float(w.rms_quantized);
    out->asset.material.error_relative = float(w.error_quantized);
    out->asset.meta = shipped_manifest(w, brdf.spec(), o, *out);
    if (!o.keep_assets)
        for (BakeCandidate& c : out->candidates) c.asset = AssetData{};
    return true;
}

}  // namespace sepal
