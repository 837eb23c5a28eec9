#include "database/measure_plan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "util/enum_names.h"
#include "database/linear_model.h"
#include "database/plan_picture.h"
#include "util/io.h"
#include "util/parallel.h"
#include "util/thin_product.h"

namespace sepal {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Json = nlohmann::ordered_json;

constexpr int kMaxSamples = 100000;
constexpr int kMaxCandidates = 1024;
constexpr int kMaxPictureSwaps = 1 << 20;
constexpr double kRadToDeg = 57.295779513082320876798;

std::vector<int> used(const BrdfDatabase& db, const std::vector<uint8_t>& use) {
    std::vector<int> cols;
    for (int j = 0; j < db.size(); ++j)
        if (use.empty() || use[size_t(j)]) cols.push_back(j);
    return cols;
}

double exact_condition(const MatrixXd& A) {
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(A, Eigen::EigenvaluesOnly);
    const double lo = es.eigenvalues()(0), hi = es.eigenvalues()(A.rows() - 1);
    return lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
}

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// rows x B = pool (M x K) * U (K x B), computed in row blocks on all cores (each block is
// independent: the result does not depend on the thread count). The swap loop's B = 2
// scans go through thin_product: Eigen's product copied ("packed") the whole 24,576 x 99
// pool on every call, 3.4 ms against 1.7 ms streamed, 120-odd times per plan.
RowMat pool_times(const RowMat& pool, const RowMat& U) {
    RowMat T(pool.rows(), U.cols());
    constexpr Index kBlock = 8192;
    const size_t blocks = size_t((pool.rows() + kBlock - 1) / kBlock);
    parallel_for(blocks, 0, [&](size_t b) {
        const Index r0 = Index(b) * kBlock, n = std::min(kBlock, pool.rows() - r0);
        if (!thin_product(pool.row(r0).data(), size_t(pool.cols()), int(n), int(pool.cols()), U.data(),
                          int(U.cols()), T.row(r0).data()))
            T.middleRows(r0, n).noalias() = pool.middleRows(r0, n) * U;
    });
    return T;
}

// The candidates' rows of the system the fit solves, column-normalised, in double (leverages
// cancel heavily). Linear space: the materials' values, columns scaled to unit norm over the
// whole grid, rows by 1/sigma of the residual model (o.weighted). Log space: the log model's
// design (linear_model.h: log(P_j + eps) and the channel indicators, times cos theta_i),
// columns scaled to unit norm over the candidates.
RowMat design_pool(const BrdfDatabase& db, const PlanOptions& o, const std::vector<int>& cols,
                   const std::vector<size_t>& cand) {
    const size_t M = cand.size();
    const int K = int(cols.size());
    if (o.space == FitSpace::kLog) {
        RowMat pool(Index(M), K + 3);
        for (size_t i = 0; i < M; ++i)
            log_design_row(db, db.pool_row_index(cand[i]), db.pool_row(cand[i]), cols, pool.row(Index(i)).data());
        for (Index j = 0; j < pool.cols(); ++j) {
            const double n = pool.col(j).norm();
            if (n > 0.0) pool.col(j) /= n;
        }
        return pool;
    }
    std::vector<double> scale(static_cast<size_t>(K));
    for (int j = 0; j < K; ++j) {
        const double g = db.gram()[size_t(cols[size_t(j)]) * size_t(db.size()) + size_t(cols[size_t(j)])];
        scale[size_t(j)] = g > 0.0 ? 1.0 / std::sqrt(g) : 0.0;
    }
    std::vector<double> sigma2;
    if (o.weighted) {
        std::vector<size_t> grid_rows(M);
        for (size_t i = 0; i < M; ++i) grid_rows[i] = db.pool_row_index(cand[i]);
        sigma2 = row_sigma2(db, residual_model(db, o.use), grid_rows);
    }
    RowMat pool(Index(M), K);  // row-major: rows are what every step reads
    for (size_t i = 0; i < M; ++i) {
        const float* r = db.pool_row(cand[i]);
        const double w = o.weighted ? 1.0 / std::sqrt(sigma2[i]) : 1.0;
        for (int j = 0; j < K; ++j)
            pool(Index(i), j) = double(r[cols[size_t(j)]]) * scale[size_t(j)] * w;
    }
    return pool;
}

// PlanObjective::kPrediction: greedy V-optimal design. Each step adds the candidate that most
// lowers the mean prediction variance over the candidates, mean_p r_p^T A^-1 r_p (A = delta I
// + X^T X): adding a lowers it by v^T G v / (1 + a^T v), v = A^-1 a, G = P^T P / M. Per block
// of rows the gains are computed exactly for every candidate (V = P A^-1, one product each
// with A^-1 and G); within the block, a short list of the best is updated exactly by
// Sherman-Morrison as each row goes in (the forward pass of plan_greedy, another gain).
void plan_prediction(const RowMat& pool, const std::vector<size_t>& cand, int N, std::vector<size_t>* sel) {
    const Index M = pool.rows(), K = pool.cols();
    const MatrixXd G = pool.transpose() * pool / double(M);
    const double delta = 1e-6 * std::max(G.trace() / double(K), 1e-300);
    MatrixXd Ainv = MatrixXd::Identity(K, K) / delta;
    std::vector<uint8_t> chosen(static_cast<size_t>(M), 0);
    constexpr int kBlock = 32, kShort = 256;
    while (int(sel->size()) < N) {
        const int B = std::min(kBlock, N - int(sel->size()));
        const RowMat V = pool_times(pool, RowMat(Ainv));
        const RowMat VG = pool_times(V, RowMat(G));
        std::vector<size_t> idx;
        std::vector<double> gain(static_cast<size_t>(M), -1.0), g(static_cast<size_t>(M), 0.0), lev(static_cast<size_t>(M), 0.0);
        for (Index i = 0; i < M; ++i) {
            if (chosen[size_t(i)]) continue;
            g[size_t(i)] = VG.row(i).dot(V.row(i));
            lev[size_t(i)] = V.row(i).dot(pool.row(i));
            gain[size_t(i)] = g[size_t(i)] / (1.0 + lev[size_t(i)]);
            idx.push_back(size_t(i));
        }
        // A short list per channel: the plan takes R, G and B in turn, as the paper's does (a
        // channel left out would leave its offset unmeasured).
        std::vector<size_t> shortlist;
        for (size_t ch = 0; ch < 3; ++ch) {
            std::vector<size_t> in;
            for (size_t i : idx)
                if (cand[i] % 3 == ch) in.push_back(i);
            const size_t n = std::min<size_t>(kShort / 3 + size_t(B), in.size());
            std::partial_sort(in.begin(), in.begin() + Index(n), in.end(), [&](size_t a, size_t b) {
                return gain[a] > gain[b] || (gain[a] == gain[b] && a < b);
            });
            shortlist.insert(shortlist.end(), in.begin(), in.begin() + Index(n));
        }
        idx = shortlist;
        const size_t ns = idx.size(), before = sel->size();
        for (int b = 0; b < B; ++b) {
            const size_t want = sel->size() % 3;
            size_t best = ns;
            for (size_t s = 0; s < ns; ++s)
                if (!chosen[idx[s]] && cand[idx[s]] % 3 == want && (best == ns || gain[idx[s]] > gain[idx[best]])) best = s;
            if (best == ns) break;  // this channel's short list is spent: the next block refills it
            const size_t i = idx[best];
            chosen[i] = 1;
            sel->push_back(i);
            const VectorXd a = pool.row(Index(i)).transpose();
            const VectorXd u = Ainv * a;
            const double d = 1.0 + a.dot(u);
            const VectorXd z = Ainv * (G * u);
            const double uGu = u.dot(G * u);
            Ainv -= u * u.transpose() / d;
            for (size_t s = 0; s < ns; ++s) {
                const size_t j = idx[s];
                if (chosen[j]) continue;
                const double t = pool.row(Index(j)).dot(u) / d, q = pool.row(Index(j)).dot(z);
                g[j] += -2.0 * t * q + t * t * uGu;
                lev[j] -= t * t * d;
                gain[j] = g[j] / (1.0 + lev[j]);
            }
        }
        if (sel->size() == before) return;  // no candidate of the channel left (N <= candidates: not reached)
    }
}

bool plan_greedy(const BrdfDatabase& db, const PlanOptions& o, const std::vector<int>& cols,
                 MeasurementPlan* plan, std::string* err) {
    // Candidates: the pool's rows, or every stride-th pool cell (all 3 channels) of it.
    const size_t cells = db.pool_rows() / 3;
    const size_t stride = o.pool_cells > 0 && size_t(o.pool_cells) < cells ? cells / size_t(o.pool_cells) : 1;
    std::vector<size_t> cand;  // pool row indices
    for (size_t c = 0; c < cells; c += stride)
        for (size_t ch = 0; ch < 3; ++ch) cand.push_back(3 * c + ch);
    const size_t M = cand.size();
    const int N = o.samples;
    if (size_t(N) > M) {
        if (err) *err = "plan: " + std::to_string(N) + " samples is more than the " +
                        std::to_string(M) + " candidate rows of the planning pool";
        return false;
    }
    const RowMat pool = design_pool(db, o, cols, cand);
    const int K = int(pool.cols());
    if (o.objective == PlanObjective::kPrediction) {
        std::vector<size_t> sel;
        plan_prediction(pool, cand, N, &sel);
        if (int(sel.size()) < N) {
            if (err) *err = "plan: the pool ran out of candidates of one channel after " + std::to_string(sel.size()) + " samples";
            return false;
        }
        for (size_t i : sel) plan->rows.push_back(db.pool_row_index(cand[i]));
        return true;
    }
    VectorXd lev = pool.rowwise().squaredNorm();
    const double delta = 1e-9 * std::max(lev.maxCoeff(), 1e-300);
    lev /= delta;
    MatrixXd Ainv = MatrixXd::Identity(K, K) / delta;
    std::vector<uint8_t> chosen(M, 0);
    std::vector<size_t> sel;
    // Forward pass. Within a block, the leverages of a short list are updated exactly; at the
    // block's end the whole pool takes the block's rank-B update in one matrix product.
    constexpr int kBlock = 32, kShort = 256;
    while (int(sel.size()) < N) {
        const int B = std::min(kBlock, N - int(sel.size()));
        std::vector<size_t> idx;
        for (size_t i = 0; i < M; ++i)
            if (!chosen[i]) idx.push_back(i);
        const size_t ns = std::min<size_t>(kShort + size_t(B), idx.size());
        std::partial_sort(idx.begin(), idx.begin() + Index(ns), idx.end(), [&](size_t a, size_t b) {
            return lev(Index(a)) > lev(Index(b)) || (lev(Index(a)) == lev(Index(b)) && a < b);
        });
        idx.resize(ns);
        std::vector<double> slev(ns);
        for (size_t s = 0; s < ns; ++s) slev[s] = lev(Index(idx[s]));
        RowMat U(K, B);
        VectorXd den(B);
        for (int b = 0; b < B; ++b) {
            size_t best = ns;
            for (size_t s = 0; s < ns; ++s)
                if (!chosen[idx[s]] && (best == ns || slev[s] > slev[best])) best = s;
            const size_t i = idx[best];
            chosen[i] = 1;
            sel.push_back(i);
            const VectorXd a = pool.row(Index(i)).transpose();
            const VectorXd u = Ainv * a;
            const double d = 1.0 + a.dot(u);
            Ainv -= u * u.transpose() / d;
            U.col(b) = u;
            den(b) = d;
            for (size_t s = 0; s < ns; ++s) {
                const double t = pool.row(Index(idx[s])).dot(u);
                slev[s] -= t * t / d;
            }
        }
        const RowMat T = pool_times(pool, U);
        for (int b = 0; b < B; ++b) lev -= T.col(b).cwiseAbs2() / den(b);
    }
    MatrixXd A = MatrixXd::Zero(K, K);
    for (size_t i : sel) A.noalias() += pool.row(Index(i)).transpose() * pool.row(Index(i));
    double cond = exact_condition(A);
    plan->condition_forward = cond;
    if (o.progress)
        std::fprintf(o.progress, "plan: forward pass: %d samples, condition number %.4g\n", N, cond);

    // The paper's swap loop on the exact condition number.
    std::vector<size_t> pos_of(M, size_t(-1));
    for (size_t s = 0; s < sel.size(); ++s) pos_of[sel[s]] = s;
    for (int it = 0; it < o.max_swaps; ++it) {
        Eigen::SelfAdjointEigenSolver<MatrixXd> es(A);
        const double lo = es.eigenvalues()(0), hi = es.eigenvalues()(K - 1);
        RowMat V(K, 2);
        V.col(0) = es.eigenvectors().col(0);
        V.col(1) = es.eigenvectors().col(K - 1);
        const RowMat T = pool_times(pool, V);
        // First-order estimates of the condition number after adding / removing each row.
        std::vector<std::pair<double, size_t>> adds, rems;
        for (size_t i = 0; i < M; ++i) {
            const double pmin = T(Index(i), 0) * T(Index(i), 0), pmax = T(Index(i), 1) * T(Index(i), 1);
            if (!chosen[i]) {
                adds.push_back({(hi + pmax) / (lo + pmin), i});
            } else if (lo - pmin > 0.0) {
                rems.push_back({(hi - pmax) / (lo - pmin), i});
            }
        }
        const size_t na = std::min<size_t>(8, adds.size()), nr = std::min<size_t>(4, rems.size());
        std::partial_sort(adds.begin(), adds.begin() + Index(na), adds.end());
        std::partial_sort(rems.begin(), rems.begin() + Index(nr), rems.end());
        bool accepted = false;
        int tries = 0;
        for (size_t r = 0; r < nr && !accepted && tries < o.swap_tries; ++r) {
            for (size_t a = 0; a < na && tries < o.swap_tries; ++a, ++tries) {
                const VectorXd ra = pool.row(Index(adds[a].second)).transpose();
                const VectorXd rr = pool.row(Index(rems[r].second)).transpose();
                MatrixXd A2 = A + ra * ra.transpose() - rr * rr.transpose();
                const double c2 = exact_condition(A2);
                if (c2 < cond * (1.0 - 1e-9)) {
                    const size_t in = adds[a].second, out = rems[r].second;
                    A = A2;
                    cond = c2;
                    chosen[in] = 1;
                    chosen[out] = 0;
                    sel[pos_of[out]] = in;
                    pos_of[in] = pos_of[out];
                    pos_of[out] = size_t(-1);
                    ++plan->swaps;
                    accepted = true;
                    break;
                }
            }
        }
        if (!accepted) break;
    }
    if (o.progress)
        std::fprintf(o.progress, "plan: %d swaps, condition number %.4g\n", plan->swaps, cond);
    plan->rows.clear();
    for (size_t i : sel) plan->rows.push_back(db.pool_row_index(cand[i]));
    return true;
}

// N rows uniform over all rows, without repetition (rejection of repeats: N <= 100000 of
// ~3.3M rows, so few redraws).
std::vector<size_t> random_rows(size_t R, size_t N, uint64_t seed) {
    SplitMix64 rng(seed);
    std::vector<uint8_t> taken(R, 0);
    std::vector<size_t> rows;
    while (rows.size() < N) {
        const size_t r = size_t(rng.uniform() * double(R));
        if (r >= R || taken[r]) continue;
        taken[r] = 1;
        rows.push_back(r);
    }
    return rows;
}

// PlanMethod::kPicture: of o.candidates random plans (seeds o.seed, o.seed + 1, ...), the one
// whose leave-one-out pictures of the materials in use are best (plan_picture.h); then
// o.picture_swaps proposals, each a plan row exchanged for a random row, kept when the figure
// rises. Proposals are scored with the ridge weights of the last refresh (every kRefresh
// proposals, and at the end); a refresh that finds the plan below the best plan seen so far
// goes back to that one, so the result is never below the best candidate.
bool plan_picture(const BrdfDatabase& db, const PlanOptions& o, const std::vector<int>& cols,
                  MeasurementPlan* plan, std::string* err) {
    PlanPictureScorer scorer;
    if (!scorer.init(db, cols, o.picture_size, err)) return false;
    double best = -std::numeric_limits<double>::infinity();
    uint64_t best_seed = o.seed;
    for (int s = 0; s < o.candidates; ++s) {
        std::vector<size_t> rows = random_rows(db.rows(), size_t(o.samples), o.seed + uint64_t(s));
        const double score = scorer.score(rows);
        if (score > best) best = score, plan->rows = std::move(rows), best_seed = o.seed + uint64_t(s);
    }
    if (o.progress)
        std::fprintf(o.progress, "plan: the best of %d random plans (seed %llu): leave-one-out pictures %.2f dB\n",
                     o.candidates, (unsigned long long)best_seed, best);
    constexpr int kRefresh = 100, kReport = 500;
    std::vector<uint8_t> taken(db.rows(), 0);
    for (size_t r : plan->rows) taken[r] = 1;
    std::vector<double> lambdas;
    std::vector<size_t> best_rows = plan->rows;
    int best_swaps = 0;
    double current = scorer.score(plan->rows, &lambdas);
    SplitMix64 rng(o.seed ^ 0x5eb1c7u);
    // A plan of every row has no row to swap in.
    const int swaps = plan->rows.size() < db.rows() ? o.picture_swaps : 0;
    for (int t = 1; t <= swaps; ++t) {
        const size_t i = std::min(plan->rows.size() - 1, size_t(rng.uniform() * double(plan->rows.size())));
        size_t r = db.rows();
        while (r >= db.rows() || taken[r]) r = size_t(rng.uniform() * double(db.rows()));
        const size_t old = plan->rows[i];
        plan->rows[i] = r;
        const double s = scorer.score(plan->rows, &lambdas, true);
        if (s > current) {
            current = s, taken[old] = 0, taken[r] = 1, ++plan->swaps;
        } else {
            plan->rows[i] = old;
        }
        if (t % kRefresh == 0 || t == swaps) {
            current = scorer.score(plan->rows, &lambdas);
            if (current >= best) {
                best = current, best_rows = plan->rows, best_swaps = plan->swaps;
            } else {
                for (size_t x : plan->rows) taken[x] = 0;
                plan->rows = best_rows, plan->swaps = best_swaps;
                for (size_t x : plan->rows) taken[x] = 1;
                current = scorer.score(plan->rows, &lambdas);
            }
            if (o.progress && (t % kReport == 0 || t == swaps))
                std::fprintf(o.progress, "plan: %d/%d swaps proposed, %d kept: leave-one-out pictures %.2f dB\n", t,
                             o.picture_swaps, plan->swaps, best);
        }
    }
    plan->rows = best_rows;
    plan->swaps = best_swaps;  // the swaps in the plan kept, not those a refresh undid
    plan->picture_db = best;
    return true;
}

}  // namespace

