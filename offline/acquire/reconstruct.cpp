#include "acquire/reconstruct.h"
#include "spec/spec.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>

#include <glm/glm.hpp>

#include "brdf/brdf_util.h"  // kPi
#include "util/parallel.h"

namespace sepal {
namespace {

constexpr double kInf = 1e300;

// Samples of each atlas texel: (capture, index) pairs in capture order.
struct TexelIndex {
    std::vector<int> start;  // res*res + 1
    std::vector<std::pair<int, int>> refs;
    int count(int t) const { return start[size_t(t) + 1] - start[size_t(t)]; }
};

TexelIndex index_samples(size_t texels, const std::vector<Capture>& caps) {
    TexelIndex ix;
    ix.start.assign(texels + 1, 0);
    for (const Capture& c : caps)
        for (int t : c.texel) ++ix.start[size_t(t) + 1];
    for (size_t t = 0; t < texels; ++t) ix.start[t + 1] += ix.start[t];
    ix.refs.resize(size_t(ix.start[texels]));
    std::vector<int> fill(ix.start.begin(), ix.start.end() - 1);
    for (size_t ci = 0; ci < caps.size(); ++ci)
        for (size_t i = 0; i < caps[ci].size(); ++i)
            ix.refs[size_t(fill[size_t(caps[ci].texel[i])]++)] = {int(ci), int(i)};
    return ix;
}

BrdfSample sample_of(const std::vector<Capture>& caps, const std::pair<int, int>& r) {
    const Capture& c = caps[size_t(r.first)];
    const size_t i = size_t(r.second);
    BrdfSample s;
    s.wi = glm::dvec3(c.wi[i]);
    s.wo = glm::dvec3(c.wo[i]);
    s.value = glm::dvec3(c.value[i]);
    s.weight = c.weight[i];
    return s;
}

// Weighted squared residual of a texel's samples under a model.
double texel_residual(const LafortuneModel& m, const std::vector<Capture>& caps, const TexelIndex& ix, int t) {
    double sum = 0;
    for (int k = ix.start[size_t(t)]; k < ix.start[size_t(t) + 1]; ++k) {
        const BrdfSample s = sample_of(caps, ix.refs[size_t(k)]);
        const glm::dvec3 d = (m.eval(s.wi, s.wo) - s.value) * s.weight;
        sum += glm::dot(d, d);
    }
    return sum;
}

// Non-negative least squares on K x K normal equations by projected Gauss-Seidel
// (K <= 8: exact enough in a few dozen sweeps, no active-set bookkeeping).
void nnls_small(const std::vector<double>& A, const std::vector<double>& b, int K, std::vector<double>* x) {
    for (int sweep = 0; sweep < 60; ++sweep)
        for (int j = 0; j < K; ++j) {
            const double ajj = A[size_t(j * K + j)];
            if (!(ajj > 0)) continue;
            double r = b[size_t(j)];
            for (int l = 0; l < K; ++l)
                if (l != j) r -= A[size_t(j * K + l)] * (*x)[size_t(l)];
            (*x)[size_t(j)] = std::max(0.0, r / ajj);
        }
}

// (1) The initial clusters. Per measured texel, the median of its own and its 8 neighbours'
// values per channel (times pi: the albedo of a Lambertian with that value);
// pooled because a texel alone has a handful of samples (4 to 8 on the bench's planned
// sphere) and the median of so few can be a highlight. Then k-means on these colours, seeded
// by bisection: from one cluster, the one with the largest squared spread is split along its
// principal axis (2-means from its mean +- one standard deviation) until there are `clusters`.
// Deterministic, and a split follows where most of the spread is, not single outliers:
// farthest-point seeding picked the few texels seen only in highlights, and with 4 clusters
// on the bench's planned sphere the white and blue materials shared one. Seeded by bisection,
// the bench's planned sphere renders within 1.1 dB with 4, 6 or 8 clusters (its
// "reconstruction's choices" lines).
void texel_colours(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
                   const SurfaceAtlas& atlas, std::vector<glm::dvec3>* colour) {
    std::vector<double> ch[3];
    for (int t : measured) {
        for (std::vector<double>& c : ch) c.clear();
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int q = atlas.step(t, dx, dy);
                if (q < 0) continue;
                for (int k = ix.start[size_t(q)]; k < ix.start[size_t(q) + 1]; ++k) {
                    const glm::vec3& v = caps[size_t(ix.refs[size_t(k)].first)].value[size_t(ix.refs[size_t(k)].second)];
                    for (int c = 0; c < 3; ++c) ch[c].push_back(double(v[c]) * kPi);
                }
            }
        const size_t mid = ch[0].size() / 2;
        for (int c = 0; c < 3; ++c) {
            std::nth_element(ch[c].begin(), ch[c].begin() + long(mid), ch[c].end());
            (*colour)[size_t(t)][c] = ch[c][mid];
        }
    }
}

// Splits cluster k of `centre` in two along its principal axis; the new one is appended.
// False (nothing changed) when its colours do not spread or one side would be empty.
bool split_cluster(const std::vector<glm::dvec3>& colour, const std::vector<int>& measured, int k,
                   std::vector<glm::dvec3>* centre, std::vector<int>* cluster) {
    glm::dmat3 C(0.0);
    int n = 0;
    for (int t : measured)
        if ((*cluster)[size_t(t)] == k) {
            const glm::dvec3 d = colour[size_t(t)] - (*centre)[size_t(k)];
            C += glm::outerProduct(d, d);
            ++n;
        }
    // Power iteration towards the largest eigenvector (3 x 3: no library), from the column of
    // the largest variance: never orthogonal to the axis of the spread.
    int widest = 0;
    for (int i = 1; i < 3; ++i)
        if (C[i][i] > C[widest][widest]) widest = i;
    glm::dvec3 v = C[widest];
    for (int it = 0; it < 64; ++it) {
        const glm::dvec3 w = C * v;
        const double l = glm::length(w);
        if (!(l > 0)) return false;
        v = w / l;
    }
    const glm::dvec3 m = (*centre)[size_t(k)];
    const double sd = std::sqrt(glm::dot(v, C * v) / std::max(1, n));
    if (!(sd > 1e-9 * (1 + glm::length(m)))) return false;
    glm::dvec3 a = m + sd * v, b = m - sd * v;
    std::vector<int> side;  // per member: 0 with a, 1 with b
    for (int t : measured)
        if ((*cluster)[size_t(t)] == k) side.push_back(0);
    for (int it = 0; it < 10; ++it) {
        glm::dvec3 sa(0), sb(0);
        int na = 0, nb = 0;
        size_t i = 0;
        for (int t : measured) {
            if ((*cluster)[size_t(t)] != k) continue;
            const glm::dvec3& x = colour[size_t(t)];
            side[i] = glm::dot(x - a, x - a) <= glm::dot(x - b, x - b) ? 0 : 1;
            (side[i] ? sb : sa) += x;
            ++(side[i++] ? nb : na);
        }
        if (na == 0 || nb == 0) return false;
        a = sa / double(na);
        b = sb / double(nb);
    }
    const int kb = int(centre->size());
    size_t i = 0;
    for (int t : measured)
        if ((*cluster)[size_t(t)] == k && side[i++]) (*cluster)[size_t(t)] = kb;
    (*centre)[size_t(k)] = a;
    centre->push_back(b);
    return true;
}

void colour_clusters(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
                     int clusters, const SurfaceAtlas& atlas, std::vector<glm::dvec3>* colour,
                     std::vector<int>* cluster) {
    texel_colours(caps, ix, measured, atlas, colour);
    const std::vector<glm::dvec3>& col = *colour;
    glm::dvec3 mean(0);
    for (int t : measured) {
        mean += col[size_t(t)];
        (*cluster)[size_t(t)] = 0;
    }
    std::vector<glm::dvec3> centre{mean / double(measured.size())};
    std::vector<uint8_t> whole{0};  // per cluster: a split failed, it stays as it is
    while (int(centre.size()) < clusters) {
        std::vector<double> spread(centre.size(), 0.0);
        for (int t : measured) {
            const glm::dvec3 d = col[size_t(t)] - centre[size_t((*cluster)[size_t(t)])];
            spread[size_t((*cluster)[size_t(t)])] += glm::dot(d, d);
        }
        int k = -1;
        for (int c = 0; c < int(centre.size()); ++c)
            if (!whole[size_t(c)] && (k < 0 || spread[size_t(c)] > spread[size_t(k)])) k = c;
        if (k < 0) break;  // nothing left to split: fewer clusters
        if (split_cluster(col, measured, k, &centre, cluster)) {
            whole.push_back(0);
        } else {
            whole[size_t(k)] = 1;
        }
    }
    for (int it = 0; it < 10; ++it) {
        for (int t : measured) {
            double best = 1e300;
            for (size_t k = 0; k < centre.size(); ++k) {
                const double d = glm::dot(col[size_t(t)] - centre[k], col[size_t(t)] - centre[k]);
                if (d < best) {
                    best = d;
                    (*cluster)[size_t(t)] = int(k);
                }
            }
        }
        std::vector<glm::dvec3> sum(centre.size(), glm::dvec3(0));
        std::vector<int> cnt(centre.size(), 0);
        for (int t : measured) {
            sum[size_t((*cluster)[size_t(t)])] += col[size_t(t)];
            ++cnt[size_t((*cluster)[size_t(t)])];
        }
        for (size_t k = 0; k < centre.size(); ++k)
            if (cnt[k]) centre[k] = sum[k] / double(cnt[k]);
    }
}

// Moves the texels of cluster `gone` to the nearest other cluster by colour. False when no
// other cluster is left.
bool dissolve_cluster(int gone, const std::vector<int>& measured, const std::vector<glm::dvec3>& colour,
                      std::vector<int>* cluster) {
    std::map<int, std::pair<glm::dvec3, int>> centres;
    for (int t : measured)
        if ((*cluster)[size_t(t)] != gone) {
            auto& c = centres[(*cluster)[size_t(t)]];
            c.first += colour[size_t(t)];
            ++c.second;
        }
    if (centres.empty()) return false;
    for (int t : measured)
        if ((*cluster)[size_t(t)] == gone) {
            double best = 1e300;
            for (const auto& c : centres) {
                const glm::dvec3 d = colour[size_t(t)] - c.second.first / double(c.second.second);
                if (glm::dot(d, d) < best) {
                    best = glm::dot(d, d);
                    (*cluster)[size_t(t)] = c.first;
                }
            }
        }
    return true;
}

// Renumbers the clusters in order without the empty ones; the fits of the kept clusters
// (those fits has) in *kept_fits, and their flags (optional, one per fit) kept the same way.
// Returns the number kept.
int drop_empty_clusters(const std::vector<int>& measured, const std::vector<LafortuneFit>& fits,
                        std::vector<int>* cluster, std::vector<LafortuneFit>* kept_fits,
                        std::vector<uint8_t>* flags = nullptr) {
    std::vector<uint8_t> kept_flags;
    int K = 0;
    for (int t : measured) K = std::max(K, (*cluster)[size_t(t)] + 1);
    std::vector<int> cnt(size_t(K), 0), remap(size_t(K), -1);
    for (int t : measured) ++cnt[size_t((*cluster)[size_t(t)])];
    int kept = 0;
    for (int k = 0; k < K; ++k)
        if (cnt[size_t(k)] > 0) {
            remap[size_t(k)] = kept++;
            if (size_t(k) < fits.size()) kept_fits->push_back(fits[size_t(k)]);
            if (flags && size_t(k) < flags->size()) kept_flags.push_back((*flags)[size_t(k)]);
        }
    for (int t : measured) (*cluster)[size_t(t)] = remap[size_t((*cluster)[size_t(t)])];
    if (flags) *flags = std::move(kept_flags);
    return kept;
}

// A cluster without a plausible fit keeps its colour: the model becomes diffuse, rho_d by
// weighted least squares on its samples (f = rho_d / pi), its lobes switched off (C = 0).
void drop_lobes(const std::vector<BrdfSample>& s, LafortuneModel* m) {
    glm::dvec3 num(0);
    double den = 0;
    for (const BrdfSample& x : s) {
        num += x.weight * x.weight * x.value;
        den += x.weight * x.weight;
    }
    const glm::dvec3 rho = den > 0 ? num * (kPi / den) : glm::dvec3(0);
    m->rho_d = glm::clamp(rho, glm::dvec3(0), glm::dvec3(1));
    for (LafortuneLobe& l : m->lobes) l = LafortuneLobe{0, 0, 0, 1, glm::dvec3(1)};
}

// The final fit's options for one cluster, chosen by how well each candidate predicts views it
// was not fitted to. Candidates: the options as given (the previous iteration's start), one
// lobe from the grid's starts, one more lobe from the grid's, kept forward when `forward`
// (LafortuneFitOptions::forward; free, the extra lobe of the bench's gold paint went to grazing
// angles, where no capture measures). A candidate whose fit to all
// samples does not render as fitted (the spec clamps it: a negative diffuse colour that a
// lobe made up for) or creates energy (max_albedo) is out. The samples fall into kFolds folds
// by capture; each remaining candidate is fitted to all but one fold and scored by its
// weighted residual on that fold; the lowest total wins, the earlier (fewer parameters) where
// no fold can be held out. A model fitted to every view can bend where none measured (a lobe
// that lives only at grazing angles, a second lobe where the data hold one); held-out views
// and the energy bound see that. *out: the winner's fit to all samples (tinted when `tint`);
// false when no candidate is plausible.
bool chosen_fit(const std::vector<BrdfSample>& s, const std::vector<int>& view, const LafortuneFitOptions& given,
                int max_lobes, bool forward, bool tint, LafortuneFit* out) {
    constexpr int kFolds = 3;
    std::vector<LafortuneFitOptions> cand{given};
    LafortuneFitOptions grid = given;
    grid.start = nullptr;
    if (given.start) cand.push_back(grid);
    if (grid.lobes < max_lobes) {
        ++grid.lobes;
        grid.forward = forward;
        cand.push_back(grid);
    }
    std::vector<BrdfSample> fit_of[kFolds], test_of[kFolds];  // fold f: fitted without it, tested on it
    for (int f = 0; f < kFolds; ++f)
        for (size_t i = 0; i < s.size(); ++i) (view[i] % kFolds == f ? test_of[f] : fit_of[f]).push_back(s[i]);
    double best = kInf;
    bool picked = false;
    for (size_t c = 0; c < cand.size(); ++c) {
        LafortuneFit all;
        if (!fit_lafortune(s, cand[c], &all, nullptr)) continue;
        if (tint) tint_lafortune_lobes(s, &all.model);
        if (!lafortune_plausible(all.model)) continue;
        double score = 0;
        for (int f = 0; f < kFolds && score < best; ++f) {
            const std::vector<BrdfSample>& fit_s = fit_of[f];
            const std::vector<BrdfSample>& test_s = test_of[f];
            LafortuneFit fit;
            if (test_s.empty() || !fit_lafortune(fit_s, cand[c], &fit, nullptr)) {
                score = kInf;
                break;
            }
            if (tint) tint_lafortune_lobes(fit_s, &fit.model);
            for (const BrdfSample& x : test_s) {
                const glm::dvec3 d = (fit.model.eval(x.wi, x.wo) - x.value) * x.weight;
                score += glm::dot(d, d);
            }
        }
        if (!(score < kInf)) score = kInf;  // NaN too: it must not block the later candidates
        if (!picked || score < best) {
            best = score;
            picked = true;
            *out = std::move(all);
        }
    }
    return picked;
}

// Every measured texel to the cluster whose model explains its samples best (weighted
// residual).
void reassign(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
              const std::vector<LafortuneFit>& fits, int threads, std::vector<int>* cluster) {
    parallel_for(64, threads, [&](size_t chunk) {
        for (size_t m = measured.size() * chunk / 64; m < measured.size() * (chunk + 1) / 64; ++m) {
            const int t = measured[m];
            double best = kInf;
            for (size_t k = 0; k < fits.size(); ++k) {
                const double r = texel_residual(fits[k].model, caps, ix, t);
                if (r < best) {
                    best = r;
                    (*cluster)[size_t(t)] = int(k);
                }
            }
        }
    });
}

// (2) A Lafortune fit per cluster; texels reassigned to the fit that explains their samples
// best; repeated o.iterations times. A cluster with too few samples for a fit, or whose fit
// fails, is dissolved into the nearest (by colour) and the iteration runs again.
bool fit_clusters(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
                  const std::vector<glm::dvec3>& colour, const ReconstructOptions& o,
                  std::vector<int>* cluster, std::vector<LafortuneFit>* fits_out, std::vector<uint8_t>* dropped_out,
                  std::string* err) {
    std::vector<uint8_t> dropped;
    constexpr int kMinClusterSamples = 16;
    std::vector<LafortuneFit> fits;
    for (int it = 0; it <= o.iterations; ++it) {
        {
            std::map<int, int> samples_of;
            for (int t : measured) samples_of[(*cluster)[size_t(t)]] += ix.count(t);
            for (const auto& c : samples_of)
                if (c.second < kMinClusterSamples && samples_of.size() > 1 &&
                    dissolve_cluster(c.first, measured, colour, cluster)) {
                    fits.clear();
                    break;  // one at a time: the next iteration looks again
                }
        }
        std::vector<LafortuneFit> kept_fits;
        const int kept = drop_empty_clusters(measured, fits, cluster, &kept_fits);
        const bool warm = kept_fits.size() == size_t(kept);
        std::vector<LafortuneFit> next(static_cast<size_t>(kept));
        std::vector<std::string> errors(static_cast<size_t>(kept));
        std::vector<int> ok(size_t(kept), 0);
        dropped.assign(size_t(kept), 0);
        parallel_for(size_t(kept), o.threads, [&](size_t k) {
            std::vector<std::pair<int, int>> refs;
            for (int t : measured)
                if ((*cluster)[size_t(t)] == int(k))
                    for (int j = ix.start[size_t(t)]; j < ix.start[size_t(t) + 1]; ++j) refs.push_back(ix.refs[size_t(j)]);
            const size_t stride = std::max<size_t>(1, (refs.size() + size_t(o.max_cluster_samples) - 1) /
                                                          size_t(std::max(1, o.max_cluster_samples)));
            std::vector<BrdfSample> s;
            for (size_t j = 0; j < refs.size(); j += stride) s.push_back(sample_of(caps, refs[j]));
            LafortuneFitOptions fo;
            fo.lobes = o.lobes;
            fo.sigma = 1.0;  // weights are 1 / std (capture.h)
            if (warm) fo.start = &kept_fits[k].model;
            if (it == o.iterations && o.choose_fit) {
                std::vector<int> view;
                for (size_t j = 0; j < refs.size(); j += stride) view.push_back(refs[j].first);
                if (chosen_fit(s, view, fo, o.max_lobes, o.forward_lobes, o.tint_lobes, &next[k])) {
                    ok[k] = 1;
                    return;
                }
                dropped[k] = 1;
            }
            ok[k] = fit_lafortune(s, fo, &next[k], &errors[k]);
            if (ok[k] && o.tint_lobes) tint_lafortune_lobes(s, &next[k].model);
            if (ok[k] && dropped[k]) drop_lobes(s, &next[k].model);
        });
        bool redo = false;
        for (int k = 0; k < kept && !redo; ++k)
            if (!ok[size_t(k)]) {
                if (kept == 1 || !dissolve_cluster(k, measured, colour, cluster)) {
                    if (err) *err = "reconstruct: cluster " + std::to_string(k) + ": " + errors[size_t(k)];
                    return false;
                }
                redo = true;
            }
        if (redo) {
            fits.clear();
            --it;  // the same iteration with one cluster fewer (terminates: clusters only go)
            continue;
        }
        fits = std::move(next);
        if (it == o.iterations) break;
        reassign(caps, ix, measured, fits, o.threads, cluster);
    }
    // The chosen fits are not the ones the texels were last assigned by: once more by them,
    // and a cluster this empties goes (with its fit and flag).
    if (o.choose_fit) {
        reassign(caps, ix, measured, fits, o.threads, cluster);
        std::vector<LafortuneFit> kept;
        drop_empty_clusters(measured, fits, cluster, &kept, &dropped);
        fits = std::move(kept);
    }
    *fits_out = std::move(fits);
    *dropped_out = std::move(dropped);
    return true;
}

// (3) Per measured texel, non-negative weights over the basis: weighted least squares on
// its samples, ridge-pulled towards its own cluster's model. The normal equations are kept
// per fold of captures (index % kWeightFolds) so that a ridge can be scored on views its
// weights were not fitted to: x^T A_f x - 2 x^T b_f + c_f is fold f's weighted residual.
constexpr int kWeightFolds = 3;

struct TexelSystem {
    std::vector<double> A, b;  // per fold: K x K, K
    double c[kWeightFolds] = {0, 0, 0};
};

void texel_system(const std::vector<Capture>& caps, const TexelIndex& ix, int t,
                  const std::vector<LafortuneFit>& fits, TexelSystem* sys) {
    const int K = int(fits.size());
    sys->A.assign(size_t(kWeightFolds * K * K), 0.0);
    sys->b.assign(size_t(kWeightFolds * K), 0.0);
    std::fill(sys->c, sys->c + kWeightFolds, 0.0);
    std::vector<glm::dvec3> fk(static_cast<size_t>(K));
    for (int j = ix.start[size_t(t)]; j < ix.start[size_t(t) + 1]; ++j) {
        const int f = ix.refs[size_t(j)].first % kWeightFolds;
        const BrdfSample s = sample_of(caps, ix.refs[size_t(j)]);
        const double w2 = s.weight * s.weight;
        for (int k = 0; k < K; ++k) fk[size_t(k)] = fits[size_t(k)].model.eval(s.wi, s.wo);
        double* A = &sys->A[size_t(f * K * K)];
        double* b = &sys->b[size_t(f * K)];
        for (int k = 0; k < K; ++k) {
            b[k] += w2 * glm::dot(fk[size_t(k)], s.value);
            for (int l = 0; l < K; ++l) A[k * K + l] += w2 * glm::dot(fk[size_t(k)], fk[size_t(l)]);
        }
        sys->c[f] += w2 * glm::dot(s.value, s.value);
    }
}

// What a texel's weights are pulled towards: its cluster's material (one-hot), or, given
// earlier weights, the mean of its measured 8-neighbours' (across the atlas's edges where the
// surface continues: SurfaceAtlas::step; its cluster where no neighbour was measured). For scoring a held-out
// fold f the earlier weights are those solved without fold f: a neighbour's fold f holds the
// same views, so weights fitted to it would carry the held-out views into the prior.
struct WeightPrior {
    const std::vector<int>* cluster = nullptr;
    // Per texel K weights: solved from all folds ([kWeightFolds]) or without fold f ([f]);
    // null: one-hot.
    const std::vector<float>* earlier[kWeightFolds + 1] = {};
    const std::vector<uint8_t>* measured = nullptr;  // per texel
    const SurfaceAtlas* atlas = nullptr;

