// Any BRDF the tools take, from its spec string: the one factory above the analytic models
// (brdf/) and the measured readers (measured/), so that neither stage depends on the other.
//
// Usage:
//   std::string err;
//   std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("ward:rho_d=0.1,rho_s=1.2,ax=0.2,ay=0.02", &err);
//   if (!f) { fprintf(stderr, "%s\n", err.c_str()); return 2; }
//
// SPEC is an analytic model ("model:param=value,...", brdf/brdf_models.h), a path to measured
// data (.binary MERL, .brdf Cornell; measured/measured.h) or "nbrdf:NAME", one of the 100 MERL
// materials as a neural fit (measured/nbrdf.h; `sepal info nbrdf:` lists them).
#pragma once
#include <memory>
#include <string>

#include "brdf/brdf.h"

namespace sepal {

// Null with the reason in *err: unknown model, bad parameter, unreadable or corrupt file.
std::unique_ptr<Brdf> make_brdf(const std::string& spec, std::string* err);

}  // namespace sepal
