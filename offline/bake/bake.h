// Baking: from a BRDF to the asset a game ships (quantized texture pairs, a pass plan).
//
// Usage:
//   sepal::BakeOptions o;                 // defaults: the image on GL ES 1.1 decides
//   o.target = sepal::Target::Gles1;      // gles1 | gles2 | cpu
//   sepal::BakeResult r; std::string err;
//   if (!sepal::bake(*brdf, o, &r, &err)) ...
//   sepal::write_asset("ward.sepal", r.asset, &err);
//
// What is fitted (radiance.h): by default f cos(theta_i), capped at the white level of the
// declared light range (light_range.h: f cos above 1.25 / its dimmest irradiance is white
// under every light of the range), minus the diffuse part (a constant BRDF drawn by an
// untextured pass): format-2 radiance assets, with the range in the header (2.3).
// `radiance = false` factors f itself (what format 1.x assets hold).
// How candidates are judged (image_score.h): every candidate asset is drawn on its target
// (the GL ES pipeline emulated on the CPU, or the CPU backend) in every training view (the
// light range's training conditions) and scored by PSNR against the exact render, 8-bit, as
// a display shows it. The winner is then judged on the range's held-out conditions (other
// directions and intensities, the torus, two lights): BakeResult::held_out_psnr, the figure
// the bake reports first; the training figure is in-sample. The direction-space figures (relative cosine-
// weighted RMS over 8000 fixed pairs, factor_error.h) stay as diagnostics and budgets.
// The search, coarse to fine: with more than one (parameterization, map, method) listed,
// each is first factored at coarse_res and judged on small images; only the best (and
// those within keep_db of it, at most keep) go on to the listed resolutions, where every
// k-term solution (prefix for svd) and depth is quantized (quantize.h), planned (plan.h),
// encoded, judged at judge_size (and the front-runners again at twice that when one has a
// 128-texel sharp factor: fine_judge_texels) and measured. The winner: with min_psnr (or max_error), the
// fastest predicted frame (cost_model.h) that meets every budget; otherwise the highest PSNR
// within the pass and byte budgets among the candidates whose every view reaches
// goal_worst_db (all of them when none does), where anything within tie_db of it that needs
// fewer passes, then fewer bytes, is preferred. The winner's asset is kept, never refactored.
// Methods come from one table (bake_methods()): a row per factorization with the targets it
// may ship on (signed factors need bias passes, which an 8-bit framebuffer cannot hold:
// svd ships on cpu only).
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
#include "bake/image_score.h"
#include "bake/light_range.h"
#include "bake/quantize.h"
#include "bake/radiance.h"