    // fold: the held-out fold, -1 for none.
    void of(int t, int K, int fold, double* p) const {
        std::fill(p, p + K, 0.0);
        int n = 0;
        const std::vector<float>* w = earlier[fold < 0 ? kWeightFolds : fold];
        if (w) {
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int q = atlas->step(t, dx, dy);
                    if (q < 0 || q == t || !(*measured)[size_t(q)]) continue;
                    for (int k = 0; k < K; ++k) p[k] += double((*w)[size_t(q) * size_t(K) + size_t(k)]);
                    ++n;
                }
        }
        if (n == 0) {
            p[(*cluster)[size_t(t)]] = 1.0;
            return;
        }
        for (int k = 0; k < K; ++k) p[k] /= n;
    }
};

// The weights from the folds not equal to `skip` (-1: all), ridge_share of their own scale
// towards `prior` (K values).
void solve_weights(const TexelSystem& sys, int K, int skip, const double* prior, double ridge_share,
                   std::vector<double>* A, std::vector<double>* b, std::vector<double>* x) {
    std::fill(A->begin(), A->end(), 0.0);
    std::fill(b->begin(), b->end(), 0.0);
    for (int f = 0; f < kWeightFolds; ++f) {
        if (f == skip) continue;
        for (int i = 0; i < K * K; ++i) (*A)[size_t(i)] += sys.A[size_t(f * K * K + i)];
        for (int i = 0; i < K; ++i) (*b)[size_t(i)] += sys.b[size_t(f * K + i)];
    }
    double trace = 0;
    for (int k = 0; k < K; ++k) trace += (*A)[size_t(k * K + k)];
    const double ridge = ridge_share * trace / K + 1e-30;
    for (int k = 0; k < K; ++k) {
        (*A)[size_t(k * K + k)] += ridge;
        (*b)[size_t(k)] += ridge * prior[k];
        (*x)[size_t(k)] = prior[k];
    }
    nnls_small(*A, *b, K, x);
}

