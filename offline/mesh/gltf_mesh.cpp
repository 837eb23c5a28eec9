#include "mesh/gltf_mesh.h"

#include <cmath>
#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include "mesh/tiny_gltf.h"

#include "util/io.h"

namespace sepal {
namespace {

constexpr int kMaxNodeDepth = 64;

// External buffers through the same bound as the file itself.
bool read_bounded(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, kGltfMaxFileBytes)) return false;
    out->assign(bytes.begin(), bytes.end());
    return true;
}

bool no_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;
}

struct Reader {
    const tinygltf::Model& model;
    std::string file;
    std::string* err;

    bool fail(const std::string& where, const std::string& what) const {
        *err = file + ": " + where + ": " + what;
        return false;
    }

    // Accessor `index` as `components` floats per element (float, or normalized unsigned
    // byte/short when `normalized_ok`), every byte checked against its buffer.
    bool floats(int index, int components, bool normalized_ok, const std::string& where, std::vector<float>* out) const {
        if (index < 0 || size_t(index) >= model.accessors.size()) return fail(where, "accessor index out of range");
        const tinygltf::Accessor& a = model.accessors[size_t(index)];
        const int type = components == 2 ? TINYGLTF_TYPE_VEC2 : components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
        if (a.type != type) return fail(where, "expected VEC" + std::to_string(components) + " elements");
        if (a.sparse.isSparse) return fail(where, "sparse accessors are not supported");
        int bytes_per = 4;
        if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && normalized_ok && a.normalized) bytes_per = 1;
        else if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && normalized_ok && a.normalized) bytes_per = 2;
        else if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            return fail(where, normalized_ok ? "components must be float or normalized unsigned byte/short"
                                             : "components must be float");
        const uint8_t* base = nullptr;
        size_t stride = 0;
        if (!locate(a, size_t(bytes_per) * size_t(components), where, &base, &stride)) return false;
        out->resize(a.count * size_t(components));
        for (size_t i = 0; i < a.count; ++i)
            for (int c = 0; c < components; ++c) {
                const uint8_t* p = base + i * stride + size_t(c) * size_t(bytes_per);
                float v;
                if (bytes_per == 4) std::memcpy(&v, p, 4);
                else if (bytes_per == 1) v = float(*p) / 255.0f;
                else v = float(uint16_t(p[0] | (p[1] << 8))) / 65535.0f;
                if (!std::isfinite(v)) return fail(where, "element " + std::to_string(i) + " is not finite");
                (*out)[i * size_t(components) + size_t(c)] = v;
            }
        return true;
    }

    bool indices(int index, size_t vertex_count, const std::string& where, std::vector<uint32_t>* out) const {
        if (index < 0 || size_t(index) >= model.accessors.size()) return fail(where, "accessor index out of range");
        const tinygltf::Accessor& a = model.accessors[size_t(index)];
        if (a.type != TINYGLTF_TYPE_SCALAR) return fail(where, "expected SCALAR elements");
        if (a.sparse.isSparse) return fail(where, "sparse accessors are not supported");
        const int t = a.componentType;
        const size_t bytes_per = t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 1 : t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                 : t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT ? 4 : 0;
        if (!bytes_per) return fail(where, "components must be unsigned byte, short or int");
        const uint8_t* base = nullptr;
        size_t stride = 0;
        if (!locate(a, bytes_per, where, &base, &stride)) return false;
        out->resize(a.count);
        for (size_t i = 0; i < a.count; ++i) {
            const uint8_t* p = base + i * stride;
            uint32_t v = bytes_per == 1 ? p[0] : bytes_per == 2 ? uint32_t(p[0] | (p[1] << 8))
                                                               : uint32_t(p[0] | (p[1] << 8) | (p[2] << 16) | (uint32_t(p[3]) << 24));
            if (v >= vertex_count)
                return fail(where, "index " + std::to_string(v) + " at " + std::to_string(i) + " is past the " +
                                       std::to_string(vertex_count) + " vertices");
            (*out)[i] = v;
        }
        return true;
    }

    bool locate(const tinygltf::Accessor& a, size_t element_bytes, const std::string& where, const uint8_t** base,
                size_t* stride) const {
        if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
            return fail(where, "has no buffer view (accessors without data are not supported)");
        const tinygltf::BufferView& v = model.bufferViews[size_t(a.bufferView)];
        if (v.buffer < 0 || size_t(v.buffer) >= model.buffers.size()) return fail(where, "buffer index out of range");
        const std::vector<unsigned char>& b = model.buffers[size_t(v.buffer)].data;
        *stride = v.byteStride ? v.byteStride : element_bytes;
        if (*stride < element_bytes) return fail(where, "byte stride smaller than an element");
        const size_t start = v.byteOffset + a.byteOffset;
        const size_t need = a.count ? start + (a.count - 1) * *stride + element_bytes : start;
        if (v.byteOffset > b.size() || v.byteLength > b.size() - v.byteOffset || need > v.byteOffset + v.byteLength ||
            a.count > (kGltfMaxFileBytes / element_bytes))
            return fail(where, std::to_string(a.count) + " elements reach past the buffer view (" +
                                   std::to_string(v.byteLength) + " bytes)");
        *base = b.data() + start;
        return true;
    }
};

