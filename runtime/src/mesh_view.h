// The vertices a backend draws (internal): a sepal_mesh, or the engine's own arrays read by
// offset and stride (sepal_vertex_data), and the affine map from the object's space into
// the space it is shaded in.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sepal/sepal_frame.h"

namespace srt {

struct MeshView {
    enum { kPosition, kNormal, kTangent, kUv, kAttributes };
    const unsigned char* attr[kAttributes] = {};  // vertex 0's element of each attribute
    size_t stride[kAttributes] = {};              // bytes from one vertex's element to the next
    int vertex_count = 0;
    const uint16_t* indices = nullptr;
    int index_count = 0;
    // The vertices as a plain sepal_vertex array (a sepal_mesh, no transform): the batched
    // set-up reads them in place. NULL otherwise.
    const sepal_vertex* direct = nullptr;
    // Shading space from object space: positions by m (3 x 3 column-major, then the
    // translation), normals by n (the inverse transpose of m's 3 x 3), tangents by m's
    // 3 x 3 (w kept: det > 0). transform false: the two spaces are one.
    bool transform = false;
    float m[12] = {}, n[9] = {};

    MeshView() = default;
    MeshView(const sepal_mesh& mesh);  // NOLINT: a mesh is a view of itself (implicit on purpose)

    const float* element(int a, int i) const { return (const float*)(attr[a] + (size_t)i * stride[a]); }
    // The object-space position (what GL transforms with the modelview).
    const float* position(int i) const { return element(kPosition, i); }
    // Vertex i in the shading space (every backend shades this), and count of them from first.
    void load(int i, sepal_vertex* v) const { load_range(i, 1, v); }
    void load_range(int first, int count, sepal_vertex* out) const;
};

// The engine's arrays: checks every pointer, stride, alignment and count (messages name the
// attribute and the number), then views them. transform as object_scene chose.
sepal_result mesh_view(const sepal_vertex_data& data, MeshView* out, sepal_error* err);
// An object's vertices (its mesh or its vertex data; exactly one of them), with the
// shading transform of object_scene.
sepal_result object_mesh_view(const sepal_object& o, const struct ObjectSpace& space, MeshView* out,
                              sepal_error* err);
// Both for a frame's object: object_space of view and the object's model and lights, then its
// vertices.
sepal_result object_view(const float view[16], const sepal_object& o, struct ObjectSpace* space, MeshView* mesh,
                         sepal_error* err);

}  // namespace srt
