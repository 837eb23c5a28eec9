#include "acquire/planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/glm.hpp>

#include "util/parallel.h"

namespace sepal {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int L = kPlanParams;
// Chunks of texels per evaluation: fixed, so sums do not depend on the thread count.
constexpr size_t kChunks = 64;

inline int up(int i, int j) {  // index into a 4x4 upper triangle, i <= j
    static const int t[4][4] = {{0, 1, 2, 3}, {1, 4, 5, 6}, {2, 5, 7, 8}, {3, 6, 8, 9}};
    return t[i][j];
}

// U(H) from the eigenvalues (planner.h).
struct Spectrum {
    int rank;
    double cov_norm, largest_cov;
};

Spectrum spectrum(const double lambda[4], double threshold) {
    Spectrum s{0, 0, 0};
    double sum = 0, smallest = 0;
    for (int i = 0; i < L; ++i)
        if (lambda[i] > threshold) {
            ++s.rank;
            sum += 1.0 / (lambda[i] * lambda[i]);
            smallest = smallest == 0 ? lambda[i] : std::min(smallest, lambda[i]);
        }
    s.cov_norm = std::sqrt(sum);
    s.largest_cov = smallest > 0 ? 1.0 / smallest : 0.0;
    return s;
}

double rank_penalty(int rank, double base, double inf) {
    double u = 0, step = 1;
    for (int j = L - 1; j >= rank; --j) {  // the step from j to j+1 is worth inf * base^(L-1-j)
        u += step;
        step *= base;
    }
    return inf * u;
}

// The relative scale of each parameter of an estimate.
void param_scale(const LafortuneModel& m, double s[4]) {
    s[0] = std::max(std::fabs(m.rho_d.x), 0.01);
    s[1] = std::max(std::fabs(m.lobes[0].cx), 0.01);
    s[2] = std::max(std::fabs(m.lobes[0].cz), 0.01);
    s[3] = std::max(m.lobes[0].n, 1.0);
}

void relative_gradient(const LafortuneModel& m, const glm::dvec3& wi, const glm::dvec3& wo, double g[4]) {
    lafortune_gradient_grey_iso(m, wi, wo, g);
    double s[4];
    param_scale(m, s);
    for (int j = 0; j < L; ++j) g[j] *= s[j];
}

glm::dvec3 fibonacci(int i, int n) {
    const double z = 1 - (2.0 * i + 1) / n, r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = i * kPi * (3 - std::sqrt(5.0));
    return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
}

// A uniformly random rotation (a normalized quaternion of four Gaussians).
glm::dmat3 random_rotation(uint64_t seed) {
    double q[4];
    for (int i = 0; i < 4; ++i) q[i] = counter_gauss(seed, uint64_t(i));
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    return glm::dmat3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y),  //
                      2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x),  //
                      2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
}

glm::dvec3 uniform_dir(uint64_t seed, uint64_t i) {
    const double z = 1 - 2 * counter_uniform(seed, 2 * i), phi = 2 * kPi * counter_uniform(seed, 2 * i + 1);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
}