constexpr EnumName<PlanMethod> kPlanMethods[] = {{PlanMethod::kGreedy, "greedy"}, {PlanMethod::kRandom, "random"}, {PlanMethod::kUniform, "uniform"},
                                                 {PlanMethod::kPicture, "picture"}};

const char* plan_method_name(PlanMethod m) { return enum_name(kPlanMethods, m); }

bool parse_plan_method(const std::string& s, PlanMethod* m) { return parse_enum(kPlanMethods, s, m); }

bool plan_measurement(const BrdfDatabase& db, const PlanOptions& o, MeasurementPlan* plan,
                      std::string* err) {
    *plan = MeasurementPlan();
    plan->method = o.method;
    plan->seed = o.seed;
    if (!o.use.empty() && int(o.use.size()) != db.size()) {
        if (err) *err = "plan: the material mask has the wrong size";
        return false;
    }
    const std::vector<int> cols = used(db, o.use);
    for (int j = 0; j < db.size(); ++j)
        if (!o.use.empty() && !o.use[size_t(j)]) plan->excluded.push_back(db.name(j));
    if (o.samples < 1 || o.samples > kMaxSamples || size_t(o.samples) > db.rows()) {
        if (err) *err = "plan: " + std::to_string(o.samples) + " samples is outside 1.." +
                        std::to_string(std::min<size_t>(kMaxSamples, db.rows()));
        return false;
    }
    // Fewer samples than fitted materials leave X^T X singular: no weights to fit.
    if (size_t(o.samples) < cols.size()) {
        if (err)
            *err = "plan: " + std::to_string(o.samples) + " samples cannot fit the weights of " +
                   std::to_string(cols.size()) + " materials: at least " + std::to_string(cols.size()) +
                   " samples (more for a well-conditioned plan), or fewer materials";
        return false;
    }
    const size_t R = db.rows(), V = db.valid_cells(), N = size_t(o.samples);
    if (o.method == PlanMethod::kGreedy) {
        if (!plan_greedy(db, o, cols, plan, err)) return false;
    } else if (o.method == PlanMethod::kPicture) {
        if (o.picture_swaps < 0 || o.picture_swaps > kMaxPictureSwaps) {
            if (err) *err = "plan: " + std::to_string(o.picture_swaps) + " picture swaps is outside 0.." + std::to_string(kMaxPictureSwaps);
            return false;
        }
        if (o.candidates < 1 || o.candidates > kMaxCandidates) {
            if (err) *err = "plan: " + std::to_string(o.candidates) + " candidates is outside 1.." + std::to_string(kMaxCandidates);
            return false;
        }
        if (!plan_picture(db, o, cols, plan, err)) return false;
    } else if (o.method == PlanMethod::kRandom) {
        plan->rows = random_rows(R, N, o.seed);
    } else {
        for (size_t i = 0; i < N; ++i) {
            const size_t v = std::min(V - 1, size_t((double(i) + 0.5) * double(V) / double(N)));
            plan->rows.push_back(3 * v + i % 3);
        }
    }
    plan->condition = plan_condition(db, plan->rows, o.use, o.weighted, o.space);
    if (!(std::isfinite(plan->condition) && plan->condition > 0)) {
        if (err)
            *err = "plan: the " + std::to_string(o.samples) + " samples chosen (" + plan_method_name(o.method) +
                   ") leave X^T X singular: they cannot tell the materials apart; more samples or another --method";
        return false;
    }
    return true;
}

