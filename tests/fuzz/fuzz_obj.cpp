// The runtime's OBJ reader (sepal_rt.h: sepal_obj_measure, then sepal_obj_load into the
// storage it asked for). A loaded mesh's indices are in range and its vertices finite; a
// refusal has a message.
#include <cmath>
#include <cstring>
#include <vector>

#include "fuzz/fuzz.h"
#include "sepal/sepal_rt.h"

extern "C" int sepal_fuzz_obj(const uint8_t* data, size_t size) {
    const char* h = "obj";
    const char* text = reinterpret_cast<const char*>(data);
    sepal_obj_info info = {};
    sepal_error err = {};
    if (sepal_obj_measure(text, size, &info, &err) != SEPAL_OK) {
        sepal_fuzz::check(err.message[0] != '\0', h, "measure: a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(info.max_vertices >= 0 && info.max_indices >= 0, h, "negative capacities");
    if (info.max_vertices > (1 << 20) || info.max_indices > (1 << 22) || info.scratch_bytes > (size_t(1) << 28)) return 0;
    std::vector<sepal_vertex> vertices(size_t(info.max_vertices) + 1);
    std::vector<uint16_t> indices(size_t(info.max_indices) + 1);
    std::vector<uint8_t> scratch(info.scratch_bytes + 1);
    sepal_mesh mesh = {vertices.data(), indices.data(), info.max_vertices, info.max_indices};
    sepal_obj_stats stats = {};
    if (sepal_obj_load(text, size, &mesh, scratch.data(), info.scratch_bytes, &stats, &err) != SEPAL_OK) {
        sepal_fuzz::check(err.message[0] != '\0', h, "load: a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(mesh.vertex_count >= 0 && mesh.vertex_count <= info.max_vertices && mesh.index_count >= 0 &&
                          mesh.index_count <= info.max_indices && mesh.index_count % 3 == 0,
                      h, "counts beyond the measured capacities");
    for (int i = 0; i < mesh.index_count; ++i)
        sepal_fuzz::check(indices[size_t(i)] < mesh.vertex_count, h, "an index past the vertices");
    return 0;
}