void tangent_basis(const glm::dvec3& n, glm::dvec3* t, glm::dvec3* b) {
    *t = glm::normalize(glm::cross(n, std::fabs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
    *b = glm::cross(n, *t);
}

}  // namespace

void sym4_eigen(const double a[10], double lambda[4], double* V) {
    double A[4][4], v[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) A[i][j] = a[up(std::min(i, j), std::max(i, j))];
    double scale = 0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, std::fabs(A[i][i]));
    for (int sweep = 0; sweep < 12; ++sweep) {
        double off = 0;
        for (int p = 0; p < 3; ++p)
            for (int q = p + 1; q < 4; ++q) off = std::max(off, std::fabs(A[p][q]));
        if (!(off > 1e-15 * scale)) break;
        for (int p = 0; p < 3; ++p)
            for (int q = p + 1; q < 4; ++q) {
                if (!(std::fabs(A[p][q]) > 1e-300)) continue;
                const double theta = (A[q][q] - A[p][p]) / (2 * A[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 4; ++k) {  // A <- A J (columns p, q)
                    const double akp = A[k][p], akq = A[k][q];
                    A[k][p] = c * akp - s * akq;
                    A[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 4; ++k) {  // A <- J^T A (rows p, q)
                    const double apk = A[p][k], aqk = A[q][k];
                    A[p][k] = c * apk - s * aqk;
                    A[q][k] = s * apk + c * aqk;
                }
                if (V)
                    for (int k = 0; k < 4; ++k) {
                        const double vkp = v[k][p], vkq = v[k][q];
                        v[k][p] = c * vkp - s * vkq;
                        v[k][q] = s * vkp + c * vkq;
                    }
            }
    }
    int order[4] = {0, 1, 2, 3};
    std::sort(order, order + 4, [&](int x, int y) { return A[x][x] < A[y][y]; });
    for (int i = 0; i < 4; ++i) {
        lambda[i] = A[order[i]][order[i]];
        if (V)
            for (int k = 0; k < 4; ++k) V[k * 4 + i] = v[k][order[i]];
    }
}

LafortuneModel plan_prior() {
    LafortuneModel m;
    m.rho_d = glm::dvec3(0.3);
    m.lobes.push_back({-0.8, -0.8, 0.8, 10});
    return m;
}

void init_plan_state(const AcqObject& obj, const PlannerOptions& o, PlanState* st) {
    PlanState s;
    s.texels = obj.atlas.texels;
    s.estimate.assign(s.texels.size(), plan_prior());
    s.H.assign(s.texels.size() * 10, 0.0);
    s.index_of.assign(obj.atlas.valid.size(), -1);
    for (size_t e = 0; e < s.texels.size(); ++e) s.index_of[size_t(s.texels[e])] = int(e);
    s.threshold = o.rank_threshold;
    s.base = o.rank_base;
    s.inf = o.inf;
    *st = std::move(s);
    prepare_plan_state(st, o.threads);
}

void set_estimates(const std::vector<LafortuneModel>& per_texel, PlanState* st) {
    for (size_t e = 0; e < st->texels.size(); ++e) {
        const LafortuneModel& m = per_texel[size_t(st->texels[e])];
        if (m.lobes.empty()) continue;
        LafortuneModel g;
        g.rho_d = glm::dvec3(luminance(m.rho_d));
        g.lobes.push_back(m.lobes[0]);
        g.lobes[0].cy = g.lobes[0].cx;
        st->estimate[e] = g;
    }
}

void accumulate(const std::vector<Capture>& captures, const RigOptions& rig, PlanState* st, int threads) {
    (void)rig;
    std::fill(st->H.begin(), st->H.end(), 0.0);
    // Each chunk owns a contiguous range of entries; captures are walked in order.
    const size_t n = st->texels.size();
    parallel_for(kChunks, threads, [&](size_t chunk) {
        const size_t begin = n * chunk / kChunks, end = n * (chunk + 1) / kChunks;
        for (const Capture& c : captures)
            for (size_t i = 0; i < c.size(); ++i) {
                const int e = st->index_of[size_t(c.texel[i])];
                if (e < int(begin) || e >= int(end)) continue;
                double g[4];
                relative_gradient(st->estimate[size_t(e)], glm::dvec3(c.wi[i]), glm::dvec3(c.wo[i]), g);
                double* H = &st->H[size_t(e) * 10];
                const double w2 = double(c.weight[i]) * c.weight[i];
                for (int a = 0; a < L; ++a)
                    for (int b = a; b < L; ++b) H[up(a, b)] += w2 * g[a] * g[b];
            }
    });
    prepare_plan_state(st, threads);
}

void prepare_plan_state(PlanState* st, int threads) {
    const size_t n = st->texels.size();
    st->eigval.assign(n * 4, 0.0);
    st->eigvec.assign(n * 16, 0.0);
    st->rank.assign(n, 0);
    st->cov_norm.assign(n, 0.0);
    st->uncertainty.assign(n, 0.0);
    st->smallest.assign(n, 0.0);
    parallel_for(kChunks, threads, [&](size_t chunk) {
        for (size_t e = n * chunk / kChunks; e < n * (chunk + 1) / kChunks; ++e) {
            double* lambda = &st->eigval[e * 4];
            sym4_eigen(&st->H[e * 10], lambda, &st->eigvec[e * 16]);
            const Spectrum s = spectrum(lambda, st->threshold);
            st->rank[e] = s.rank;
            st->cov_norm[e] = s.cov_norm;
            st->smallest[e] = s.largest_cov;
            st->uncertainty[e] = rank_penalty(s.rank, st->base, st->inf) + s.cov_norm;
        }
    });
}

bool predicted_row(const PlanState& st, int e, const glm::vec3& wi, const glm::vec3& wo, double E,
                   const RigOptions& rig, double row[4]) {
    const LafortuneModel& m = st.estimate[size_t(e)];
    const glm::dvec3 di(wi), dout(wo);
    const double f = m.rho_d.x / kPi + m.lobe_sum(di, dout);
    const double w = wo.z * E / radiance_std(rig, f * E);
    relative_gradient(m, di, dout, row);
    for (int j = 0; j < L; ++j) row[j] *= w;
    return true;
}

double view_gain(const PlanState& st, const PointView& cam, const PointView& light, double intensity,
                 const RigOptions& rig, size_t begin, size_t end) {
    const float cos_max = float(std::cos(rig.max_angle_deg * kPi / 180));
    double gain = 0;
    for (size_t e = begin; e < end; ++e) {
        const size_t t = size_t(st.texels[e]);
        if (!cam.ok[t] || !light.ok[t]) continue;
        const glm::vec3& wo = cam.local[t];
        const glm::vec3& wi = light.local[t];
        if (wo.z < cos_max || wi.z < cos_max) continue;
        double r[4];
        predicted_row(st, int(e), wi, wo, intensity * wi.z / light.dist2[t], rig, r);
        const double* V = &st.eigvec[e * 16];
        const double* d = &st.eigval[e * 4];
        double z[4];
        for (int i = 0; i < L; ++i) z[i] = V[0 * 4 + i] * r[0] + V[1 * 4 + i] * r[1] + V[2 * 4 + i] * r[2] + V[3 * 4 + i] * r[3];
        // Rank after the update: inertia of D + z z^T - threshold (see the header).
        const double tau = st.threshold;
        int measured = 0;
        double secular = 1;
        bool singular = false;
        for (int i = 0; i < L; ++i) {
            if (d[i] > tau) ++measured;
            const double diff = d[i] - tau;
            if (diff == 0) singular = true;
            else secular += z[i] * z[i] / diff;
        }
        const bool gains_rank = measured < L && (singular || secular < 0);
        // ||CoV||_F^2 on the measured block by Sherman-Morrison with C = D^-1 there.
        double den = 1, uu = 0, uCu = 0, sum = 0;
        int top_unmeasured = -1;
        for (int i = 0; i < L; ++i) {
            if (!(d[i] > tau)) {
                top_unmeasured = i;
                continue;
            }
            const double u = z[i] / d[i];
            den += z[i] * u;
            uu += u * u;
            uCu += u * u / d[i];
            sum += 1 / (d[i] * d[i]);
        }
        double n1sq = sum - 2 * uCu / den + uu * uu / (den * den);
        int rank = measured;
        if (gains_rank) {
            ++rank;
            const double dn = std::max(tau, d[top_unmeasured] + z[top_unmeasured] * z[top_unmeasured]);
            n1sq += 1 / (dn * dn);
        }
        const double after = rank_penalty(rank, st.base, st.inf) + std::sqrt(std::max(0.0, n1sq));
        gain += st.uncertainty[e] - after;
    }
    return gain;
}

ViewPair plan_next_view(const AcqObject& obj, const RigOptions& rig, const PlannerOptions& o, int step,
                        const PlanState& st, PlanStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    PlanStats ps;
    const int N = std::max(4, o.sphere_points);
    const glm::dmat3 R = random_rotation(splitmix64(o.seed) ^ (uint64_t(step) * 0x9e3779b97f4a7c15ULL));
    std::vector<glm::dvec3> dirs(static_cast<size_t>(N));
    for (int i = 0; i < N; ++i) dirs[size_t(i)] = R * fibonacci(i, N);
    const double intensity = light_intensity(obj, rig);
    const bool shared = rig.camera_distance == rig.light_distance;
    std::vector<PointView> cams(static_cast<size_t>(N)), lights(shared ? 0 : size_t(N));
    parallel_for(size_t(N), o.threads, [&](size_t i) {
        view_from_point(obj, dirs[i] * (rig.camera_distance * obj.radius), rig.depth_res, &cams[i]);
        if (!shared) view_from_point(obj, dirs[i] * (rig.light_distance * obj.radius), rig.depth_res, &lights[i]);
    });
    const std::vector<PointView>& lv = shared ? cams : lights;
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j)
            if (i != j && separation_deg({dirs[size_t(i)], dirs[size_t(j)]}) >= rig.min_separation_deg)
                pairs.push_back({i, j});
    std::vector<double> gains(pairs.size(), 0.0);
    parallel_for(pairs.size(), o.threads, [&](size_t p) {
        gains[p] = view_gain(st, cams[size_t(pairs[p].first)], lv[size_t(pairs[p].second)], intensity, rig, 0,
                             st.texels.size());
    });
    ps.evaluations = int(pairs.size());
    size_t best = 0;
    for (size_t p = 1; p < pairs.size(); ++p)
        if (gains[p] > gains[best]) best = p;
    ViewPair v{dirs[size_t(pairs[best].first)], dirs[size_t(pairs[best].second)]};
    ps.discrete_best = ps.objective = pairs.empty() ? 0.0 : gains[best];

    // Nelder-Mead in the tangent planes of the two positions (minimizing -gain).
    if (o.refine_evaluations > 0 && !pairs.empty()) {
        glm::dvec3 ct, cb, lt, lb;
        tangent_basis(v.camera, &ct, &cb);
        tangent_basis(v.light, &lt, &lb);
        const ViewPair v0 = v;
        auto at = [&](const double x[4]) {
            return ViewPair{glm::normalize(v0.camera + x[0] * ct + x[1] * cb),
                            glm::normalize(v0.light + x[2] * lt + x[3] * lb)};
        };
        int evals = 0;
        auto f = [&](const double x[4]) {
            ++evals;
            const ViewPair w = at(x);
            if (separation_deg(w) < rig.min_separation_deg) return 0.0;
            PointView c, l;
            view_from_point(obj, camera_position(obj, w, rig), rig.depth_res, &c);
            view_from_point(obj, light_position(obj, w, rig), rig.depth_res, &l);
            std::vector<double> part(kChunks, 0.0);
            const size_t n = st.texels.size();
            parallel_for(kChunks, o.threads, [&](size_t k) {
                part[k] = view_gain(st, c, l, intensity, rig, n * k / kChunks, n * (k + 1) / kChunks);
            });
            double g = 0;
            for (double v_part : part) g += v_part;
            return -g;
        };
        const double h = 0.5 * std::sqrt(4 * kPi / N);
        double X[5][4] = {};
        double F[5];
        F[0] = -ps.discrete_best;
        for (int i = 1; i < 5; ++i) {
            X[i][i - 1] = h;
            F[i] = f(X[i]);
        }
        while (evals < o.refine_evaluations) {
            int idx[5] = {0, 1, 2, 3, 4};
            std::sort(idx, idx + 5, [&](int a, int b) { return F[a] < F[b]; });
            const int worst = idx[4], second = idx[3], bestv = idx[0];
            double c[4] = {0, 0, 0, 0};
            for (int i = 0; i < 4; ++i)
                for (int k = 0; k < 4; ++k) c[k] += X[idx[i]][k] / 4;
            auto point = [&](double t, double* out) {
                for (int k = 0; k < 4; ++k) out[k] = c[k] + t * (X[worst][k] - c[k]);
            };
            double xr[4], xe[4], xc[4];
            point(-1, xr);
            const double fr = f(xr);
            if (fr < F[bestv]) {
                point(-2, xe);
                const double fe = f(xe);
                if (fe < fr) {
                    std::copy(xe, xe + 4, X[worst]);
                    F[worst] = fe;
                } else {
                    std::copy(xr, xr + 4, X[worst]);
                    F[worst] = fr;
                }
            } else if (fr < F[second]) {
                std::copy(xr, xr + 4, X[worst]);
                F[worst] = fr;
            } else {
                point(fr < F[worst] ? -0.5 : 0.5, xc);
                const double fc = f(xc);
                if (fc < std::min(fr, F[worst])) {
                    std::copy(xc, xc + 4, X[worst]);
                    F[worst] = fc;
                } else {  // shrink towards the best
                    for (int i = 0; i < 5; ++i) {
                        if (i == bestv) continue;
                        for (int k = 0; k < 4; ++k) X[i][k] = X[bestv][k] + 0.5 * (X[i][k] - X[bestv][k]);
                        F[i] = f(X[i]);
                    }
                }
            }
        }
        int bi = 0;
        for (int i = 1; i < 5; ++i)
            if (F[i] < F[bi]) bi = i;
        if (-F[bi] > ps.objective) {
            ps.objective = -F[bi];
            v = at(X[bi]);
        }
        ps.evaluations += evals;
    }
    ps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (stats) *stats = ps;
    return v;
}

ViewPair random_view(const RigOptions& rig, uint64_t seed, int step) {
    const uint64_t s = splitmix64(seed ^ 0x5eed) + uint64_t(step);
    for (uint64_t i = 0;; i += 2) {
        const ViewPair v{uniform_dir(s, i), uniform_dir(s, i + 1)};
        if (separation_deg(v) >= rig.min_separation_deg) return v;
    }
}

ViewPair expert_view(int step, int per_lap) {
    per_lap = std::max(1, per_lap);
    const int lap = step / per_lap, i = step % per_lap;
    const double az = 360.0 * (i + 0.5 * (lap % 2)) / per_lap;
    const double side = (step % 2) ? 40.0 : -40.0;
    return view_from_angles(az, 20, az + side, 50);
}

UncertaintySummary summarize(const PlanState& st) {
    UncertaintySummary u;
    u.texels = int(st.texels.size());
    double log_sum = 0;
    for (size_t e = 0; e < st.texels.size(); ++e) {
        const int k = st.rank[e];
        ++u.by_rank[k];
        u.mean_largest_cov[k] += st.smallest[e];
        u.total_uncertainty += st.uncertainty[e];
        if (k == L) log_sum += std::log10(std::max(st.cov_norm[e], 1e-300));
        double f2 = 0;
        for (int i = 0; i < L; ++i) {
            const double l = std::max(0.0, st.eigval[e * 4 + size_t(i)]) + st.threshold;
            f2 += 1 / (l * l);
        }
        u.mean_log_cov_all += 0.5 * std::log10(f2);
    }
    if (u.texels) u.mean_log_cov_all /= u.texels;
    for (int k = 0; k <= L; ++k)
        if (u.by_rank[k]) u.mean_largest_cov[k] /= u.by_rank[k];
    u.full_rank_share = u.texels ? double(u.by_rank[L]) / u.texels : 0;
    u.mean_log_cov_full = u.by_rank[L] ? log_sum / u.by_rank[L] : 0;
    return u;
}

}  // namespace sepal