// The ridge share for the weights: o.ridge_share, or (o.choose_ridge) the candidate whose
// weights best predict each texel's held-out folds, summed over the measured texels.
double chosen_ridge(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
                    const WeightPrior& prior, const std::vector<LafortuneFit>& fits, const ReconstructOptions& o) {
    if (!o.choose_ridge) return o.ridge_share;
    static const double kCandidates[] = {1e-3, 1e-2, 1e-1, 1.0};
    constexpr int kC = 4, kChunks = 64;
    const int K = int(fits.size());
    std::vector<double> score(size_t(kChunks * kC), 0.0);  // per chunk: summed in order below
    parallel_for(kChunks, o.threads, [&](size_t chunk) {
        TexelSystem sys;
        std::vector<double> A(static_cast<size_t>(K * K)), b(static_cast<size_t>(K)), x(static_cast<size_t>(K)),
            p(static_cast<size_t>(K));
        for (size_t m = measured.size() * chunk / kChunks; m < measured.size() * (chunk + 1) / kChunks; ++m) {
            const int t = measured[m];
            texel_system(caps, ix, t, fits, &sys);
            for (int f = 0; f < kWeightFolds; ++f) {
                prior.of(t, K, f, p.data());
                for (int r = 0; r < kC; ++r) {
                    solve_weights(sys, K, f, p.data(), kCandidates[r], &A, &b, &x);
                    const double* Af = &sys.A[size_t(f * K * K)];
                    const double* bf = &sys.b[size_t(f * K)];
                    double e = sys.c[f];
                    for (int k = 0; k < K; ++k) {
                        e -= 2 * x[size_t(k)] * bf[k];
                        for (int l = 0; l < K; ++l) e += x[size_t(k)] * Af[k * K + l] * x[size_t(l)];
                    }
                    score[chunk * kC + size_t(r)] += e;
                }
            }
        }
    });
    int best = 0;
    double best_score = kInf;
    for (int r = 0; r < kC; ++r) {
        double sum = 0;
        for (int chunk = 0; chunk < kChunks; ++chunk) sum += score[size_t(chunk * kC + r)];
        if (sum < best_score) {
            best_score = sum;
            best = r;
        }
    }
    return kCandidates[best];
}

