#include "database/plan_picture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>

#include <Eigen/Core>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "bake/light_range.h"
#include "bake/picture.h"
#include "brdf/brdf.h"
#include "database/linear_model.h"
#include "measured/tabulated.h"
#include "reference/render_exact.h"
#include "util/parallel.h"

namespace sepal {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// f = 1: the picture of this BRDF is each pixel's irradiance times cos theta_i.
class UnitBrdf : public Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3&, const glm::dvec3&) const override { return glm::dvec3(1.0); }
    std::string spec() const override { return "unit"; }
    std::string model() const override { return "unit"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return true; }
};

// Returns the call's number (1, 2, ...) and keeps its directions: over the unit picture, a
// pixel's value names the pair it was shaded with (one light, one sample per pixel).
class RecordingBrdf : public Brdf {
  public:
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        std::lock_guard<std::mutex> lock(mutex_);
        calls_.push_back({wi, wo});
        return glm::dvec3(double(calls_.size()));
    }
    std::string spec() const override { return "recording"; }
    std::string model() const override { return "recording"; }
    std::string info() const override { return ""; }
    bool isotropic() const override { return true; }
    const std::vector<std::pair<glm::dvec3, glm::dvec3>>& calls() const { return calls_; }

  private:
    mutable std::mutex mutex_;
    mutable std::vector<std::pair<glm::dvec3, glm::dvec3>> calls_;
};


}  // namespace

bool PlanPictureScorer::init(const BrdfDatabase& db, const std::vector<int>& cols, int size, std::string* err) {
    db_ = &db;
    cols_ = cols;
    size_ = size;
    if (cols.size() < 2 || size < 8 || size > 512) {
        if (err) *err = "plan: the picture score needs at least 2 materials and a size in 8..512";
        return false;
    }
    log_.clear(), truth_.clear(), weight_.clear(), view_.clear();
    // The default scene, then the light range's single-light training conditions (other
    // directions and irradiances, a rim light): scored on one view alone, a plan gathers its
    // rows where that view looks and the held-out conditions lose what it gained.
    std::vector<BakeView> views, training;
    if (!picture_views(&views, err)) return false;
    views.resize(1);
    std::vector<LightCondition> single;
    for (const LightCondition& c : training_conditions(LightRange{}))
        if (c.lights.size() == 1) single.push_back(c);
    if (!condition_views(single, &training, err)) return false;
    views.insert(views.end(), training.begin(), training.end());
    views_ = int(views.size());
    for (int vi = 0; vi < views_; ++vi)
        if (!add_view(views[size_t(vi)], vi, err)) return false;
    if (weight_.empty()) {
        if (err) *err = "plan: the judged views show no lit pixel of the database's grid";
        return false;
    }
    return true;
}

// The view's lit pixels: their grid cells' values and irradiance times cos theta_i.
bool PlanPictureScorer::add_view(const BakeView& v, int index, std::string* err) {
    const BrdfDatabase& db = *db_;
    UnitBrdf unit;
    RecordingBrdf rec;
    Image w, id;
    if (!render_exact(unit, v.scene, v.mesh(), size_, size_, &w, nullptr, err) ||
        !render_exact(rec, v.scene, v.mesh(), size_, size_, &id, nullptr, err))
        return false;
    const size_t K = cols_.size(), P = size_t(size_) * size_t(size_);
    for (size_t p = 0; p < P; ++p) {
        const double irr = w.data[3 * p];
        if (!(irr > 1e-9)) continue;
        const double q = double(id.data[3 * p]) / irr, call = std::round(q);
        // Not one call's number: the pixel was shaded more than once (not reached with one
        // light and one sample); it is left out of the figure.
        if (std::fabs(q - call) > 0.01 || call < 1.0 || call > double(rec.calls().size())) continue;
        const auto& pair = rec.calls()[size_t(call) - 1];
        const DatabaseGrid& g = db.grid();
        const int64_t cell = db.valid_index(table_cell_index(g.n_theta_h, g.n_theta_d, g.n_phi_d, ThetaHMapping::kSqrt,
                                                             to_half_diff(pair.first, pair.second)));
        if (cell < 0) continue;
        for (size_t ch = 0; ch < 3; ++ch) {
            const size_t row = 3 * size_t(cell) + ch;
            for (size_t k = 0; k < K; ++k) {
                const double f = db.value(cols_[k], row);
                truth_.push_back(f);
                log_.push_back(std::log(std::max(f, 0.0) + kDatabaseLogEps));
            }
            for (size_t c = 0; c < 3; ++c) log_.push_back(c == ch ? 1.0 : 0.0);
            weight_.push_back(irr);
            view_.push_back(index);
        }
    }
    return true;
}