namespace sepal {

struct BakeOptions {
    std::vector<Param> params = {Param::GsHalf, Param::IncidentView, Param::ViewHalf, Param::Axis, Param::GsMirror};
    std::vector<HemiMap> maps = {HemiMap::XY};
    // Texels per side: of both factors, or with smooth_resolutions given, of the sharp
    // factor (param.h: gs-half's G, vh's H, axis's G, gs-mirror's H) while the other one
    // takes each of smooth_resolutions not above it (the lobe's factor is sharp, the other
    // smooth: both need not pay for it).
    // Empty: the ladder. Every kept pair is factored on the ladder's first rung (iv: both
    // factors at ladder_iv), and the best one climbs while a rung gains climb_db; on the
    // rung it reached, the other factor is tried at finer_other too (it holds the grazing
    // views where a light behind the object puts its highlight).
    std::vector<int> resolutions;
    std::vector<int> smooth_resolutions;
    std::vector<std::pair<int, int>> ladder = {{32, 16}, {64, 16}, {128, 8}};  // (half-angle, other)
    int ladder_iv = 32;
    double climb_db = 0.5;
    // The runner-up half-angle pair of the first rung, when within this of the climber, is
    // tried with the other factor at finer_other on the first rung too, and its best
    // configuration gets more_terms like the winner's.
    double second_climb_db = 1.0;
    int finer_other = 32;
    // With max_bytes (and the ladder), every kept pair is also factored with both factors at
    // small_rung: the sizes an 8 KB material needs sit below the ladder's first rung.
    int small_rung = 16;
    // With terms empty (and climb_terms), the winner's configuration is factored again with
    // more_terms when it is below goal_db and its largest term count still gained
    // more_terms_db over the one before (passes cost frame time; above goal_db a better image
    // is not worth them). 0.25, not climb_db: Hapke-Lommel's fourth term gains 0.43 dB on the
    // 128 x 64 judged sphere, and 8 terms then reach 38 dB against 36.4.
    bool climb_terms = true;
    double goal_db = 40;
    // Also when the winner's worst view is below goal_worst_db (0: off), and the winner is
    // chosen among the candidates whose every view reaches it when any does (choose_winner):
    // the held-out conditions an asset is reported on are judged one by one, and the view a
    // pooled figure hides is a light behind the object, whose rim highlight needs the rank.
    double goal_worst_db = 40;
    double more_terms_db = 0.25;
    std::vector<int> more_terms = {6, 8};
    // Term counts; empty: 1..4, and more_terms when the winner is below goal_db (climb_terms).
    std::vector<int> terms;
    // Empty: the default methods of bake_methods() that may ship on the target (acls, the
    // non-negative fit by exact block updates, on gles1/gles2; acls and svd on cpu).
    std::vector<Method> methods;
    // Factors per channel (rgb) or of the luminance with one colour ratio (a third of the
    // texel bytes). colour_auto: luminance when what the factors hold is one colour times one
    // function (colour_residual() at most kColourSeparable), else rgb; `colour` is then unused.
    ColourMode colour = ColourMode::PerChannel;
    bool colour_auto = true;
    std::vector<int> bits = {8};  // 8 and/or 16 per texel channel
    // A MIP chain for the factor textures. Off by default: GL picks a level from the screen
    // derivative of the factor coordinates, which is largest at the rim where the view grazes,
    // and the coarse levels blur the lobe there; level 0 alone measured 0.0-0.8 dB better at
    // 512x512 and up to 5 dB at 64x64 on every default bake (docs/fidelity.md), and 20-25%
    // fewer bytes.
    bool mips = false;
    // The image that decides: the backend the asset ships on.
    Target target = Target::Gles1;
    // The device profile it is judged on (devices.h; gles1 only): the emulator at its
    // framebuffer's bits, textures at or under its limit, blend subtraction as it has it;
    // recorded in the asset (format 2.4). Empty or "default": today's bake, byte for byte.
    std::string profile;
    // The lighting the asset must hold under (light_range.h): candidates are ranked on its
    // training conditions, the result is reported on its held-out ones, and the white level
    // follows from its dimmest light. The default: 8:1, any direction above the horizon, two
    // lights at once (docs/fidelity.md says why).
    LightRange light_range;
    // Views to rank by instead of the range's training conditions (bake-scene's scene views);
    // the white level then follows from the dimmer of their lights and the range's dimmest.
    std::vector<BakeView> views;
    bool held_out = true;   // judge the winner on the held-out conditions (the report's headline)
    int judge_size = 128;   // pixels per side of the judged images
    // When a candidate whose sharp factor has fine_judge_texels or more texels a side (the
    // ladder's last rung; 0: never) is within fine_judge_db of the best figure, the candidates
    // within fine_keep_db of it are judged again at twice judge_size, and the winner (among
    // those only) and the held-out figure come from those images: a 128-texel factor holds a
    // lobe a few pixels wide at 128 x 128, where which pixel centres it hits, not the
    // factors, decides the ranking (cook-torrance m=0.05: 16/64 won with a square-edged
    // highlight, 39.6 dB in its worst held-out condition at 512; judged at 256, 8/128: 42.4).
    int fine_judge_texels = 128;
    double fine_judge_db = 1.0;
    // The winners at 256 were 0.12-0.27 dB behind the best at 128 (phong n=1000, cayman,
    // cook-torrance m=0.05): candidates further behind are not judged again.
    double fine_keep_db = 0.5;
    // Coarse stage (only with more than one parameterization, map or method listed): every
    // pair factored at coarse_res (0: no coarse stage) with up to coarse_terms terms and
    // judged at coarse_size; per family (Kautz-McCool's parameterizations and homomorphic;
    // axis, only within keep_db of the best overall) the best pair and those within keep_db
    // of it (at most keep) go on.
    int coarse_res = 16;
    int coarse_terms = 3;
    int coarse_size = 64;
    // 2.5, not 1.5: 16 texels misrank pairs that turn on the ladder (cook-torrance's gs-half,
    // 1.6 dB behind vh there, leads it by 2.3 dB at 32/32). 3, not 2: MERL blue-metallic-
    // paint's gs-half came third of its family at 16 texels (behind vh and gs-mirror) and
    // never went on, and its 32 x4 holds 46.5 dB in its worst held-out condition where the
    // winner without it (axis 32 x3) held 41.5.
    double keep_db = 2.5;
    int keep = 3;
    double tie_db = 0.2;    // the winner: fewest passes, then bytes, within this of the best worth
    // The winner's worth: its PSNR less bytes_db per doubling of its bytes (a candidate of
    // twice the bytes must render this much better to win).
    double bytes_db = 0.5;
    // Radiance fit (radiance.h, format 2): the factors hold f cos(theta_i) capped at white,
    // minus the diffuse part. white: > 0 the cap (per steradian); 0: from the light range
    // (1.25 / its dimmest irradiance at the object); < 0: no cap. diffuse: estimated (estimate_diffuse)
    // unless diffuse_given.
    bool radiance = true;
    double white = 0;
    // The radiance fit's horizon window c0 (format 2.7, sepal_horizon_window; 0: none, the
    // factors hold f cos(theta_i) down to the horizon and format 2.6 or older is written):
    // the vertex colour, not the factors, takes the radiance to 0 at the horizon, so a lit
    // crescent ends without the factors' step (entries weighed by w^2, the drawn error). In
    // [0, 1]. Off by default: measured on the fidelity bench, 0.1 moves the fit's error
    // into other views by +-2 dB and misranks cook-torrance (docs/fidelity.md, "The horizon
    // window").
    double horizon = 0;
    // The radiance fit's entry weights: Display weighs each value's error as a display shows
    // it across the light range (radiance.h, display_weight); Uniform counts every entry alike.
    enum class FitWeight { Display, Uniform };
    FitWeight fit_weight = FitWeight::Display;
    // The diffuse part: a profile over (cos theta_i, cos theta_o) of diffuse_side^2 nodes
    // (estimate_diffuse_profile; constant when flat), or with diffuse_side 0 a constant, the
    // diffuse_quantile of f (estimate_diffuse); or given (diffuse_given: the constant diffuse).
    int diffuse_side = 16;
    double diffuse_quantile = 0.005;
    bool diffuse_given = false;
    glm::dvec3 diffuse{0, 0, 0};
    // The frame-time model the budgets use; an empty backend means the built-in gles1
    // model (cost_model.h).
    CostModel cost;
    double min_psnr = -1;   // dB on the target; < 0: none
    double max_error = -1;  // relative cosine-weighted RMS after quantization; < 0: none
    int max_passes = -1;    // plan passes per light; < 0: none
    int64_t max_bytes = -1;  // encoded asset size; < 0: none
    int supersample = 1;
    // nmf/acls outer iterations per term count (0: 12 for acls, factor.h's default otherwise).
    int iterations = 0;
    int threads = 0;
    double max_memory_mb = 2048;
    bool progress = false;  // a line per factorization on stderr
    // Values of f above `cap` (per steradian) are clamped before factoring; <= 0: none.
    // (The radiance fit's white level is the better tool; kept for factors of f.) The
    // error is still measured against the uncapped BRDF, and the clamped share is reported.
    double cap = -1;
    // Stored in the asset's manifest as "bake_key" (bake-scene's up-to-date check).
    std::string key;
    // Keep every candidate's asset in BakeCandidate::asset (sweeps; memory grows with the
    // search).
    bool keep_assets = false;
};

// One row of the bake's method table: a factorization and where its assets may ship.
struct BakeMethod {
    const char* name;
    Method method;
    bool non_negative;      // no bias passes: fit for an 8-bit framebuffer
    bool default_method;    // searched when BakeOptions::methods is empty (on its targets)
};
const std::vector<BakeMethod>& bake_methods();
// Whether a method's assets may ship on a target (signed ones only on cpu).
bool method_allowed(Method m, Target t);

struct BakeCandidate {
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 0, res_h = 0, terms = 0, bits = 8;  // res: G's side, res_h: H's
    Method method = Method::SVD;
    bool coarse = false;        // judged in the coarse stage (small images)
    bool ok = false;            // factored and encoded; else `note` says why not
    std::string note;
    double psnr = 0;            // image PSNR on the target, pooled over the views
    std::vector<double> psnr_views;
    double error_float = 0;     // relative cosine-weighted RMS of the float factors (diagnostic)
    double error_quantized = 0;  // the same after quantization
    double rms_quantized = 0;   // absolute
    int passes = 0;             // plan passes per light
    int doublings = 0;          // framebuffer doublings of the frame (first view, GL targets)
    bool non_negative = false;  // no correction passes
    int64_t bytes = 0;
    double ms = 0;              // predicted frame time (BakeOptions::cost)
    double factor_seconds = 0;  // its factorization's sampling and fitting time (shared by its term counts)
    bool on_front = false;      // no other candidate is as fast and as accurate, and better in one
    bool meets = false;         // within every budget
    bool unranked = false;      // left at the first judge's size by the fine judge: never the winner
    AssetData asset;            // with BakeOptions::keep_assets (and the winner's, always)
    std::string label() const;  // "gs-half/xy 64 nmf x2 8b", "gs-half/xy 128/16 nmf x1 8b"
    double worst_view() const;  // the lowest of psnr_views (psnr without them)
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
    Target target = Target::Gles1;
    std::string target_label;        // "gles1", or "gles1:PROFILE" when judged on a device profile
    std::vector<std::string> views;  // the judged (training) views' names
    double white = 0;                // the radiance fit's cap (0: none or not a radiance fit)
    double horizon = 0;              // the radiance fit's horizon window c0 (0: none)
    double irradiance_min = 0;       // the dimmest light the asset holds for (the header's; 0: any)
    // The winner on the held-out conditions (BakeOptions::held_out): the headline figure.
    // psnr pooled over them; per condition its PSNR and the share of pixels more than 16
    // levels from the exact render; the flags that render each (`sepal render`).
    double held_out_psnr = 0;
    int judge_size = 0;  // the images' side the winner and the held-out figure were judged at
    std::vector<std::string> held_out_views, held_out_flags;
    std::vector<double> held_out_psnr_views, held_out_share16;
    DiffusePart diffuse;             // the radiance fit's diffuse part
    ColourMode colour = ColourMode::PerChannel;  // the factors' colour mode (chosen or given)
    double colour_residual = 0;      // colour_residual() of what the factors hold
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
// How far f is from one colour times one function: the relative RMS of f - ratio *
// luminance(f) over 4096 fixed direction pairs, the ratio fitted by least squares. 0 for a
// grey BRDF (every analytic default here but Cook-Torrance's coloured Fresnel) or one whose
// colour does not change with direction.
double colour_residual(const Brdf& f);
// At or below it, luminance factors lose under half an 8-bit level where f is white
// (measured: the grey defaults bake to the same PSNR in both modes at ~40% of the bytes).
constexpr double kColourSeparable = 1e-3;
// Sets on_front on every fine-stage candidate: ok, and no such candidate has ms and image
// error both at most its own with one of them lower (the Pareto front of predicted frame
// time and PSNR; with max_error and no min_psnr, of frame time and quantized error).
void mark_front(std::vector<BakeCandidate>* candidates, const BakeOptions& options);
// Sets meets on every fine-stage candidate from the options' budgets and returns the
// winner's index (-1: none meets): with min_psnr or max_error, the fastest predicted frame,
// then the highest PSNR, then the fewest bytes; without, the highest PSNR among those whose
// every view reaches goal_worst_db (when any does), preferring within tie_db of it the fewest
// passes, then the fewest bytes.
int choose_winner(std::vector<BakeCandidate>* candidates, const BakeOptions& options);

// The first `terms` terms of a factorization as a quantized asset with its plan;
// spec and method go into the META manifest. errors may be NaN when not measured.
// An all-zero factorization gives the constant-zero plan (plan.h). With counts, the
// textures' and plan's counts (zero textures, zero-scale channels, clamped codes, all_zero)
// are added to it.
// Radiance factors (Factored::radiance) give a format-2 radiance material with its diffuse part.
bool make_asset(const Factored& f, int terms, const QuantizeOptions& q, AssetData* out, std::string* err,
                BakeCounts* counts = nullptr);
// The float factors an asset stands for (level 0, scale * q + bias), for measuring it.
Factored dequantize(const AssetData& asset, const Factored& like);
// What the bake fitted and judged, for the manifest ("fit").
struct ManifestFit {
    double white = 0;      // the radiance fit's cap; 0: none
    std::string target;    // "gles1", ...
    double psnr = 0;       // on the target, pooled over the views
    std::vector<std::string> views;
    // The held-out figures (pooled and the worst condition), written at a fixed width so that
    // a candidate's bytes (--max-bytes) do not change when the winner's are filled in; < 0:
    // not measured.
    double held_out_psnr = -1, held_out_worst = -1;
    std::string light_range;  // describe_light_range()
};
// The asset's META: compact JSON provenance (spec, method, bake key, and the fit);
// the rest is in the binary chunks.
std::string asset_manifest(const AssetData& asset, const std::string& spec, const std::string& method,
                           const std::string& bake_key = "", const ManifestFit* fit = nullptr);

}  // namespace sepal