// The weights of the measured texels from all folds into *weights and, for each f where
// without[f] is given, from all folds but f into *without[f]: one texel system for them all.
void project_weights(const std::vector<Capture>& caps, const TexelIndex& ix, const std::vector<int>& measured,
                     const WeightPrior& prior, const std::vector<LafortuneFit>& fits, double ridge_share,
                     int threads, std::vector<float>* weights, std::vector<float>* const* without = nullptr) {
    const int K = int(fits.size());
    parallel_for(64, threads, [&](size_t chunk) {
        TexelSystem sys;
        std::vector<double> A(static_cast<size_t>(K * K)), b(static_cast<size_t>(K)), x(static_cast<size_t>(K)),
            p(static_cast<size_t>(K));
        for (size_t m = measured.size() * chunk / 64; m < measured.size() * (chunk + 1) / 64; ++m) {
            const int t = measured[m];
            texel_system(caps, ix, t, fits, &sys);
            for (int skip = -1; skip < kWeightFolds; ++skip) {
                std::vector<float>* out = skip < 0 ? weights : without ? without[skip] : nullptr;
                if (!out) continue;
                prior.of(t, K, skip, p.data());
                solve_weights(sys, K, skip, p.data(), ridge_share, &A, &b, &x);
                for (int k = 0; k < K; ++k) (*out)[size_t(t) * size_t(K) + size_t(k)] = float(x[size_t(k)]);
            }
        }
    });
}