glm::dmat4 node_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        glm::dmat4 m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(4 * c + r)];
        return m;
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (n.translation.size() == 3) t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    if (n.rotation.size() == 4)
        r = glm::dmat4(glm::mat3_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2])));
    if (n.scale.size() == 3) s[0][0] = n.scale[0], s[1][1] = n.scale[1], s[2][2] = n.scale[2];
    return t * r * s;
}

// Tangents from the UV gradients of the triangles around each vertex (Lengyel 2001), made
// orthogonal to the normal; a vertex whose UVs give none gets any perpendicular.
void derive_tangents(std::vector<sepal_vertex>& v, const std::vector<uint32_t>& idx, size_t first) {
    std::vector<glm::vec3> tan(v.size() - first, glm::vec3(0)), bit(v.size() - first, glm::vec3(0));
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
        const sepal_vertex& a = v[first + idx[t]];
        const sepal_vertex& b = v[first + idx[t + 1]];
        const sepal_vertex& c = v[first + idx[t + 2]];
        const glm::vec3 e1 = glm::vec3(b.position[0], b.position[1], b.position[2]) - glm::vec3(a.position[0], a.position[1], a.position[2]);
        const glm::vec3 e2 = glm::vec3(c.position[0], c.position[1], c.position[2]) - glm::vec3(a.position[0], a.position[1], a.position[2]);
        const float s1 = b.uv[0] - a.uv[0], t1 = b.uv[1] - a.uv[1], s2 = c.uv[0] - a.uv[0], t2 = c.uv[1] - a.uv[1];
        const float det = s1 * t2 - s2 * t1;
        if (!(std::fabs(det) > 1e-20f)) continue;
        const glm::vec3 sdir = (e1 * t2 - e2 * t1) / det, tdir = (e2 * s1 - e1 * s2) / det;
        for (int k = 0; k < 3; ++k) tan[idx[t + size_t(k)]] += sdir, bit[idx[t + size_t(k)]] += tdir;
    }
    for (size_t i = first; i < v.size(); ++i) {
        const glm::vec3 n(v[i].normal[0], v[i].normal[1], v[i].normal[2]);
        glm::vec3 t = tan[i - first] - n * glm::dot(n, tan[i - first]);
        if (!(glm::length(t) > 1e-12f)) t = std::fabs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0));
        t = glm::normalize(t);
        const float w = glm::dot(glm::cross(n, t), bit[i - first]) < 0.0f ? -1.0f : 1.0f;
        v[i].tangent[0] = t.x, v[i].tangent[1] = t.y, v[i].tangent[2] = t.z, v[i].tangent[3] = w;
    }
}

