// Baking: from a BRDF to the asset a game ships (quantized texture pairs, a pass plan).
//
// Usage:
//   sepal::BakeOptions o;                 // search space and budgets, see below
//   o.max_error = 0.1;                    // relative cosine-weighted RMS
//   sepal::BakeResult r; std::string err;
//   if (!sepal::bake(*brdf, o, &r, &err)) ...
//   sepal::write_asset("ward.sepal", r.asset, &err);
//
// The search: every combination of the listed parameterizations, maps, resolutions and
// methods is factored once with the largest term count (factor.h); each k-term prefix (or
// k-term solution, for nmf and acls) is quantized (quantize.h), given a plan (plan.h),
// encoded, and measured again with the same metric as the float factors (factor_error.h:
// 8000 Monte Carlo pairs, fixed seed), so every candidate knows its passes, bytes, float
// error, quantized error and predicted frame time (cost_model.h: a linear model of the
// chosen backend fitted to `make bench`'s measured frames). The winner is the fastest
// predicted frame that meets every budget, then the lowest error, then the fewest bytes;
// it lies on the Pareto front of (predicted ms, quantized error), which every candidate is
// marked on. Without --max-error the lowest quantized error within the pass and byte
// budgets wins.
// Determinism: equal inputs give byte-identical assets whatever the thread count; the
// asset's META chunk holds no timings.
// Limits: resolutions must be powers of two in 1..256 (GL ES 1.1 textures; 1 gives constant
// factors, 256 needs --method nd: the others refuse for memory); at most 64 factorizations
// per search.
// Extremes: an all-zero BRDF bakes to a valid asset that renders black (one constant-zero
// pass, build_plan's allow_all_zero), with counts.all_zero set and a note; every clamp or
// fallback is in BakeResult::counts (tests/extremes_test.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bake/asset_file.h"
#include "brdf/brdf.h"
#include "bake/cost_model.h"
#include "factor/factor.h"
#include "factor/factored.h"
#include "bake/quantize.h"

