#include "acquire/session.h"

#include <chrono>

#include "util/parallel.h"

namespace sepal {

const char* strategy_name(Strategy s) {
    switch (s) {
        case Strategy::kPlanner: return "planner";
        case Strategy::kRandom: return "random";
        case Strategy::kExpert: return "expert";
    }
    return "?";
}

bool parse_strategy(const std::string& name, Strategy* out) {
    for (Strategy s : {Strategy::kPlanner, Strategy::kRandom, Strategy::kExpert})
        if (name == strategy_name(s)) {
            *out = s;
            return true;
        }
    return false;
}

bool run_session(const AcqObject& obj, const BlendSvbrdf& truth, const SessionOptions& o, Session* out,
                 std::string* err, const std::function<void(const Session&)>& on_view) {
    if (o.views < 1 || o.views > 1000) {
        if (err) *err = "session: views must be 1..1000";
        return false;
    }
    Session s;
    init_plan_state(obj, o.planner, &s.state);
    for (int k = 0; k < o.views; ++k) {
        SessionStep step;
        switch (o.strategy) {
            case Strategy::kPlanner: step.view = plan_next_view(obj, o.rig, o.planner, k, s.state, &step.plan); break;
            case Strategy::kRandom: step.view = random_view(o.rig, o.seed, k); break;
            case Strategy::kExpert: step.view = expert_view(k, o.expert_per_lap); break;
        }
        Capture c;
        capture_atlas(obj, truth, step.view, o.rig, splitmix64(o.seed) + uint64_t(k), &c);
        step.samples = int(c.size());
        s.captures.push_back(std::move(c));
        const auto t0 = std::chrono::steady_clock::now();
        if ((k + 1) % std::max(1, o.refit_every) == 0) {
            Reconstruction r;
            std::string e;
            ReconstructOptions ro = o.estimates;
            ro.threads = o.planner.threads;
            if (reconstruct(obj, s.captures, ro, &r, &e)) set_estimates(r.texel_model, &s.state);
        }
        accumulate(s.captures, o.rig, &s.state, o.planner.threads);
        step.refit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        step.summary = summarize(s.state);
        s.steps.push_back(step);
        if (on_view) on_view(s);
    }
    *out = std::move(s);
    return true;
}

}  // namespace sepal
