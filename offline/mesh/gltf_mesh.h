// glTF 2.0 meshes (.gltf with embedded or external buffers, .glb) as one sepal_mesh: what
// engines' asset pipelines exchange, read with tinygltf (Debian libtinygltf-dev).
//
// Usage:
//   sepal::GltfMesh m;
//   std::string err;
//   if (!sepal::load_gltf_mesh("chair.glb", &m, &err)) fail(err);   // err names file and part
//   sepal_mesh mesh = m.mesh();                                      // points into m
//
// What is read: every triangle primitive (mode 4) of every mesh the default scene's nodes
// reach (all meshes when the file has no scene), each moved by its node's world transform
// (normals by the inverse transpose), merged into one mesh. Per vertex: POSITION and NORMAL
// (required), TANGENT (xyz, w handedness: the runtime's convention; derived from the UV
// gradients when absent, Lengyel 2001) and TEXCOORD_0 (float or normalized unsigned; zero
// when absent, and then TANGENT is required). Indices: unsigned byte, short or int, or none.
// Refused with a message naming the file, mesh, primitive and attribute: a missing or
// malformed required attribute, a primitive that is not triangles, sparse accessors, an
// accessor reaching past its buffer, extensions the file marks required (Draco, meshopt),
// more than kGltfMaxVertices vertices or kGltfMaxIndices indices in all (sepal_mesh indexes
// with 16 bits), a file or external buffer over kGltfMaxFileBytes, non-finite values.
// Images and materials are ignored (never decoded).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sepal/sepal_rt.h"

namespace sepal {

constexpr size_t kGltfMaxFileBytes = size_t(256) << 20;
constexpr int kGltfMaxVertices = 65535;
constexpr int kGltfMaxIndices = 3 << 20;

struct GltfMesh {
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    int primitives = 0;        // triangle primitives merged
    int derived_tangents = 0;  // vertices whose tangent came from the UV gradients
    sepal_mesh mesh() { return {vertices.data(), indices.data(), int(vertices.size()), int(indices.size())}; }
};

// .glb by its extension or its magic ("glTF"), else JSON glTF; external buffers are read
// relative to the file's folder.
bool load_gltf_mesh(const std::string& path, GltfMesh* out, std::string* err);

}  // namespace sepal