// (4) Texels without samples: the nearest measured texel's cluster and weights (breadth
// first over the atlas grid, across its edges where the surface continues).
void fill_unmeasured(const SurfaceAtlas& a, const std::vector<int>& measured, int K, bool weights_too,
                     std::vector<int>* cluster, std::vector<float>* weights) {
    const size_t n = a.valid.size();
    std::deque<int> queue(measured.begin(), measured.end());
    std::vector<uint8_t> done(n, 0);
    for (int t : measured) done[size_t(t)] = 1;
    while (!queue.empty()) {
        const int t = queue.front();
        queue.pop_front();
        const int nb[4] = {a.step(t, 1, 0), a.step(t, -1, 0), a.step(t, 0, 1), a.step(t, 0, -1)};
        for (int q : nb) {
            if (q < 0 || done[size_t(q)] || !a.valid[size_t(q)]) continue;
            done[size_t(q)] = 1;
            (*cluster)[size_t(q)] = (*cluster)[size_t(t)];
            if (weights_too)
                for (int k = 0; k < K; ++k)
                    (*weights)[size_t(q) * size_t(K) + size_t(k)] = (*weights)[size_t(t) * size_t(K) + size_t(k)];
            queue.push_back(q);
        }
    }
}

}  // namespace

bool reconstruct(const AcqObject& obj, const std::vector<Capture>& caps, const ReconstructOptions& o,
                 Reconstruction* out, std::string* err) {
    if (o.clusters < 1 || o.clusters > 8 || o.lobes < 1 || o.lobes > 4 || o.max_lobes < 1 || o.max_lobes > 4) {
        if (err) *err = "reconstruct: clusters must be 1..8, lobes and max_lobes 1..4";
        return false;
    }
    const SurfaceAtlas& a = obj.atlas;
    const size_t n = a.valid.size();
    const TexelIndex ix = index_samples(n, caps);
    std::vector<int> measured;
    for (int t : a.texels)
        if (ix.count(t) > 0) measured.push_back(t);
    if (measured.empty()) {
        if (err) *err = "reconstruct: no texel has a sample";
        return false;
    }
    std::vector<glm::dvec3> colour(n, glm::dvec3(0));
    std::vector<int> cluster(n, -1);
    colour_clusters(caps, ix, measured, o.clusters, a, &colour, &cluster);
    std::vector<LafortuneFit> fits;
    std::vector<uint8_t> dropped;
    if (!fit_clusters(caps, ix, measured, colour, o, &cluster, &fits, &dropped, err)) return false;
    const int K = int(fits.size());

    Reconstruction r;
    r.basis = fits;
    r.lobes_dropped = dropped;
    r.samples.assign(n, 0);
    for (int t : a.texels) r.samples[size_t(t)] = ix.count(t);
    r.svbrdf.maps.width = r.svbrdf.maps.height = a.res;
    r.svbrdf.maps.count = K;
    for (const LafortuneFit& f : fits) {
        std::string e;
        std::unique_ptr<Brdf> b = make_brdf(f.model.spec(), &e);
        if (!b) {
            if (err) *err = "reconstruct: " + e;
            return false;
        }
        r.svbrdf.basis.emplace_back(std::move(b));
        r.svbrdf.specs.push_back(f.model.spec());
    }
    if (o.project) {
        r.svbrdf.maps.w.assign(n * size_t(K), 0.0f);
        WeightPrior own;
        own.cluster = &cluster;
        r.ridge_share = chosen_ridge(caps, ix, measured, own, fits, o);
        // With the neighbours' pull to come, also the weights without each fold: its priors
        // when that fold is held out.
        std::vector<float> earlier[kWeightFolds];
        std::vector<float>* without[kWeightFolds] = {};
        if (o.spatial)
            for (int f = 0; f < kWeightFolds; ++f) {
                earlier[f].assign(n * size_t(K), 0.0f);
                without[f] = &earlier[f];
            }
        project_weights(caps, ix, measured, own, fits, r.ridge_share, o.threads, &r.svbrdf.maps.w, without);
        if (o.spatial) {
            std::vector<uint8_t> is_measured(n, 0);
            for (int t : measured) is_measured[size_t(t)] = 1;
            const std::vector<float> all = r.svbrdf.maps.w;
            WeightPrior near = own;
            near.measured = &is_measured;
            near.atlas = &a;
            for (int f = 0; f < kWeightFolds; ++f) near.earlier[f] = &earlier[f];
            near.earlier[kWeightFolds] = &all;
            r.spatial_share = chosen_ridge(caps, ix, measured, near, fits, o);
            project_weights(caps, ix, measured, near, fits, r.spatial_share, o.threads, &r.svbrdf.maps.w);
        }
    }
    fill_unmeasured(a, measured, K, o.project, &cluster, &r.svbrdf.maps.w);
    r.cluster = cluster;
    r.texel_model.assign(n, LafortuneModel());
    for (int t : a.texels)
        if (cluster[size_t(t)] >= 0) r.texel_model[size_t(t)] = fits[size_t(cluster[size_t(t)])].model;
    *out = std::move(r);
    return true;
}

