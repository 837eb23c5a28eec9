// Shared small SVBRDFs for the inverse-shade-tree suites: generated once per process (the
// decompositions are the slow part; each suite reuses them).
#pragma once
#include "ist/decompose.h"
#include "ist/tree.h"

namespace sepal_test {

struct IstCase {
    sepal::SvbrdfSamples svbrdf;      // complete data
    sepal::BlendSvbrdf truth;
    sepal::Decomposition sacls;  // default SACLS, 4 terms
};

// 24 x 24 texels, 4 materials of the mixed preset, 8 views x (32 + 12) lights.
const IstCase& ist_case();
sepal::GenerateOptions ist_case_options();
// The decomposition options the suites use (fewer restarts and iterations than the default).
sepal::DecomposeOptions ist_decompose_options(sepal::IstMethod m);
// A tree of ist_case().sacls at res 16 (built once).
const sepal::ShadeTree& ist_case_tree();

}  // namespace sepal_test
