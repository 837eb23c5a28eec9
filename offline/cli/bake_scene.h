// bake-scene's scene file (offline/cli/cmd_bake_scene.cpp): one material's options.
#pragma once
#include <string>

#include "bake/bake.h"
#include "util/json.h"

namespace sepal {

// Reads a "materials" entry's options beyond "name" and "spec" (param, map, method, res,
// terms, max_error, max_passes, max_bytes, bits, cap, target, white, min_psnr) into *out,
// each kind and range checked before conversion. False with a message naming the member
// (f.where + ".max_passes: ...") on an unknown key or a bad value.
bool scene_material_options(const JsonField& f, BakeOptions* out, std::string* err);

}  // namespace sepal
