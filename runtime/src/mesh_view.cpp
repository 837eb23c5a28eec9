// Views of an object's vertices (see mesh_view.h): a sepal_mesh or the engine's arrays.
#include "mesh_view.h"

#include <string.h>

#include "draw_internal.h"

namespace srt {

MeshView::MeshView(const sepal_mesh& mesh) {
    if (!mesh.vertices) return;
    const sepal_vertex* v = mesh.vertices;
    attr[kPosition] = (const unsigned char*)v->position;
    attr[kNormal] = (const unsigned char*)v->normal;
    attr[kTangent] = (const unsigned char*)v->tangent;
    attr[kUv] = (const unsigned char*)v->uv;
    for (size_t& s : stride) s = sizeof(sepal_vertex);
    vertex_count = mesh.vertex_count;
    indices = mesh.indices;
    index_count = mesh.index_count;
    direct = v;
}

sepal_result mesh_view(const sepal_vertex_data& data, MeshView* out, sepal_error* err) {
    static const char* const kName[MeshView::kAttributes] = {"position", "normal", "tangent", "uv"};
    static const int kFloats[MeshView::kAttributes] = {3, 3, 4, 2};
    const sepal_vertex_stream* streams[MeshView::kAttributes] = {&data.position, &data.normal, &data.tangent,
                                                                 &data.uv};
    if (data.vertex_count < 1 || data.vertex_count > 65535)
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "vertices: vertex_count %d outside 1..65535 (16-bit indices)",
                    data.vertex_count);
    if (!data.indices || data.index_count < 3 || data.index_count % 3)
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                    "vertices: %d indices%s (triangles: a positive multiple of 3 and an index array)",
                    data.index_count, data.indices ? "" : " and a NULL index array");
    MeshView v;
    for (int a = 0; a < MeshView::kAttributes; ++a) {
        const sepal_vertex_stream& s = *streams[a];
        const int size = kFloats[a] * (int)sizeof(float);
        if (!s.data) return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "vertices: the %s array is NULL", kName[a]);
        if (s.offset < 0 || s.stride < 0 || (s.stride > 0 && s.stride < size))
            return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                        "vertices: %s offset %d, stride %d: the stride is 0 (packed) or at least the element's %d "
                        "bytes, the offset at least 0",
                        kName[a], s.offset, s.stride, size);
        const unsigned char* first = (const unsigned char*)s.data + s.offset;
        if ((uintptr_t)first % sizeof(float) || s.stride % (int)sizeof(float))
            return fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                        "vertices: %s offset %d or stride %d leaves its floats unaligned (multiples of 4 bytes)",
                        kName[a], s.offset, s.stride);
        v.attr[a] = first;
        v.stride[a] = (size_t)(s.stride ? s.stride : size);
    }
    v.vertex_count = data.vertex_count;
    v.indices = data.indices;
    v.index_count = data.index_count;
    *out = v;
    return ok(err);
}

sepal_result object_mesh_view(const sepal_object& o, const ObjectSpace& space, MeshView* out, sepal_error* err) {
    if (o.mesh && o.vertices)
        return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: both a mesh and vertex data (give one of them)");
    if (o.vertices) {
        const sepal_result r = mesh_view(*o.vertices, out, err);
        if (r != SEPAL_OK) return r;
    } else {
        if (!o.mesh || !o.mesh->vertices || !o.mesh->indices || o.mesh->vertex_count < 1 || o.mesh->index_count % 3)
            return fail(err, SEPAL_ERR_INVALID_ARGUMENT, "object: no mesh or vertex data, or an empty or malformed mesh");
        *out = MeshView(*o.mesh);
    }
    out->transform = space.transform;
    if (space.transform) {
        out->direct = nullptr;
        memcpy(out->m, space.m, sizeof out->m);
        memcpy(out->n, space.n, sizeof out->n);
    }
    return ok(err);
}

sepal_result object_view(const float view[16], const sepal_object& o, ObjectSpace* space, MeshView* mesh,
                         sepal_error* err) {
    const sepal_result r = object_space(view, o.model, o.lights, o.light_count, space, err);
    return r != SEPAL_OK ? r : object_mesh_view(o, *space, mesh, err);
}

}  // namespace srt
