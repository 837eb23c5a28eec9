// Scattered BRDF samples on disk: what `sepal measure capture` writes and `sepal fit
// lafortune` reads.
//
// Usage:
//   std::vector<sepal::BrdfSample> s; std::string err;
//   if (!sepal::read_brdf_samples("samples.csv", &s, &err)) ...   // or a Cornell .brdf file
//   sepal::write_brdf_samples("out.csv", s, "comment line", &err);
//
// samples.csv: '#' comment lines, then a header naming the columns, then one sample per line,
// comma separated. Required columns: theta_i, phi_i, theta_o, phi_o (degrees, the local frame
// of brdf.h: theta from the normal, phi from the tangent), and either r, g, b or one grey
// value; optional: weight (1 / std up to a common factor; default 1). Other columns (a
// capture's x, y, texel) are carried along and ignored. Written values have 9 significant
// digits. Files ending in .brdf are read as Cornell measurements (cornell.h: their samples,
// weight 1).
// The reader refuses, naming the line: a missing required column, a line with the wrong
// number of fields, a field that is not a finite number, theta outside [0, 90] or a negative
// weight, more than 4 million samples, files over 256 MiB.
#pragma once
#include <string>
#include <vector>

#include "brdf/brdf.h"  // BrdfSample

namespace sepal {

constexpr size_t kMaxBrdfSamples = 4000000;

bool read_brdf_samples(const std::string& path, std::vector<BrdfSample>* out, std::string* err);
bool parse_brdf_samples(const std::string& text, const std::string& name, std::vector<BrdfSample>* out,
                        std::string* err);
// Extra columns (e.g. "x", "y", "texel") go before the standard ones, one value per sample each.
bool write_brdf_samples(const std::string& path, const std::vector<BrdfSample>& samples, const std::string& comment,
                        std::string* err, const std::vector<std::string>& extra_names = {},
                        const std::vector<std::vector<double>>& extra_values = {});

// Degrees (theta from the normal, phi from the tangent) to a unit direction, and back.
glm::dvec3 direction_from_degrees(double theta, double phi);
void degrees_from_direction(const glm::dvec3& w, double* theta, double* phi);

}  // namespace sepal
