#include "acquire/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/glm.hpp>

#include "util/enum_names.h"
#include "util/parallel.h"

namespace sepal {

constexpr EnumName<Strategy> kStrategies[] = {{Strategy::kPlanner, "planner"}, {Strategy::kRandom, "random"}, {Strategy::kExpert, "expert"}};

const char* strategy_name(Strategy s) { return enum_name(kStrategies, s); }

bool parse_strategy(const std::string& name, Strategy* out) { return parse_enum(kStrategies, name, out); }

bool oracle_estimates(const AcqObject& obj, const BlendSvbrdf& truth, std::vector<LafortuneModel>* out,
                      std::string* err) {
    const int K = truth.materials();
    std::vector<LafortuneModel> fits(static_cast<size_t>(K));
    for (int k = 0; k < K; ++k) {
        std::vector<BrdfSample> s;
        for (uint64_t i = 0; s.size() < 4000; ++i) {
            const double u1 = counter_uniform(77, 4 * i), u2 = counter_uniform(77, 4 * i + 1);
            const double u3 = counter_uniform(77, 4 * i + 2), u4 = counter_uniform(77, 4 * i + 3);
            BrdfSample x;
            const double r = std::sqrt(u1), phi = 2 * 3.14159265358979323846 * u2;
            x.wi = glm::dvec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - u1)));
            const glm::dvec3 m(-x.wi.x, -x.wi.y, x.wi.z);
            const double r2 = std::sqrt(u3) * (i % 2 ? 1.0 : 0.5), phi2 = 2 * 3.14159265358979323846 * u4;
            // Odd samples anywhere; even ones within 30 degrees of the mirror direction.
            const glm::dvec3 t = glm::normalize(glm::cross(m, std::fabs(m.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
            const glm::dvec3 b = glm::cross(m, t);
            x.wo = i % 2 ? glm::dvec3(r2 * std::cos(phi2), r2 * std::sin(phi2), std::sqrt(std::max(0.0, 1 - r2 * r2)))
                         : glm::normalize(m + r2 * (std::cos(phi2) * t + std::sin(phi2) * b));
            if (x.wo.z <= 0.02 || x.wi.z <= 0.02) continue;
            x.value = truth.basis[size_t(k)]->eval(x.wi, x.wo);
            s.push_back(x);
        }
        LafortuneFitOptions fo;
        fo.channels = 1;
        LafortuneFit f;
        if (!fit_lafortune(s, fo, &f, err)) return false;
        fits[size_t(k)] = f.model;
    }
    out->assign(obj.atlas.valid.size(), LafortuneModel());
    for (int t : obj.atlas.texels) {
        const float* w = truth.maps.texel(t);
        (*out)[size_t(t)] = fits[size_t(std::max_element(w, w + K) - w)];
    }
    return true;
}

void evaluate_views(const AcqObject& obj, const std::vector<Capture>& captures, int views,
                    const std::vector<LafortuneModel>& estimates, const PlannerOptions& planner,
                    const RigOptions& rig, PlanState* out) {
    init_plan_state(obj, planner, out);
    set_estimates(estimates, out);
    const std::vector<Capture> prefix(captures.begin(), captures.begin() + std::min<size_t>(captures.size(), size_t(views)));
    accumulate(prefix, rig, out, planner.threads);
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
