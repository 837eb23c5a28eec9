// A plan judged by the picture its reconstructions make (the `picture` plan method,
// measure_plan.h): leave-one-out over the database itself. Each material in use is fitted,
// log model as fit_combination does it (linear_model.h), from the plan's rows by the other
// materials, and drawn beside the material in the default scene (bake/picture.h's first view,
// the sphere under `sepal render`'s light) and in the default light range's single-light
// training conditions (bake/light_range.h: other directions and irradiances, a rim light; never
// its held-out ones); the plan's figure is the mean PSNR over views and materials.
//
// Usage:
//   sepal::PlanPictureScorer s;
//   if (!s.init(db, cols, 32, &err)) ...            // cols: the materials in use; 32 x 32 views
//   double db_mean = s.score(plan_rows);             // higher is better
//
// Why: a plan chosen for the fit's conditioning or its prediction variance treats the misfit
// of a new material as white noise; it is not (docs/measure.md: such plans lose to random ones
// by the picture). Scoring plans on the database's own leave-one-out pictures measures the
// misfit where the picture looks.
// How, cheaply: each view is drawn once by the exact renderer with a recording BRDF, giving
// each lit pixel its direction pair (mapped to the grid cell holding it, where the table's
// lookup interpolates: scored on the default scene alone at 64 x 64, the figure sat about 1 dB
// above the 256 x 256 render's and followed it across plans and materials with correlation
// 0.99) and its irradiance times cos theta_i. A plan's fits all come from one Gram matrix of its log design
// (each material regressed on the others: exactly fit_combination's ridge rule), and each
// picture is K dot products per pixel channel. Cost: a few hundredths of a second per plan for
// 99 materials in 5 views of 32 x 32 on 2 cores (with the ridge weights given), a tenth with
// them chosen. Deterministic (results land in per-material slots).
// Limits: the grid's theta_h is sqrt-spaced (database.h); at least 2 materials in use.
#pragma once
#include <string>
#include <vector>

#include "bake/image_score.h"
#include "database/database.h"

namespace sepal {

class PlanPictureScorer {
  public:
    bool init(const BrdfDatabase& db, const std::vector<int>& cols, int size, std::string* err);
    // Mean over the materials in use of the PSNR (dB) of its leave-one-out reconstruction's
    // picture from these database rows. lambdas (optional, one per material in use): with
    // `reuse`, the ridge weights to use (skipping the eigenvalues that choose them, most of
    // the cost; a swap search refreshes them now and then), else filled with the ones chosen.
    // Not for concurrent calls on one scorer: it keeps the last plan's design rows.
    double score(const std::vector<size_t>& rows, std::vector<double>* lambdas = nullptr, bool reuse = false) const;
    size_t pixels() const { return weight_.size() / 3; }

  private:
    bool add_view(const BakeView& v, int index, std::string* err);

    const BrdfDatabase* db_ = nullptr;
    int views_ = 0;
    std::vector<int> view_;       // per pixel channel: the view it is in
    std::vector<int> cols_;
    int size_ = 0;
    std::vector<double> log_;     // per pixel channel: log(f_k + eps) for k in cols_, then 3 indicators
    std::vector<double> truth_;   // per pixel channel: f_k for k in cols_
    std::vector<double> weight_;  // per pixel channel: irradiance times cos theta_i
    // The last scored plan's rows and their log design rows (K + 3 each).
    mutable std::vector<size_t> design_rows_;
    mutable std::vector<double> design_;
};

}  // namespace sepal
