// A Monte Carlo renderer on the CPU, to prove samplers: each pixel of a mesh (a sphere by
// default) under distant lighting, L = (1/N) sum Le(wi) f(wi, wo) cos(theta_i) / pdf(wi), with
// wi drawn by any sampler through the runtime API (sepal_sampler.h) and f the ORIGINAL BRDF,
// as in Lawrence et al. 2004 (the estimator is unbiased whatever the sampler, tested).
//
// Usage:
//   sepal::McOptions o; o.spp = 100; o.seed = 7;
//   sepal::McResult r; std::string err;
//   if (!sepal::render_mc(*brdf, sampler.get(), *env, scene, mesh, 256, 256, o, &r, &err)) ...
//   write_png("out.png", r.image, &err);
//
// Pixels the mesh does not cover show the environment along the camera ray; back-facing
// views (wo below the interpolated frame's horizon) and unusable normals are black, counted.
// No visibility: lighting is distant and unoccluded (a convex object, as the paper's sphere).
// Multiple importance sampling (`mis`, on for every environment but a constant one): each
// of the spp iterations also draws one direction from the environment's luminance
// (EnvironmentSampler) and both samples are weighted by the balance heuristic,
// Le f cos / (pdf_brdf + pdf_light): the light samples follow a sun that a BRDF sampler
// cannot, the BRDF samples a lobe that the light sampler cannot. Still unbiased (tested).
// Runs on all cores (rows in parallel); the image depends only on the inputs and the seed,
// not on the thread count.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "sampling/environment.h"
#include "sampling/sequence.h"
#include "sepal/sepal_sampler.h"
#include "sepal/sepal_scene.h"
#include "util/image.h"

namespace sepal {

enum class Mis { Auto, On, Off };  // auto: on unless the environment is constant

// The light sampler's grid (environment.h): 512 x 256 cells.
constexpr int kMcLightWidth = 512, kMcLightHeight = 256;

struct McOptions {
    int spp = 16;  // 1..1e6 (with MIS: spp BRDF samples and spp light samples)
    Mis mis = Mis::Auto;
    uint64_t seed = 1;
    SampleSequence sequence = SampleSequence::Stratified;
    int threads = 0;
    bool progress = false;
    // With MIS: the light sampler of this same environment, built by the caller
    // (build(env, kMcLightWidth, kMcLightHeight)), so a loop of renders under one
    // environment builds it once instead of every time (2 M radiance lookups each). Not
    // owned; nullptr: built here.
    const EnvironmentSampler* light = nullptr;
};

struct McResult {
    Image image;                  // linear RGB
    std::vector<uint8_t> shaded;  // 1 where the pixel was shaded by the estimator
    int64_t shaded_pixels = 0, back_facing = 0, degenerate = 0;
    int64_t samples = 0, below_horizon = 0, failed = 0;  // failed: the sampler gave no direction
    int64_t light_samples = 0;    // with MIS: environment samples drawn
    bool mis = false;             // whether MIS was used
    double seconds = 0;
};

bool render_mc(const Brdf& brdf, const sepal_sampler& sampler, const Environment& env,
               const sepal_scene& scene, const sepal_mesh& mesh, int width, int height,
               const McOptions& o, McResult* out, std::string* err);

}  // namespace sepal
