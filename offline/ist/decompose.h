// The top level of an inverse shade tree (Lawrence et al. 2006, Tree 1): a tabulated
// SVBRDF -> blend maps x basis BRDFs, S(x, wi, wo) ~= sum_j w_j(x) f_j(wi, wo).
//
// Usage:
//   sepal::DecomposeOptions o; o.method = sepal::IstMethod::SACLS; o.terms = 4;
//   sepal::Decomposition d; std::string err;
//   if (!sepal::decompose_svbrdf(svbrdf, o, &d, &err)) ...
//   d.weights (texels x terms), d.basis (terms x pairs x RGB), d.rms
//   sepal::TermMatch m = sepal::match_terms(d, truth.blend);   // per-map error vs the truth
//
// The matrix (section 4): one row per texel, one column per direction pair and colour
// channel (colour lives in the bases, as the paper chose), entries f(wi, wo) cos(theta_i)
// (what a camera records under a light: the paper's images), each weighted by its
// sample's confidence (eq. 7; 0 = missing, left out). Methods:
//   sacls   SACLS (eq. 4): alternating exact solves, per texel the non-negative weights
//           minimizing the error plus sparsity l * sum_{a != j} w_a^2 (best j) and unit-L1
//           m * (1 - sum w)^2; the bases non-negative and energy conserving (below). l and
//           m are in units of the variance of the observed entries, per 50 observed entries
//           of a row (the paper's 50 columns), so they mean the same at any column count.
//   acls    the same with l = m = 0 (non-negative factorization by exact ACLS).
//   pca     truncated SVD (weighted least-squares ALS from it when samples are missing,
//           with a ridge of 1% of the normal equations' mean diagonal: without it a weak
//           direction predicted missing samples 100x off): the least error, signed terms.
//   nmf     Lee-Seung multiplicative updates with confidence weights from an NNDSVD start.
//   kmeans  k-means of the texels (weighted by confidence; k-means++ start), the centres
//           as bases and the weights by non-negative re-projection (Fig. 5).
// Energy conservation (section 4.3.1): per basis, view (a group of pairs, svbrdf.h) and
// channel, sum_pairs albedo_weight * f * cos(theta_i) <= 1, as linear constraints of the
// basis update (sacls, acls; `energy`). Initialization (4.4.3): k-means with
// `kmeans_clusters` centres, then `restarts` runs from random subsets of k centres; the
// lowest objective wins. Large inputs (4.4.2): the bases are fitted to at most `max_rows`
// texels (a fixed random subset), then every texel is projected onto them exactly.
// Terms: `terms`, or 0 to choose by error: the smallest K in 1..max_terms after which one
// more term lowers the RMS by less than choose_slack (the knee of the curve).
// Error: `rms` is the cosine-weighted RMS over observed samples and channels,
// sqrt(sum c (f cos - f^ cos)^2 / sum c), in the units of f cos (1/sr).
// Determinism: the same input and options give identical results on any thread count.
// Limits: terms 1..8; max_rows 16..1e6; the held matrix (max_rows x pairs x 3 floats x 2)
// must fit in max_memory_mb.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "ist/generate.h"
#include "svbrdf/samples.h"

namespace sepal {

enum class IstMethod { SACLS, ACLS, PCA, NMF, KMeans };
const char* ist_method_name(IstMethod m);  // "sacls", "acls", "pca", "nmf", "kmeans"
bool parse_ist_method(const std::string& name, IstMethod* m);

struct DecomposeOptions {
    IstMethod method = IstMethod::SACLS;
    int terms = 0;  // 0: chosen by error
    int max_terms = 6;
    double choose_slack = 0.1;
    double sparsity = 1;         // l
    double normalization = 10;   // m
    bool energy = true;
    int kmeans_clusters = 20;
    int restarts = 4;
    int iterations = 60;         // most ALS iterations per run (nmf: 5x)
    double tolerance = 1e-5;     // stop when the objective falls by less than this share
    int max_rows = 4096;
    double max_memory_mb = 2048;
    uint64_t seed = 1;
    int threads = 0;
    bool progress = false;       // one line per stage on stderr
};

struct Decomposition {
    IstMethod method = IstMethod::SACLS;
    int terms = 0, width = 0, height = 0;
    std::vector<DirPair> pairs;
    std::vector<float> weights;  // [texel * terms + j]
    std::vector<float> basis;    // [(j * pairs + p) * 3 + c], BRDF values (1/sr)
    double rms = 0;
    std::vector<double> rms_by_terms;  // terms chosen by error: [K-1] for K = 1..max_terms
    double objective = 0;              // of the winning run, on the fitted rows
    int iterations = 0;                // ALS iterations, all runs
    int fitted_rows = 0;               // texels the bases were fitted to
    double seconds = 0;
    int64_t fallbacks = 0;             // solver updates that fell back (als.h)
    std::vector<std::string> notes;

    glm::dvec3 basis_value(int j, int p) const {
        const float* b = &basis[(size_t(j) * pairs.size() + size_t(p)) * 3];
        return glm::dvec3(b[0], b[1], b[2]);
    }
    BlendMaps blend() const;
};

bool decompose_svbrdf(const SvbrdfSamples& s, const DecomposeOptions& o, Decomposition* out, std::string* err);

// Cosine-weighted RMS against `reference` (the same texels and pairs, complete data),
// separately over the samples `input` observed (confidence > 0) and those it missed.
struct ReconError {
    double observed = 0, missing = 0;
    int64_t n_observed = 0, n_missing = 0;
};
ReconError reconstruction_error(const Decomposition& d, const SvbrdfSamples& input, const SvbrdfSamples& reference);

// Recovered terms matched one-to-one to true blend maps (the assignment of largest total
// correlation, exhaustive over permutations), each term scaled by its least-squares
// factor onto its map before the error (nmf and pca terms have no fixed scale).
struct TermMatch {
    std::vector<int> truth_of_term;   // [term] -> true map index, -1 when there are more terms
    std::vector<double> map_rms;      // [term] RMS over texels of (scaled term - true map)
    std::vector<double> scale;        // [term]
    double mean_map_rms = 0;          // over matched terms
    double max_map_rms = 0;
};
TermMatch match_terms(const Decomposition& d, const BlendMaps& truth);

// Share of texels using more than one material: more than one |weight| above `threshold`
// times the texel's sum of |weights|; of a decomposition's maps or of true ones.
double multi_material_share(const BlendMaps& maps, double threshold = 0.1);
double multi_material_share(const Decomposition& d, double threshold = 0.1);

// Per basis, per view, per channel: sum albedo_weight * f * cos(theta_i); the largest.
double max_basis_albedo(const Decomposition& d);

}  // namespace sepal
