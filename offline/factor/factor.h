// The factorization engine: separable factors f(wi, wo) ~= sum_k G_k(x) H_k(y) of any BRDF.
//
// Usage:
//   sepal::FactorOptions o;
//   o.param = sepal::Param::GsHalf; o.res = 32; o.terms = 4; o.method = sepal::Method::SVD;
//   sepal::FactorResult r; std::string err;
//   if (!sepal::factor_brdf(*brdf, o, &r, &err)) { fprintf(stderr, "%s\n", err.c_str()); }
//   // r.factored: the K-term factors (factored.h); r.by_terms[k-1]: the k-term approximation
//
// Sampling: every valid texel of G (a row) is paired with every valid texel of H (a column);
// the entry M[x][y] averages f over S x S sub-sample positions of each texel (S^4 pairs,
// S = supersample), counting only pairs with both directions above the horizon; its
// weight is the share of such pairs (0 where the whole entry falls below the horizon).
// Decompositions (each per colour channel, or of the luminance with per-channel ratios):
//   svd   truncated SVD, signed, of the matrix with entries below the horizon as 0 (the
//         paper's): the top K triplets only, by randomized subspace iteration with a fixed
//         seed; k-term results are prefixes.
//   wsvd  weighted SVD (what `sepal bake` uses by default): a weighted fit instead,
//         alternating least squares over the entries by their weight (entries wholly below
//         the horizon by horizon_weight), one solution per term count, re-orthogonalized.
//         The same as svd with svd_weighted (kept for existing callers).
//   nd    normalized decomposition (Kautz-McCool 4.2) with a p-norm; multi-term on signed
//         residuals (a row's sign is that of its correlation with the largest-norm
//         residual row). Streams rows: memory = output; 1 + 2 (K - 1) sampling passes.
//   nmf   weighted non-negative factorization by multiplicative updates (Lee-Seung,
//         Euclidean, with per-entry weights), warm-started term by term from NNDSVD.
//   acls  alternating constrained least squares (Inverse Shade Trees): exact block
//         updates per term under non-negativity, optionally with term 1's half-angle factor
//         held constant (diffuse-like) and the other half-angle factors monotonically
//         non-increasing in theta_h (a tree isotonic regression over the hemisphere map).
// For nmf and acls the k-term result is the k-term solution of the warm-started sequence
// (not a prefix of the K-term one); their terms are ordered by energy.
// svd, nmf and acls hold the matrix and refuse (before sampling) when their estimate
// exceeds max_memory_mb, naming nd and a lower resolution.
// Determinism: results do not depend on the thread count (see parallel.h).
// Limits: res 1..256 (1: every factor is a constant), terms 1..16 and at most the rank the
// sample matrix can have (1 at res 1), supersample 1..4. svd, nmf and acls at 256 need tens
// of GB and refuse (naming nd); nd streams and takes 256 within the default memory limit.
// A BRDF returning NaN or inf makes the call fail with the direction pair named (measured
// loaders never do: they count such input as missing or refuse the file, see measured.h).
// Fallbacks are counted, never silent: frame_fallbacks, solver_fallbacks and
// clamped_negative below, each with a note when nonzero.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "factor/factored.h"
#include "factor/homomorphic.h"
#include "factor/param.h"

