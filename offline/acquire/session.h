// An acquisition session: capture a known object view by view, choosing each view by the
// planner or a baseline, and keep the uncertainty after every view (the loop of Lensch et al.
// 2003, Fig. 2: plan, capture, resample, update the estimates, plan again).
//
// Usage:
//   sepal::SessionOptions o;  o.strategy = sepal::Strategy::kPlanner;  o.views = 20;
//   sepal::Session s; std::string err;
//   sepal::run_session(obj, truth, o, &s, &err, [](const sepal::Session& s) { ...progress... });
//   s.steps[k].summary   // ranks and ||CoV|| after k + 1 views
//
// After each capture the estimates are refreshed every `refit_every` views: clusters and
// their Lafortune fits (reconstruct.h with the planning options: few samples per cluster,
// one refinement), each texel taking its cluster's model; then every texel's Hessian is
// rebuilt from all captures at the new estimates (planner.h). The same happens for the
// baselines, so their uncertainty is measured exactly like the planner's.
// Deterministic: a capture's noise seed is (seed, view index).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "acquire/capture.h"
#include "acquire/planner.h"
#include "acquire/reconstruct.h"

namespace sepal {

enum class Strategy { kPlanner, kRandom, kExpert };
const char* strategy_name(Strategy s);
bool parse_strategy(const std::string& name, Strategy* out);

struct SessionOptions {
    Strategy strategy = Strategy::kPlanner;
    int views = 20;
    RigOptions rig;
    PlannerOptions planner;
    ReconstructOptions estimates = planning_estimates();
    int refit_every = 1;
    int expert_per_lap = 9;
    uint64_t seed = 1;
    static ReconstructOptions planning_estimates() {
        ReconstructOptions r;
        r.iterations = 1;
        r.max_cluster_samples = 4000;
        r.project = false;
        // The planner's Hessians are of one lobe; choosing among one-lobe fits by held-out
        // views moved its path and lost 10 dB on the sphere (sepal-bench-acquire).
        r.choose_fit = false;
        return r;
    }
};

struct SessionStep {
    ViewPair view;
    int samples = 0;        // in this capture
    PlanStats plan;         // the planner's step (zero for baselines)
    double refit_seconds = 0;
    UncertaintySummary summary;  // after this view
};

struct Session {
    std::vector<Capture> captures;
    std::vector<SessionStep> steps;
    PlanState state;
};

// The reference estimates strategies are compared at: per atlas texel, a Lafortune fit
// (grey, one isotropic lobe) of the truth's dominant material there, each material fitted
// once to 4000 noise-free samples (half near the mirror direction). Measuring every
// strategy's views at the same parameters makes their ranks and ||CoV|| comparable and
// monotone in the number of views (a session's own estimates move as it learns).
bool oracle_estimates(const AcqObject& obj, const BlendSvbrdf& truth, std::vector<LafortuneModel>* out,
                      std::string* err);
// The plan state of the first `views` captures at fixed estimates (per atlas texel).
void evaluate_views(const AcqObject& obj, const std::vector<Capture>& captures, int views,
                    const std::vector<LafortuneModel>& estimates, const PlannerOptions& planner,
                    const RigOptions& rig, PlanState* out);

bool run_session(const AcqObject& obj, const BlendSvbrdf& truth, const SessionOptions& options, Session* out,
                 std::string* err, const std::function<void(const Session&)>& on_view = nullptr);

}  // namespace sepal