std::vector<TexelFit> fit_texels(const AcqObject& obj, const std::vector<Capture>& caps, const Reconstruction& r,
                                 int min_samples, int threads) {
    const size_t n = obj.atlas.valid.size();
    const TexelIndex ix = index_samples(n, caps);
    std::vector<TexelFit> out(n);
    const std::vector<int>& texels = obj.atlas.texels;
    parallel_for(64, threads, [&](size_t chunk) {
        for (size_t m = texels.size() * chunk / 64; m < texels.size() * (chunk + 1) / 64; ++m) {
            const int t = texels[m];
            if (ix.count(t) < min_samples || r.cluster[size_t(t)] < 0) continue;
            std::vector<BrdfSample> s;
            for (int j = ix.start[size_t(t)]; j < ix.start[size_t(t) + 1]; ++j) s.push_back(sample_of(caps, ix.refs[size_t(j)]));
            LafortuneFitOptions fo;
            fo.sigma = 1.0;
            // The per-texel fits have one lobe; a cluster model of two (choose_fit) starts them
            // from its stronger one (the larger peak at normal incidence).
            LafortuneModel start = r.texel_model[size_t(t)];
            const int c = r.cluster[size_t(t)];  // a cluster made diffuse: its C = 0 lobe cannot move
            const bool lobe_off = size_t(c) < r.lobes_dropped.size() && r.lobes_dropped[size_t(c)];
            if (start.lobes.size() > 1) {
                auto peak = [](const LafortuneLobe& l) {
                    return std::pow(std::fabs(l.cz), l.n) * (l.colour.x + l.colour.y + l.colour.z);
                };
                const LafortuneLobe keep = *std::max_element(
                    start.lobes.begin(), start.lobes.end(),
                    [&](const LafortuneLobe& a, const LafortuneLobe& b) { return peak(a) < peak(b); });
                start.lobes = {keep};
            }
            fo.start = lobe_off ? nullptr : &start;  // nullptr: the grid's starts
            fo.max_evaluations = 100;
            LafortuneFit f;
            if (!fit_lafortune(s, fo, &f, nullptr)) continue;
            TexelFit& tf = out[size_t(t)];
            tf.fitted = true;
            tf.rank = f.rank;
            tf.params = f.params;
            tf.ci95.resize(f.params.size());
            for (int j = 0; j < f.params.size(); ++j) tf.ci95[j] = f.ci95(j);
        }
    });
    return out;
}

}  // namespace sepal
