// Test SVBRDFs with known ground truth: an image of regions and soft transitions blending
// 2-6 basis materials, sampled on a gantry-like set of direction pairs, with measurement
// noise, misregistration and missing samples (`sepal ist generate`).
//
// Usage:
//   sepal::GenerateOptions o; o.width = o.height = 64; o.materials = 4; o.missing = 0.5;
//   sepal::SvbrdfSamples s; sepal::BlendSvbrdf truth; std::string err;
//   if (!sepal::generate_svbrdf(o, &s, &truth, &err)) ...
//   sepal::write_svbrdf("card", s, &err); sepal::write_truth("card", truth, &err);
//   render_exact_spatial(truth, scene, mesh, ...);   // the truth is a spatial BRDF
//
// The layout ("card", after the paper's Seasons Greetings): a blue and a white paper split
// by a wavy soft boundary, a gold foil border and halftone stripes of gold over the papers
// (partial blends: `halftone` is their opacity, 0.45 by default; 1 prints them opaque, so
// materials mix only along edges), silver foil disks, then (5, 6 materials) a satin band and a velvet ring.
// Layers are composited "over" with edges about 1.5 texels wide, so the true weights are
// non-negative and sum to 1 at every texel. Bases: a preset (default_bases: "analytic"
// models, "measured" MERL materials from data/merl-nbrdf, or "mixed", the default:
// blue paper, white paint, gold foil, silver metallic paint, green satin, red fabric),
// or any BRDF specs or measured files.
// Direction pairs (gantry_pairs): `views` view directions from 10 to 60 degrees of
// elevation at golden-angle azimuths; per view `lights` lights spread uniformly over the
// hemisphere (a spherical Fibonacci set) plus `lobe_lights` lights on rings around the
// mirror direction (3/4) and the view (1/4), where specular and back-scattering lobes live.
// Each light's albedo weight is the solid angle of its cell in the nearest-light partition
// of the hemisphere (they sum to 2 pi per view).
// Measurement model per sample: each pair's image is shifted by a random sub-texel offset
// (misregistration, uniform in +-misregistration texels, weights evaluated at the shifted
// position), each channel is multiplied by 1 + noise * N(0, 1) (clamped at 0), then a
// random share `missing` of the samples gets confidence 0. All randomness is counter-based
// from `seed`: the same options give byte-identical output.
// Limits: width and height 4..4096, materials 2..6, views 1..64, lights 1..512,
// lobe_lights 0..256 (at most SvbrdfSamples::kMaxPairs pairs), noise 0..1, missing 0..0.95, halftone 0..1,
// misregistration 0..4 texels.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "svbrdf/blend.h"
#include "svbrdf/samples.h"
#include "reference/render_exact.h"

namespace sepal {

struct GenerateOptions {
    int width = 64, height = 64;
    int materials = 4;
    std::vector<std::string> bases;  // empty: the first `materials` bases of the preset
    std::string preset = "mixed";
    int views = 8, lights = 40, lobe_lights = 16;
    double noise = 0.02;
    double misregistration = 0.1;
    double missing = 0;
    double halftone = 0.45;  // opacity of the gold stripes over the white paper, 0..1
    uint64_t seed = 1;
    int threads = 0;
};

struct NamedBasis {
    const char* name;
    const char* spec;
};
// The presets' six bases each (an empty list for an unknown preset).
const std::vector<NamedBasis>& default_bases(const std::string& preset);

std::vector<DirPair> gantry_pairs(int views, int lights, int lobe_lights);
// The true weights of the "card" layout at (u, v) in [0,1]^2 (edge width in UV units).
void card_weights(int materials, double u, double v, double edge, double halftone, double* w);

// truth: the true SVBRDF (names, specs, bases and weight maps), or null.
bool generate_svbrdf(const GenerateOptions& o, SvbrdfSamples* out, BlendSvbrdf* truth, std::string* err);

// DIR/truth.json and DIR/truth/blendJ.pfm (docs/ist.md).
bool write_truth(const std::string& dir, const BlendSvbrdf& t, std::string* err);
bool read_truth(const std::string& dir, BlendSvbrdf* t, std::string* err);  // builds the bases

}  // namespace sepal
