// Measured BRDF data: the entry point make_brdf uses for file specs.
//
// Usage:
//   std::unique_ptr<sepal::Brdf> f = sepal::load_measured_brdf("fixtures/cornell/cayman.brdf", &err);
//   std::printf("%s", f->info().c_str());   // sample counts, missing samples, coverage
//
// Dispatch is by content first, then by extension: a file whose first 12 bytes are a MERL
// header (90 90 180 in either byte order) or whose size is exactly a MERL file's is read as
// MERL (merl.h); otherwise a .binary file is read as MERL (which explains what is wrong) and
// anything else as Cornell text (cornell.h), except a BRDF Explorer file (GLSL shader text
// that shares the .brdf extension), which is refused naming what it is. Both kinds are isotropic tables in
// (theta_h, theta_d, phi_d) (tabulated.h) and report their counts through info().
// Limits: files over 64 MiB are refused before reading.
#pragma once
#include "brdf/brdf.h"

namespace sepal {
std::unique_ptr<Brdf> load_measured_brdf(const std::string& path, std::string* err);
}  // namespace sepal