void plan_row_directions(const BrdfDatabase& db, size_t row, glm::dvec3* wi, glm::dvec3* wo) {
    from_half_diff(db.cell_center(db.grid_cell(row / 3)), wi, wo);
}

bool write_plan_json(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& p,
                     std::string* err) {
    Json j;
    j["format"] = "sepal-measure-plan";
    j["version"] = 1;
    j["grid"] = {db.grid().n_theta_h, db.grid().n_theta_d, db.grid().n_phi_d};
    j["database"] = {{"materials", db.size()}, {"excluded", p.excluded}};
    j["method"] = plan_method_name(p.method);
    j["seed"] = p.seed;
    j["samples"] = p.rows.size();
    j["condition_number"] = p.condition;
    if (p.method == PlanMethod::kPicture) j["picture_db"] = p.picture_db;
    if (p.method == PlanMethod::kGreedy) {
        j["condition_number_forward"] = p.condition_forward;
        j["swaps"] = p.swaps;
    }
    Json list = Json::array();
    for (size_t row : p.rows) {
        const size_t cell = db.grid_cell(row / 3);
        const HalfDiff a = db.cell_center(cell);
        glm::dvec3 wi, wo;
        from_half_diff(a, &wi, &wo);
        auto deg = [](double r) { return std::round(r * kRadToDeg * 1e6) / 1e6; };
        auto azi = [&](const glm::dvec3& w) {
            double phi = std::atan2(w.y, w.x) * kRadToDeg;
            if (phi < 0.0) phi += 360.0;
            return std::round(phi * 1e6) / 1e6;
        };
        Json s;
        s["cell"] = cell;
        s["channel"] = row % 3;
        s["theta_h"] = a.theta_h;
        s["theta_d"] = a.theta_d;
        s["phi_d"] = a.phi_d;
        s["theta_i"] = deg(std::acos(std::min(1.0, wi.z)));
        s["phi_i"] = azi(wi);
        s["theta_o"] = deg(std::acos(std::min(1.0, wo.z)));
        s["phi_o"] = azi(wo);
        list.push_back(s);
    }
    j["plan"] = list;
    const std::string text = j.dump(1) + "\n";
    return write_file_atomic(path, text.data(), text.size(), err);
}