struct Merger {
    const Reader& rd;
    GltfMesh* out;
    std::vector<uint32_t> all_indices;

    bool primitive(const tinygltf::Primitive& p, const glm::dmat4& m, const std::string& where) {
        if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1)
            return rd.fail(where, "mode " + std::to_string(p.mode) + " is not triangles (4)");
        auto attr = [&](const char* name) {
            auto it = p.attributes.find(name);
            return it == p.attributes.end() ? -1 : it->second;
        };
        const int ip = attr("POSITION"), in = attr("NORMAL"), it = attr("TANGENT"), iu = attr("TEXCOORD_0");
        if (ip < 0) return rd.fail(where, "has no POSITION attribute");
        if (in < 0) return rd.fail(where, "has no NORMAL attribute (sepal shades with the file's normals)");
        if (it < 0 && iu < 0)
            return rd.fail(where, "has neither TANGENT nor TEXCOORD_0 (tangents are derived from the UVs when absent)");
        std::vector<float> pos, nrm, tng, uv;
        if (!rd.floats(ip, 3, false, where + ".POSITION", &pos) || !rd.floats(in, 3, false, where + ".NORMAL", &nrm) ||
            (it >= 0 && !rd.floats(it, 4, false, where + ".TANGENT", &tng)) ||
            (iu >= 0 && !rd.floats(iu, 2, true, where + ".TEXCOORD_0", &uv)))
            return false;
        const size_t n = pos.size() / 3;
        if (nrm.size() / 3 != n || (!tng.empty() && tng.size() / 4 != n) || (!uv.empty() && uv.size() / 2 != n))
            return rd.fail(where, "attributes have different counts");
        const size_t first = out->vertices.size();
        if (first + n > size_t(kGltfMaxVertices))
            return rd.fail(where, std::to_string(first + n) + " vertices in all, over the " + std::to_string(kGltfMaxVertices) +
                                      " a sepal_mesh indexes with 16 bits");
        std::vector<uint32_t> idx;
        if (p.indices >= 0) {
            if (!rd.indices(p.indices, n, where + ".indices", &idx)) return false;
        } else {
            idx.resize(n);
            for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
        }
        if (idx.size() % 3) return rd.fail(where, std::to_string(idx.size()) + " indices is not a whole number of triangles");
        if (all_indices.size() + idx.size() > size_t(kGltfMaxIndices))
            return rd.fail(where, "over " + std::to_string(kGltfMaxIndices) + " indices in all");
        const glm::dmat3 lin(m), nmat = glm::transpose(glm::inverse(lin));
        const bool flip = glm::determinant(lin) < 0.0;
        if (!(std::fabs(glm::determinant(lin)) > 1e-300)) return rd.fail(where, "its node's transform is singular");
        out->vertices.resize(first + n);
        for (size_t i = 0; i < n; ++i) {
            sepal_vertex& v = out->vertices[first + i];
            const glm::dvec3 P = glm::dvec3(m * glm::dvec4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], 1.0));
            glm::dvec3 N = nmat * glm::dvec3(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
            if (!(glm::length(N) > 0.0)) return rd.fail(where + ".NORMAL", "element " + std::to_string(i) + " has zero length");
            N = glm::normalize(N);
            for (int k = 0; k < 3; ++k) v.position[k] = float(P[k]), v.normal[k] = float(N[k]);
            v.uv[0] = uv.empty() ? 0.0f : uv[2 * i];
            v.uv[1] = uv.empty() ? 0.0f : uv[2 * i + 1];
            if (!tng.empty()) {
                glm::dvec3 T = lin * glm::dvec3(tng[4 * i], tng[4 * i + 1], tng[4 * i + 2]);
                T -= N * glm::dot(N, T);
                if (!(glm::length(T) > 0.0))
                    return rd.fail(where + ".TANGENT", "element " + std::to_string(i) + " is zero or parallel to the normal");
                T = glm::normalize(T);
                for (int k = 0; k < 3; ++k) v.tangent[k] = float(T[k]);
                v.tangent[3] = (tng[4 * i + 3] < 0.0f) != flip ? -1.0f : 1.0f;
            }
        }
        if (flip)
            for (size_t t = 0; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
        if (tng.empty()) {
            derive_tangents(out->vertices, idx, first);
            out->derived_tangents += int(n);
        }
        for (uint32_t i : idx) all_indices.push_back(uint32_t(first) + i);
        ++out->primitives;
        return true;
    }

    bool mesh(int index, const glm::dmat4& m) {
        const tinygltf::Mesh& me = rd.model.meshes[size_t(index)];
        for (size_t k = 0; k < me.primitives.size(); ++k)
            if (!primitive(me.primitives[k], m,
                           "meshes[" + std::to_string(index) + "]" + (me.name.empty() ? "" : " (" + me.name + ")") +
                               ".primitives[" + std::to_string(k) + "]"))
                return false;
        return true;
    }

    bool node(int index, const glm::dmat4& parent, int depth) {
        if (index < 0 || size_t(index) >= rd.model.nodes.size()) return rd.fail("nodes", "node index out of range");
        if (depth > kMaxNodeDepth) return rd.fail("nodes", "deeper than " + std::to_string(kMaxNodeDepth) + " (a cycle?)");
        const tinygltf::Node& n = rd.model.nodes[size_t(index)];
        const glm::dmat4 m = parent * node_matrix(n);
        if (n.mesh >= 0) {
            if (size_t(n.mesh) >= rd.model.meshes.size()) return rd.fail("nodes[" + std::to_string(index) + "]", "mesh index out of range");
            if (!mesh(n.mesh, m)) return false;
        }
        for (int c : n.children)
            if (!node(c, m, depth + 1)) return false;
        return true;
    }
};

}  // namespace

