// Frame-time model of a backend, fitted to measured frames: what `sepal bake --max-error`
// minimizes, and what `make bench` (build/bench/tradeoff.json) measures.
//
// Usage:
//   sepal::CostModel m;
//   if (!sepal::default_cost_model("gles1", &m, &err)) ...          // built in (llvmpipe)
//   if (!sepal::read_cost_model("tradeoff.json", "gles1", &m, &err)) ... // a bench run's
//   double ms = m.predict(passes, terms, bytes);
//
// The model is linear, ms = base + per_pass * passes + per_term * terms + per_kib * KiB
// (KiB of the encoded asset), with non-negative coefficients, fitted by least squares to
// the rows of the trade-off sweep for one backend (fit_cost_model). Passes are the plan's
// passes per light (GL ES 1.1 draws one per pass; fused GL ES 2 draws one per light
// whatever the plan), terms the texture pairs a pixel reads (what the CPU and fused
// shaders pay per pixel), KiB the textures' upload and cache footprint. It ranks assets
// for one backend on one device at the sweep's frame size; it is not a general predictor.
// fit_error says how well it matched the measurements (median |relative residual|).
// Built-in models: `make bench` on Mesa llvmpipe, 2 cores, 512x512, default scene, one
// light (see default_cost_model in cost_model.cpp for the run they came from).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {

struct CostModel {
    std::string backend;  // gles1 | gles2-fused | cpu (or any name a sweep used)
    std::string device;   // where the frames were measured
    int width = 0, height = 0;
    double base_ms = 0, per_pass_ms = 0, per_term_ms = 0, per_kib_ms = 0;
    double fit_error = 0;  // median |predicted - measured| / measured over the fitted rows
    int rows = 0;          // how many measurements the fit used
    double predict(int passes, int terms, int64_t bytes) const;
};

// One measured frame: what the fit sees.
struct CostSample {
    int passes = 0, terms = 0;
    int64_t bytes = 0;
    double ms = 0;
};

// Least squares over every subset of the three slopes (base always kept), keeping the
// best fit whose coefficients are all >= 0 (a pass never makes a frame faster). False
// when fewer than 2 finite samples.
bool fit_cost_model(const std::vector<CostSample>& samples, CostModel* out, std::string* err);
// The models measured on the machine the project is developed on (see the .cpp).
bool default_cost_model(const std::string& backend, CostModel* out, std::string* err);
// The model for `backend` from a trade-off JSON written by `make bench` ("cost_models").
bool read_cost_model(const std::string& path, const std::string& backend, CostModel* out, std::string* err);
// The same from the file's text; `path` names it in messages.
bool parse_cost_model(const std::string& text, const std::string& path, const std::string& backend, CostModel* out,
                      std::string* err);
// The backends with built-in models, for usage messages: "gles1, gles2-fused, cpu".
const char* cost_model_backends();

}  // namespace sepal