namespace sepal {

// WSVD last: the others keep their values.
enum class Method { SVD, ND, NMF, ACLS, WSVD, Homomorphic };
const char* method_name(Method m);  // "svd", "nd", "nmf", "acls", "wsvd", "homomorphic"
bool parse_method(const std::string& name, Method* m);

struct FactorOptions {
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 32;        // N: texels per side of each factor texture, 1..256
    // Texels per side of the H factors when they differ from G's (0: res). A half-angle
    // factor holds a sharp lobe where the other one is smooth: both need not pay for it.
    int res_h = 0;
    int terms = 1;       // K, 1..16
    Method method = Method::SVD;
    ColourMode colour = ColourMode::PerChannel;
    int supersample = 1;  // S, 1..4: S^4 BRDF evaluations per matrix entry
    double nd_p = 2;      // ND's norm, 1..16
    int iterations = 0;   // nmf/acls: most outer iterations per term count; 0 = default
    double tolerance = 0;  // nmf/acls: stop when the error drops by less than this share
                           // per iteration; 0 = default
    bool svd_weighted = false;   // svd: weighted fit (stages) instead of the plain SVD: wsvd
    // Weighted fits (nmf, acls, weighted svd): entries wholly below the horizon count with
    // this weight toward 0 (the BRDF's value there); 0 leaves them out (anchored to the
    // previous term count's reconstruction).
    double horizon_weight = 0.01;
    // Optional confidence of f per direction pair, in [0, 1] (scattered data tabulated with
    // push-pull: Lawrence et al. 2006, 4.4.1): multiplies the weight of each entry of the
    // held matrix (svd_weighted, nmf, acls; plain svd and nd ignore it). Entries whose
    // weight becomes 0 count as below the horizon (horizon_weight): keep a floor above 0.
    std::function<double(const glm::dvec3& wi, const glm::dvec3& wo)> confidence;
    // Optional weight of an entry from its value (the mean of f over its pairs), clamped to
    // [1e-3, 1]: multiplies the entry's weight like confidence, at no extra evaluation (the
    // bake's display weighting: radiance.h).
    std::function<double(const glm::dvec3& value)> value_weight;
    bool acls_constant = false;   // term 1's half-angle factor held constant
    bool acls_monotonic = false;  // half-angle factors non-increasing in theta_h
    double max_memory_mb = 2048;
    int threads = 0;  // 0: all cores
    uint64_t seed = 1;
    bool progress = false;  // one-line progress on stderr
    // Fill FactorResult::matrix_rms (for nd one more sampling pass); benchmarks of the
    // factoring time alone turn it off.
    bool matrix_error = true;
    // homomorphic: where the samples come from (auto: the input's scattered samples when it
    // has them, else dense samples of eval()), dense samples per texel, and the fit's own
    // knobs (its res, colour, terms and threads are taken from the fields above).
    enum class Samples { Auto, Raw, Dense };
    Samples samples = Samples::Auto;
    int dense_per_texel = 8;
    HomomorphicOptions homomorphic;
};

// Texels per side of factor `which` (0 = G, 1 = H).
inline int factor_res(const FactorOptions& o, int which) { return which == 1 && o.res_h > 0 ? o.res_h : o.res; }

// Checks ranges and combinations; false with a message naming the option.
bool validate_factor_options(const FactorOptions& o, std::string* err);

// Rows (valid texels of G) and columns (valid texels of H) of the sample matrix.
void matrix_shape(const FactorOptions& o, int* rows, int* cols);
// Memory the method needs at these options, in MB (the matrix plus working buffers for
// svd/nmf/acls; output plus per-chunk sums for nd).
double estimate_memory_mb(const FactorOptions& o);

struct FactorResult {
    Factored factored;              // the K-term result
    std::vector<Factored> by_terms;  // [k-1]: the k-term approximation, k = 1..K
    // [k-1]: weighted RMS of (matrix - k-term approximation) over the matrix entries
    // (all channels, or the luminance), the error "at the sample points".
    std::vector<double> matrix_rms;
    int rows = 0, cols = 0;
    double memory_mb = 0;          // estimate_memory_mb
    double sample_seconds = 0;     // svd/nmf/acls: sampling the matrix; nd: its first pass
    double factor_seconds = 0;     // everything after sampling (nd: the other passes)
    int64_t evaluations = 0;       // BRDF evaluations while factoring
    int iterations = 0;            // nmf/acls/weighted svd: outer iterations in all
    int clamped_negative = 0;      // nmf/acls: negative matrix entries clamped to 0
    // Sub-sample pairs of one sampling pass whose G point takes param.h's degenerate-frame
    // fallback (rusinkiewicz at --res 1: h = n).
    int64_t frame_fallbacks = 0;
    // nmf/acls/weighted svd: solver updates set to 0 (see AlsSettings::fallbacks).
    int64_t solver_fallbacks = 0;
    std::vector<std::string> notes;
};

// Samples and factors. False with a message on bad options, a memory refusal or a
// non-finite BRDF value; *out is complete only on success.
bool factor_brdf(const Brdf& brdf, const FactorOptions& o, FactorResult* out, std::string* err);

// One full pass of sampling the matrix without keeping it (for benchmarks: the unit that
// factoring times are compared with). Returns seconds, or a negative value with *err set.
double time_sampling_pass(const Brdf& brdf, const FactorOptions& o, std::string* err);

}  // namespace sepal