double PlanPictureScorer::score(const std::vector<size_t>& rows, std::vector<double>* lambdas, bool reuse) const {
    const BrdfDatabase& db = *db_;
    const Index K = Index(cols_.size()), D = K + 3;
    // The log design of the plan's rows (fit_combination's, weighted by cos theta_i) and its
    // Gram. Rows the last call had at the same place are kept: a swap search changes one per
    // call, and each new one reads K values scattered over the table.
    if (design_rows_.size() != rows.size()) {
        design_rows_.assign(rows.size(), SIZE_MAX);
        design_.assign(rows.size() * size_t(D), 0.0);
    }
    std::vector<float> values(static_cast<size_t>(db.size()));
    for (size_t i = 0; i < rows.size(); ++i) {
        if (design_rows_[i] == rows[i]) continue;
        for (int k = 0; k < db.size(); ++k) values[size_t(k)] = db.value(k, rows[i]);
        log_design_row(db, rows[i], values.data(), cols_, &design_[i * size_t(D)]);
        design_rows_[i] = rows[i];
    }
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> X(
        design_.data(), Index(rows.size()), D);
    const MatrixXd A = X.transpose() * X;
    const double max_condition = FitOptions{}.max_condition;
    const size_t PC = weight_.size();
    const double pixels = double(size_) * double(size_) * 3.0;
    std::vector<double> psnr(static_cast<size_t>(K));
    if (lambdas) lambdas->resize(size_t(K), 0.0);
    parallel_for(size_t(K), 0, [&](size_t j) {
        // Material j from the others: the normal equations without its row and column,
        // columns normalised, ridge as fit_combination_log.
        std::vector<Index> C;
        for (Index c = 0; c < D; ++c)
            if (c != Index(j)) C.push_back(c);
        const Index n = Index(C.size());
        MatrixXd B(n, n);
        VectorXd g(n), s(n);
        for (Index a = 0; a < n; ++a) s(a) = A(C[a], C[a]) > 0.0 ? 1.0 / std::sqrt(A(C[a], C[a])) : 0.0;
        for (Index a = 0; a < n; ++a) {
            g(a) = A(C[a], Index(j)) * s(a);
            for (Index b = 0; b < n; ++b) B(a, b) = A(C[a], C[b]) * s(a) * s(b);
        }
        double lambda = 0.0;
        if (lambdas && reuse) {
            lambda = (*lambdas)[j];
        } else {
            Eigen::SelfAdjointEigenSolver<MatrixXd> es(B, Eigen::EigenvaluesOnly);
            lambda = ridge_for_condition(es.eigenvalues()(0), es.eigenvalues()(n - 1), max_condition);
            if (lambdas) (*lambdas)[j] = lambda;
        }
        B.diagonal().array() += lambda;
        const VectorXd c = B.ldlt().solve(g);
        std::vector<double> coef(static_cast<size_t>(D), 0.0);
        for (Index a = 0; a < n; ++a) coef[size_t(C[a])] = c(a) * s(a);
        std::vector<double> se(size_t(views_), 0.0);
        for (size_t i = 0; i < PC; ++i) {
            const double* l = &log_[i * size_t(D)];
            double e = 0.0;
            for (Index k = 0; k < D; ++k) e += coef[size_t(k)] * l[k];
            const double f = std::exp(std::min(e, 700.0)) - kDatabaseLogEps;
            const double d = std::clamp(f * weight_[i], 0.0, 1.0) - std::min(truth_[i * size_t(K) + j] * weight_[i], 1.0);
            se[size_t(view_[i])] += d * d;
        }
        double sum = 0.0;
        for (double e : se) sum += -10.0 * std::log10(std::max(e / pixels, 1e-12));
        psnr[j] = sum / double(views_);
    });
    double sum = 0.0;
    for (double x : psnr) sum += x;
    return sum / double(K);
}

}  // namespace sepal
