// Built-in meshes with analytic normals and tangents. Callers own all storage.
#include "internal.h"

#include <math.h>

namespace {
constexpr float kPi = 3.14159265358979323846f;

srt_result check_capacity(const srt_mesh* mesh, int vertices, int indices, const char* what,
                          srt_error* err) {
    if (!mesh || !mesh->vertices || !mesh->indices)
        return srt::fail(err, SRT_ERR_INVALID_ARGUMENT, "%s: mesh storage is NULL", what);
    if (mesh->vertex_count < vertices || mesh->index_count < indices)
        return srt::fail(err, SRT_ERR_CAPACITY,
                         "%s needs %d vertices and %d indices, storage holds %d and %d", what,
                         vertices, indices, mesh->vertex_count, mesh->index_count);
    return SRT_OK;
}
}  // namespace

extern "C" srt_result srt_mesh_sphere(int slices, int stacks, srt_mesh* mesh, srt_error* err) {
    if (slices < 3 || slices > 256 || stacks < 2 || stacks > 128)
        return srt::fail(err, SRT_ERR_INVALID_ARGUMENT,
                         "sphere: slices %d (3..256) or stacks %d (2..128) out of range", slices,
                         stacks);
    const int nv = (slices + 1) * (stacks + 1);
    // The first and last stacks are fans: their degenerate pole triangles are skipped.
    const int ni = slices * (stacks - 1) * 6;
    if (srt_result r = check_capacity(mesh, nv, ni, "sphere", err)) return r;
    int v = 0;
    for (int j = 0; j <= stacks; ++j) {
        const float theta = kPi * (float)j / (float)stacks;
        for (int i = 0; i <= slices; ++i) {
            const float phi = 2.0f * kPi * (float)i / (float)slices;
            srt_vertex& p = mesh->vertices[v++];
            const float st = sinf(theta), ct = cosf(theta), sp = sinf(phi), cp = cosf(phi);
            p.position[0] = p.normal[0] = st * cp;
            p.position[1] = p.normal[1] = st * sp;
            p.position[2] = p.normal[2] = ct;
            p.tangent[0] = -sp;
            p.tangent[1] = cp;
            p.tangent[2] = 0.0f;
            p.tangent[3] = 1.0f;
            p.uv[0] = (float)i / (float)slices;
            p.uv[1] = (float)j / (float)stacks;
        }
    }
    int k = 0;
    const int row = slices + 1;
    for (int j = 0; j < stacks; ++j) {
        for (int i = 0; i < slices; ++i) {
            const uint16_t a = (uint16_t)(j * row + i), b = (uint16_t)(a + 1);
            const uint16_t c = (uint16_t)(a + row), d = (uint16_t)(c + 1);
            // Counter-clockwise seen from outside (normals point out).
            if (j != 0) {
                mesh->indices[k++] = a;
                mesh->indices[k++] = c;
                mesh->indices[k++] = b;
            }
            if (j != stacks - 1) {
                mesh->indices[k++] = b;
                mesh->indices[k++] = c;
                mesh->indices[k++] = d;
            }
        }
    }
    mesh->vertex_count = nv;
    mesh->index_count = k;
    return srt::ok(err);
}

extern "C" srt_result srt_mesh_grid(int n, srt_mesh* mesh, srt_error* err) {
    if (n < 1 || n > 254)
        return srt::fail(err, SRT_ERR_INVALID_ARGUMENT, "grid: n %d out of range 1..254", n);
    const int nv = (n + 1) * (n + 1), ni = n * n * 6;
    if (srt_result r = check_capacity(mesh, nv, ni, "grid", err)) return r;
    int v = 0;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            srt_vertex& p = mesh->vertices[v++];
            p = srt_vertex{};
            p.uv[0] = (float)i / (float)n;
            p.uv[1] = (float)j / (float)n;
            p.position[0] = 2.0f * p.uv[0] - 1.0f;
            p.position[1] = 2.0f * p.uv[1] - 1.0f;
            p.normal[2] = 1.0f;
            p.tangent[0] = 1.0f;
            p.tangent[3] = 1.0f;
        }
    }
    int k = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const uint16_t a = (uint16_t)(j * (n + 1) + i), b = (uint16_t)(a + 1);
            const uint16_t c = (uint16_t)(a + n + 1), d = (uint16_t)(c + 1);
            const uint16_t tri[6] = {a, b, d, a, d, c};
            for (uint16_t t : tri) mesh->indices[k++] = t;
        }
    }
    mesh->vertex_count = nv;
    mesh->index_count = k;
    return srt::ok(err);
}