bool read_plan_json(const std::string& path, const BrdfDatabase& db, MeasurementPlan* p,
                    std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = path + ": " + why;
        return false;
    };
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 64u << 20)) return false;
    Json j;
    try {
        j = Json::parse(bytes.begin(), bytes.end());
    } catch (const nlohmann::json::exception& ex) {
        std::string what = ex.what();
        const size_t b = what.find("] ");
        return fail("not valid JSON: " + (b == std::string::npos ? what : what.substr(b + 2)));
    }
    try {
        if (!j.is_object() || j.value("format", "") != "sepal-measure-plan")
            return fail("not a sepal measurement plan (format \"sepal-measure-plan\")");
        // Integers only: a float version (1e91) converted to int is undefined behaviour.
        const auto ver = j.find("version");
        if (ver == j.end() || !ver->is_number_integer() || ver->get<int64_t>() != 1)
            return fail("plan version " + (ver == j.end() ? std::string("missing") : ver->dump()) +
                        " (this sepal reads 1)");
        const Json& g = j.at("grid");
        if (!g.is_array() || g.size() != 3 || g[0] != db.grid().n_theta_h ||
            g[1] != db.grid().n_theta_d || g[2] != db.grid().n_phi_d)
            return fail("grid " + g.dump() + " is not the database's [" +
                        std::to_string(db.grid().n_theta_h) + "," + std::to_string(db.grid().n_theta_d) +
                        "," + std::to_string(db.grid().n_phi_d) + "]");
        *p = MeasurementPlan();
        parse_plan_method(j.value("method", "greedy"), &p->method);
        p->condition = j.value("condition_number", 0.0);
        if (j.contains("database") && j["database"].contains("excluded"))
            for (const Json& e : j["database"]["excluded"]) {
                const std::string n = e.get<std::string>();
                if (db.find(n) < 0) return fail("excluded material '" + n + "' is not in the database");
                p->excluded.push_back(n);
            }
        const Json& list = j.at("plan");
        if (!list.is_array() || list.empty() || list.size() > size_t(kMaxSamples))
            return fail("plan: expected 1.." + std::to_string(kMaxSamples) + " samples");
        for (size_t i = 0; i < list.size(); ++i) {
            const Json& s = list[i];
            const std::string at = "plan[" + std::to_string(i) + "]";
            if (!s.is_object() || !s.contains("cell") || !s.contains("channel") ||
                !s["cell"].is_number_integer() || !s["channel"].is_number_integer())
                return fail(at + ": expected integer \"cell\" and \"channel\"");
            const int64_t cell = s["cell"].get<int64_t>(), ch = s["channel"].get<int64_t>();
            if (cell < 0 || size_t(cell) >= db.grid().cells() || ch < 0 || ch > 2)
                return fail(at + ": cell " + std::to_string(cell) + " channel " + std::to_string(ch) +
                            " outside the grid (cells 0.." + std::to_string(db.grid().cells() - 1) +
                            ", channels 0..2)");
            const int64_t v = db.valid_index(size_t(cell));
            if (v < 0) return fail(at + ": cell " + std::to_string(cell) + " is below the horizon");
            p->rows.push_back(3 * size_t(v) + size_t(ch));
        }
        const size_t fitted = size_t(db.size()) - p->excluded.size();
        if (p->excluded.size() >= size_t(db.size()) || p->rows.size() < fitted)
            return fail(std::to_string(p->rows.size()) + " samples cannot fit the weights of " +
                        std::to_string(fitted) + " materials (at least as many samples as materials)");
    } catch (const nlohmann::json::exception& ex) {
        std::string what = ex.what();
        const size_t b = what.find("] ");
        return fail(b == std::string::npos ? what : what.substr(b + 2));
    }
    return true;
}

}  // namespace sepal
