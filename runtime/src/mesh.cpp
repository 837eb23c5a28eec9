// Built-in meshes with analytic normals and tangents. Callers own all storage.
#include "internal.h"

#include <math.h>

namespace {
constexpr float kPi = 3.14159265358979323846f;

sepal_result check_capacity(const sepal_mesh* mesh, int vertices, int indices, const char* what,
                          sepal_error* err) {
    if (!mesh || !mesh->vertices || !mesh->indices)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "%s: mesh storage is NULL", what);
    if (mesh->vertex_count < vertices || mesh->index_count < indices)
        return srt::fail(err, SEPAL_ERR_CAPACITY,
                         "%s needs %d vertices and %d indices, storage holds %d and %d", what,
                         vertices, indices, mesh->vertex_count, mesh->index_count);
    return SEPAL_OK;
}
}  // namespace

extern "C" sepal_result sepal_mesh_sphere(int slices, int stacks, sepal_mesh* mesh, sepal_error* err) {
    if (slices < 3 || slices > 256 || stacks < 2 || stacks > 128)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "sphere: slices %d (3..256) or stacks %d (2..128) out of range", slices,
                         stacks);
    const int nv = (slices + 1) * (stacks + 1);
    // The first and last stacks are fans: their degenerate pole triangles are skipped.
    const int ni = slices * (stacks - 1) * 6;
    if (sepal_result r = check_capacity(mesh, nv, ni, "sphere", err)) return r;
    int v = 0;
    for (int j = 0; j <= stacks; ++j) {
        const float theta = kPi * (float)j / (float)stacks;
        for (int i = 0; i <= slices; ++i) {
            const float phi = 2.0f * kPi * (float)i / (float)slices;
            sepal_vertex& p = mesh->vertices[v++];
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

extern "C" sepal_result sepal_mesh_grid(int n, sepal_mesh* mesh, sepal_error* err) {
    if (n < 1 || n > 254)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "grid: n %d out of range 1..254", n);
    const int nv = (n + 1) * (n + 1), ni = n * n * 6;
    if (sepal_result r = check_capacity(mesh, nv, ni, "grid", err)) return r;
    int v = 0;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            sepal_vertex& p = mesh->vertices[v++];
            p = sepal_vertex{};
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

extern "C" sepal_result sepal_mesh_torus(float major_radius, float minor_radius, int rings,
                                     int sides, sepal_mesh* mesh, sepal_error* err) {
    if (!(minor_radius > 0.0f) || !(major_radius > minor_radius) || !isfinite(major_radius) ||
        rings < 3 || rings > 256 || sides < 3 || sides > 128)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                         "torus: need 0 < r < R (got R %g, r %g), rings 3..256 (%d), sides "
                         "3..128 (%d)",
                         (double)major_radius, (double)minor_radius, rings, sides);
    const int nv = (rings + 1) * (sides + 1), ni = rings * sides * 6;
    if (sepal_result r = check_capacity(mesh, nv, ni, "torus", err)) return r;
    int v = 0;
    for (int j = 0; j <= sides; ++j) {
        const float psi = 2.0f * kPi * (float)j / (float)sides;  // around the tube
        for (int i = 0; i <= rings; ++i) {
            const float phi = 2.0f * kPi * (float)i / (float)rings;  // around z
            const float cp = cosf(phi), sp = sinf(phi), cs = cosf(psi), ss = sinf(psi);
            sepal_vertex& p = mesh->vertices[v++];
            const float ring = major_radius + minor_radius * cs;
            p.position[0] = ring * cp;
            p.position[1] = ring * sp;
            p.position[2] = minor_radius * ss;
            p.normal[0] = cs * cp;
            p.normal[1] = cs * sp;
            p.normal[2] = ss;
            p.tangent[0] = -sp;
            p.tangent[1] = cp;
            p.tangent[2] = 0.0f;
            p.tangent[3] = 1.0f;
            p.uv[0] = (float)i / (float)rings;
            p.uv[1] = (float)j / (float)sides;
        }
    }
    int k = 0;
    for (int j = 0; j < sides; ++j)
        for (int i = 0; i < rings; ++i) {
            const uint16_t a = (uint16_t)(j * (rings + 1) + i), b = (uint16_t)(a + 1);
            const uint16_t c = (uint16_t)(a + rings + 1), d = (uint16_t)(c + 1);
            const uint16_t tri[6] = {a, b, d, a, d, c};
            for (uint16_t t : tri) mesh->indices[k++] = t;
        }
    mesh->vertex_count = nv;
    mesh->index_count = k;
    return srt::ok(err);
}

extern "C" sepal_result sepal_mesh_wave(int n, sepal_mesh* mesh, sepal_error* err) {
    sepal_result r = sepal_mesh_grid(n, mesh, err);
    if (r != SEPAL_OK) return r;
    const float a = 0.35f, w = 0.5f * kPi;
    for (int i = 0; i < mesh->vertex_count; ++i) {
        sepal_vertex& p = mesh->vertices[i];
        const float x = p.position[0], y = p.position[1];
        p.position[2] = a * cosf(w * x) * cosf(w * y);
        const float dzdx = -a * w * sinf(w * x) * cosf(w * y);
        const float dzdy = -a * w * cosf(w * x) * sinf(w * y);
        // dP/dx = (1, 0, dzdx), dP/dy = (0, 1, dzdy), n = normalize(dP/dx x dP/dy).
        const float nl = sqrtf(dzdx * dzdx + dzdy * dzdy + 1.0f);
        p.normal[0] = -dzdx / nl;
        p.normal[1] = -dzdy / nl;
        p.normal[2] = 1.0f / nl;
        const float tl = sqrtf(1.0f + dzdx * dzdx);
        p.tangent[0] = 1.0f / tl;
        p.tangent[1] = 0.0f;
        p.tangent[2] = dzdx / tl;
        p.tangent[3] = 1.0f;
    }
    return srt::ok(err);
}