bool load_gltf_mesh(const std::string& path, GltfMesh* out, std::string* err) {
    *out = GltfMesh();
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, kGltfMaxFileBytes)) return false;
    const bool glb = file_extension(path) == "glb" || (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0);
    const size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash);
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks fs = {&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_bounded, &tinygltf::WriteWholeFile,
                                nullptr};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&no_image, nullptr);
    tinygltf::Model model;
    std::string terr, warn;
    const bool ok = glb ? loader.LoadBinaryFromMemory(&model, &terr, &warn, bytes.data(), unsigned(bytes.size()), dir)
                        : loader.LoadASCIIFromString(&model, &terr, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                     unsigned(bytes.size()), dir);
    if (!ok) {
        while (!terr.empty() && (terr.back() == '\n' || terr.back() == ' ')) terr.pop_back();
        *err = path + ": not a valid glTF 2.0 " + (glb ? "binary" : "file") + ": " + (terr.empty() ? "no reason given" : terr);
        return false;
    }
    if (!model.extensionsRequired.empty())
        return *err = path + ": needs extension " + model.extensionsRequired[0] + " (sepal reads uncompressed glTF only)",
               false;
    const Reader rd{model, path, err};
    Merger mg{rd, out, {}};
    bool good = true;
    if (!model.scenes.empty()) {
        const int s = model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size() ? model.defaultScene : 0;
        for (int n : model.scenes[size_t(s)].nodes) good = good && mg.node(n, glm::dmat4(1.0), 0);
    } else {
        for (size_t k = 0; k < model.meshes.size(); ++k) good = good && mg.mesh(int(k), glm::dmat4(1.0));
    }
    if (!good) return false;
    if (mg.all_indices.empty()) return *err = path + ": no triangles (no triangle primitive in the default scene)", false;
    out->indices.assign(mg.all_indices.begin(), mg.all_indices.end());
    return true;
}

}  // namespace sepal
