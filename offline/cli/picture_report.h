// The picture figures (bake/picture.h) as the tools print and write them: `measure reconstruct
// --truth` and `fit lafortune --truth` judge what they produced by its exact renders against the
// true BRDF, in the default scene and the held-out conditions.
#pragma once
#include <cstdio>
#include <string>

#include "bake/picture.h"
#include "util/json.h"

namespace sepal {

// Renders `approx` and `truth` in picture_views() at 256 x 256, prints two "picture" lines to
// out and returns the figures as JSON in *json.
bool report_picture(const Brdf& truth, const Brdf& approx, FILE* out, Json* json, std::string* err);

}  // namespace sepal
