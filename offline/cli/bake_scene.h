// bake-scene's scene file (offline/cli/cmd_bake_scene.cpp): one material's options.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "brdf/brdf.h"
#include "util/json.h"

namespace sepal {

// Reads a "materials" entry's options beyond "name" and "spec" (param, map, method, res,
// terms, max_error, max_passes, max_bytes, bits, cap, target, white, min_psnr) into *out,
// each kind and range checked before conversion. False with a message naming the member
// (f.where + ".max_passes: ...") on an unknown key or a bad value.
bool scene_material_options(const JsonField& f, BakeOptions* out, std::string* err);

// The bake key: a checksum of the canonical spec, the measured file's bytes, the options, the
// scene's views (views_key) and the format version; an asset holding the same key need not be
// baked again.
std::string scene_bake_key(const Brdf& brdf, const BakeOptions& o, const std::string& views_key,
                           const std::vector<uint8_t>& measured);
// The bake key in the asset at path, or "" when there is none (or it is not a valid asset).
std::string existing_bake_key(const std::string& path);

}  // namespace sepal
