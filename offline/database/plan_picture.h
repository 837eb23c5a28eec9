// A plan judged by the picture its reconstructions make (the `picture` plan method,
// measure_plan.h): leave-one-out over the database itself. Each material in use is fitted,
// log model as fit_combination does it (linear_model.h), from the plan's rows by the other
// materials, and drawn in the default scene (bake/picture.h's first view, the sphere under
// `sepal render`'s light) beside the material; the plan's figure is the mean PSNR over them.
//
// Usage:
//   sepal::PlanPictureScorer s;
//   if (!s.init(db, cols, 64, &err)) ...            // cols: the materials in use
//   double db_mean = s.score(plan_rows);             // higher is better
//
// Why: a plan chosen for the fit's conditioning or its prediction variance treats the misfit
// of a new material as white noise; it is not (docs/measure.md: such plans lose to random ones
// by the picture). Scoring plans on the database's own leave-one-out pictures measures the
// misfit where the picture looks.
// How, cheaply: the scene is drawn once by the exact renderer with a recording BRDF, giving
// each lit pixel its direction pair (mapped to the grid cell holding it; the table's lookup
// interpolates, so the figure is within a few tenths of a dB of a rendered one) and its
// irradiance times cos theta_i. A plan's fits all come from one Gram matrix of its log design
// (each material regressed on the others: exactly fit_combination's ridge rule), and each
// picture is K dot products per pixel channel. Cost: about 0.1 s per plan for 99 materials at
// 64 x 64 on 2 cores. Deterministic (results land in per-material slots).
// Limits: the grid's theta_h is sqrt-spaced (database.h); at least 2 materials in use.
#pragma once
#include <string>
#include <vector>

#include "database/database.h"

namespace sepal {

class PlanPictureScorer {
  public:
    bool init(const BrdfDatabase& db, const std::vector<int>& cols, int size, std::string* err);
    // Mean over the materials in use of the PSNR (dB) of its leave-one-out reconstruction's
    // picture from these database rows.
    double score(const std::vector<size_t>& rows) const;
    size_t pixels() const { return weight_.size() / 3; }

  private:
    const BrdfDatabase* db_ = nullptr;
    std::vector<int> cols_;
    int size_ = 0;
    std::vector<double> log_;     // per pixel channel: log(f_k + eps) for k in cols_, then 3 indicators
    std::vector<double> truth_;   // per pixel channel: f_k for k in cols_
    std::vector<double> weight_;  // per pixel channel: irradiance times cos theta_i
};

}  // namespace sepal
