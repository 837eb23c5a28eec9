// Planning a reduced measurement (Matusik et al. 2003, section 7): which N (direction pair,
// colour channel) samples let the database's linear combination be fitted robustly.
//
// Usage:
//   sepal::PlanOptions o;  o.samples = 800;              // o.method = PlanMethod::kRandom ...
//   sepal::MeasurementPlan plan;
//   if (!sepal::plan_measurement(*db, o, &plan, &err)) ...;
//   std::printf("condition number %.3g\n", plan.condition);
//   sepal::write_plan_json("plan.json", *db, plan, &err);
//
// A sample is a database row: a valid cell of the grid (its bin-centre direction pair, phi_h
// = 0) and one channel (the paper measures R, G or B at each point). The figure of merit is
// the condition number of X^T X, X = the plan's rows of the system the fit solves, columns
// normalised (linear_model.h, plan_condition): the log model's design by default
// (PlanOptions::space), or the paper's, the database's values with every material's column
// scaled to unit norm over the whole grid.
// Methods:
//   picture  (default) of `candidates` random plans (seeds seed, seed + 1, ...), the one whose
//            leave-one-out reconstructions of the database's own materials (each fitted by
//            the others from the plan's rows, log model) draw best, mean PSNR over the
//            default scene and the default light range's single-light training conditions
//            (plan_picture.h); then `picture_swaps` proposals, each a plan row exchanged for
//            a random row, kept when that figure rises. A new material's error is its misfit,
//            the part of it no combination of the database holds; the greedy designs below
//            treat it as white noise and lose to random plans by the picture, while plans
//            differ from one another by the picture in a way that holds across materials (a
//            plan good for half of the database is good for the other half), which this
//            method climbs. docs/measure.md has its figures against random and greedy plans.
//   greedy   the paper's condition-number-driven selection, made fast: a forward
//            pass adds, one at a time, the pool row of largest leverage r^T A^-1 r under the
//            rows chosen so far (A = delta I + X^T X; Sherman-Morrison updates, applied to the
//            whole pool in blocks of 32 rows as one matrix product), then the paper's swap
//            loop exchanges a chosen row for a pool row whenever the exact condition number
//            (eigenvalues of the 100 x 100 X^T X) drops; proposals are ranked by the
//            first-order change of the extreme eigenvalues; it stops after `max_swaps` or
//            when `swap_tries` proposals in a row fail.
//            Candidates come from the database's planning pool (database.h).
//   random   uniform over all rows (valid cells x channels), without repetition (seeded).
//   uniform  evenly strided over the valid cells in grid order, channels in turn.
// Deterministic: the same database, options and seed give the same plan (whatever the thread count).
// Limits: 1 <= samples <= 100000 and at most the rows available.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "database/database.h"
#include "database/linear_model.h"

namespace sepal {

enum class PlanMethod { kGreedy, kRandom, kUniform, kPicture };
// What the greedy method optimises: the mean prediction variance over the planning pool (a
// V-optimal design: samples that pin down the model where the material is looked at), or the
// paper's condition number of X^T X (an extreme-seeking design).
enum class PlanObjective { kPrediction, kCondition };

const char* plan_method_name(PlanMethod m);
bool parse_plan_method(const std::string& s, PlanMethod* m);

struct PlanOptions {
    int samples = 800;
    PlanMethod method = PlanMethod::kPicture;
    uint64_t seed = 1;
    std::vector<uint8_t> use;  // materials taking part (size K), empty: all
    // The model the plan is for (linear_model.h): the log model by default, whose design the
    // greedy pass and the swaps condition; kLinear: the paper's system, rows weighted 1/sigma
    // when `weighted`.
    FitSpace space = FitSpace::kLog;
    PlanObjective objective = PlanObjective::kPrediction;
    bool weighted = true;
    int pool_cells = 8192;     // greedy: candidates from this many pool cells (0: the whole pool)
    int max_swaps = 400;       // greedy: swap iterations at most
    int swap_tries = 24;       // greedy: proposals in a row without a gain before stopping
    int candidates = 32;       // picture: random plans judged (1..1024)
    int picture_swaps = 2000;  // picture: row exchanges proposed after the best candidate
    int picture_size = 32;     // picture: pixels per side of each judged view
    FILE* progress = nullptr;
};

struct MeasurementPlan {
    PlanMethod method = PlanMethod::kPicture;
    uint64_t seed = 1;
    std::vector<size_t> rows;          // database rows: 3 * valid cell + channel
    std::vector<std::string> excluded;  // database materials left out of the model
    double condition = 0;              // of the column-normalised X^T X
    double condition_forward = 0;      // greedy: after the forward pass, before swaps
    int swaps = 0;                     // greedy, picture: accepted swaps
    double picture_db = 0;             // picture: the chosen plan's mean leave-one-out PSNR
};

bool plan_measurement(const BrdfDatabase& db, const PlanOptions& o, MeasurementPlan* plan,
                      std::string* err);

// plan.json: {"format": "sepal-measure-plan", "version": 1, "grid": [nh, nd, np],
// "database": {"materials": K, "excluded": [...]}, "method", "seed", "samples": N,
// "condition_number", "plan": [{"cell", "channel" (0 R, 1 G, 2 B), "theta_h", "theta_d",
// "phi_d" (radians, the bin centre), "theta_i", "phi_i", "theta_o", "phi_o" (degrees: the
// instrument setting, phi_h = 0)}, ...]}.
bool write_plan_json(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& p,
                     std::string* err);
// Reads a plan back against a database (grid must match; cells must be valid; names of
// excluded materials must exist). Bounded: at most 100000 samples, file <= 64 MiB.
bool read_plan_json(const std::string& path, const BrdfDatabase& db, MeasurementPlan* p,
                    std::string* err);

// The instrument directions of a database row's cell (bin centre, phi_h = 0).
void plan_row_directions(const BrdfDatabase& db, size_t row, glm::dvec3* wi, glm::dvec3* wo);

}  // namespace sepal