namespace sepal {

struct BakeOptions {
    std::vector<Param> params = {Param::GsHalf, Param::IncidentView, Param::ViewHalf};
    std::vector<HemiMap> maps = {HemiMap::XY};
    // Defaults keep a bake under a minute on two cores; widen them for the best asset.
    std::vector<int> resolutions = {32};
    std::vector<int> terms = {1, 2, 3, 4};
    // wsvd, not svd: the plain zero-filled SVD spends its rank on the horizon's edge
    // (Lambert: 22% error plain, 0.9% weighted, at 32x32 gs-half); svd stays available.
    std::vector<Method> methods = {Method::WSVD, Method::NMF};
    ColourMode colour = ColourMode::PerChannel;
    std::vector<int> bits = {8};  // 8 and/or 16 per texel channel
    bool mips = true;
    // The frame-time model the winner minimizes; an empty backend means the built-in
    // gles1 model (cost_model.h).
    CostModel cost;
    double max_error = -1;  // relative cosine-weighted RMS after quantization; < 0: none
    int max_passes = -1;    // plan passes per light; < 0: none
    int64_t max_bytes = -1;  // encoded asset size; < 0: none
    int supersample = 1;
    int threads = 0;
    double max_memory_mb = 2048;
    bool progress = false;  // a line per factorization on stderr
    // Values of f above `cap` (per steradian) are clamped before factoring; <= 0: none.
    // GL ES 1.1 draws through an 8-bit framebuffer whose scale-up multiplies its step by
    // the largest factor product: BRDFs with huge grazing peaks (Ward, Cook-Torrance) lose
    // every mid-tone there unless the peaks, white on screen anyway, are capped. The error
    // is still measured against the uncapped BRDF, and the clamped share is reported.
    double cap = -1;
    // Stored in the asset's manifest as "bake_key" (bake-scene's up-to-date check).
    std::string key;
    // Keep every candidate's asset in BakeCandidate::asset (sweeps; memory grows with the
    // search), which also spares the winner's second factorization; BakeResult::counts then
    // holds the input's counts only (the factor and quantizer counts come from that rebuild).
    bool keep_assets = false;
};

struct BakeCandidate {
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 0, terms = 0, bits = 8;
    Method method = Method::SVD;
    bool ok = false;            // factored and encoded; else `note` says why not
    std::string note;
    double error_float = 0;     // relative cosine-weighted RMS of the float factors
    double error_quantized = 0;  // the same after quantization
    double rms_quantized = 0;   // absolute
    int passes = 0;             // plan passes per light
    int doublings = 0;
    bool non_negative = false;  // no correction passes
    int64_t bytes = 0;
    double ms = 0;              // predicted frame time (BakeOptions::cost)
    bool on_front = false;      // no other candidate is as fast and as accurate, and better in one
    bool meets = false;         // within every budget
    AssetData asset;            // with BakeOptions::keep_assets
    std::string label() const;  // "gs-half/xy 64 svd x2 8b"
};

// Every clamp, replacement and fallback behind a bake, counted (never silent): printed by
// `sepal bake` and written to its --report as "counts". Totals are exact and do not depend
// on the thread count.
struct BakeCounts {
    // The winner's factorization (the one the asset is made from):
    int64_t evaluations = 0;       // BRDF evaluations it sampled
    int64_t capped = 0;            // of those, values clamped at --cap
    int64_t negative_clamped = 0;  // nmf/acls: negative matrix entries set to 0
    int64_t frame_fallbacks = 0;   // sample pairs built with param.h's degenerate-frame fallback
    int64_t solver_fallbacks = 0;  // solver updates set to 0 (factor_internal.h, AlsSettings)
    // The winner's textures and plan:
    int zero_textures = 0;         // textures that are 0 everywhere (scale 0, bias 0)
    int zero_scale_channels = 0;   // texture channels with scale 0 (constant: the bias)
    int64_t quantize_clamped = 0;  // codes clamped into range (0 by construction; see quantize.h)
    bool all_zero = false;         // every plan coefficient is 0: one constant-zero pass, black
    // The input, as its loader counted it (measured data; 0 for analytic models):
    InputCounts input;
};

struct BakeResult {
    std::vector<BakeCandidate> candidates;
    double capped_share = 0;  // share of sampled f values the cap clamped
    BakeCounts counts;        // filled as far as the bake got (input counts always)
    std::vector<std::string> notes;  // one line each: what was clamped, replaced or special
    int winner = -1;
    std::string why;  // one line: why the winner won
    CostModel cost;   // the model the candidates' ms came from
    AssetData asset;  // the winner's
    double seconds = 0;
};

bool bake(const Brdf& brdf, const BakeOptions& options, BakeResult* out, std::string* err);
// Sets on_front on every candidate: ok, and no ok candidate has ms and error both <= its
// own with one of them < (the Pareto front of predicted frame time and quantized error).
void mark_front(std::vector<BakeCandidate>* candidates);
// Sets meets on every candidate from the options' budgets and returns the winner's index
// (-1: none meets): with max_error, the fastest predicted frame, then the lowest error, then
// the fewest bytes; without, the lowest error, then the fastest, then the fewest bytes.
int choose_winner(std::vector<BakeCandidate>* candidates, const BakeOptions& options);

// The first `terms` terms of a factorization as a quantized asset with its plan;
// spec and method go into the META manifest. errors may be NaN when not measured.
// An all-zero factorization gives the constant-zero plan (plan.h). With counts, the
// textures' and plan's counts (zero textures, zero-scale channels, clamped codes, all_zero)
// are added to it.
bool make_asset(const Factored& f, int terms, const QuantizeOptions& q, AssetData* out, std::string* err,
                BakeCounts* counts = nullptr);
// The float factors an asset stands for (level 0, scale * q + bias), for measuring it.
Factored dequantize(const AssetData& asset, const Factored& like);
// The JSON manifest (scales, biases, parameterization, map, plan, errors).
std::string asset_manifest(const AssetData& asset, const std::string& spec, const std::string& method, int res,
                           const std::string& bake_key = "");

}  // namespace sepal
