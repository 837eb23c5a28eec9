// Wavefront OBJ loading from memory into caller-provided storage (see sepal_rt.h).
// Hand-written rather than a library: the runtime allocates nothing and must not depend
// on the C locale (strtof reads "1,5" in some locales), which common OBJ loaders do.
#include <math.h>
#include <string.h>

#include "internal.h"

namespace {

struct Cursor {
    const char* p;
    const char* end;
    int line;
};

bool at_line_end(const Cursor& c) { return c.p >= c.end || *c.p == '\n' || *c.p == '\r'; }

void skip_spaces(Cursor& c) {
    while (c.p < c.end && (*c.p == ' ' || *c.p == '\t')) ++c.p;
}

// A line ends at LF, CRLF or a lone CR (classic Mac OS files).
void next_line(Cursor& c) {
    while (c.p < c.end && *c.p != '\n' && *c.p != '\r') ++c.p;
    if (c.p < c.end && *c.p == '\r') ++c.p;
    if (c.p < c.end && *c.p == '\n') ++c.p;
    ++c.line;
}

// The first line, past a UTF-8 byte order mark (editors on Windows write one).
Cursor first_line(const char* text, size_t length) {
    Cursor c = {text, text + length, 1};
    if (length >= 3 && (uint8_t)text[0] == 0xEF && (uint8_t)text[1] == 0xBB && (uint8_t)text[2] == 0xBF) c.p += 3;
    return c;
}

// Locale-independent decimal float: [sign] digits [. digits] [(e|E) [sign] digits].
bool parse_float(Cursor& c, float* out) {
    skip_spaces(c);
    const char* p = c.p;
    double sign = 1.0;
    if (p < c.end && (*p == '-' || *p == '+')) sign = (*p++ == '-') ? -1.0 : 1.0;
    double value = 0.0;
    int digits = 0;
    while (p < c.end && *p >= '0' && *p <= '9') value = value * 10.0 + (*p++ - '0'), ++digits;
    if (p < c.end && *p == '.') {
        ++p;
        double scale = 0.1;
        while (p < c.end && *p >= '0' && *p <= '9') value += (*p++ - '0') * scale, scale *= 0.1, ++digits;
    }
    if (digits == 0) return false;
    if (p < c.end && (*p == 'e' || *p == 'E')) {
        ++p;
        int esign = 1, e = 0, edigits = 0;
        if (p < c.end && (*p == '-' || *p == '+')) esign = (*p++ == '-') ? -1 : 1;
        while (p < c.end && *p >= '0' && *p <= '9') {
            if (e < 1000) e = e * 10 + (*p - '0');
            ++p, ++edigits;
        }
        if (edigits == 0) return false;
        value *= pow(10.0, esign * e);
    }
    if (p < c.end && !(*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) return false;
    const float f = (float)(sign * value);
    if (!isfinite(f)) return false;
    c.p = p;
    *out = f;
    return true;
}

// An index; one beyond 10^9 (no mesh has that many of anything) becomes 10^9 + 1, out of
// range whatever the counts: messages quote the text as written, never the clamped value.
bool parse_int(const char*& p, const char* end, long* out) {
    long sign = 1, v = 0;
    int digits = 0;
    if (p < end && *p == '-') sign = -1, ++p;
    while (p < end && *p >= '0' && *p <= '9') {
        v = v > 100000000 ? 1000000001 : v * 10 + (*p - '0');
        ++p, ++digits;
    }
    *out = sign * v;
    return digits > 0;
}

// "v", "vt", "vn", "f" or other: the keyword at the start of a line.
enum Keyword { kOther, kV, kVt, kVn, kF };
Keyword keyword(Cursor& c) {
    skip_spaces(c);
    const char* p = c.p;
    size_t n = 0;
    while (p + n < c.end && p[n] != ' ' && p[n] != '\t' && p[n] != '\n' && p[n] != '\r') ++n;
    c.p += n;
    if (n == 1 && p[0] == 'v') return kV;
    if (n == 2 && p[0] == 'v' && p[1] == 't') return kVt;
    if (n == 2 && p[0] == 'v' && p[1] == 'n') return kVn;
    if (n == 1 && p[0] == 'f') return kF;
    return kOther;
}

// Counts the corners of a face line without resolving them.
int count_corners(Cursor c) {
    int n = 0;
    while (true) {
        skip_spaces(c);
        if (at_line_end(c)) return n;
        ++n;
        while (!at_line_end(c) && *c.p != ' ' && *c.p != '\t') ++c.p;
    }
}

struct Corner {
    int p, t, n;  // 0-based; -1 when absent
};

// Parses "p", "p/t", "p//n" or "p/t/n"; resolves negative (relative) indices.
bool parse_corner(Cursor& c, int np, int nt, int nn, Corner* out, sepal_error* err) {
    skip_spaces(c);
    const char* p = c.p;
    long idx[3] = {0, 0, 0};
    bool has[3] = {false, false, false};
    const char* text[3] = {p, p, p};  // each index as written, for messages
    int text_len[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        if (k > 0) {
            if (p >= c.end || *p != '/') break;
            ++p;
        }
        if (p < c.end && *p == '/') continue;  // empty field ("p//n")
        text[k] = p;
        has[k] = parse_int(p, c.end, &idx[k]);
        text_len[k] = (int)(p - text[k]);
        if (!has[k] && k == 0) break;
    }
    c.p = p;
    const int counts[3] = {np, nt, nn};
    int resolved[3] = {-1, -1, -1};
    for (int k = 0; k < 3; ++k) {
        if (!has[k]) continue;
        const long i = idx[k] < 0 ? counts[k] + idx[k] : idx[k] - 1;
        if (idx[k] == 0 || i < 0 || i >= counts[k]) {
            srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                      "obj line %d: %s index %.*s out of range (1..%d defined so far)", c.line,
                      k == 0 ? "position" : k == 1 ? "texcoord" : "normal", text_len[k] < 40 ? text_len[k] : 40,
                      text[k], counts[k]);
            return false;
        }
        resolved[k] = (int)i;
    }
    if (!has[0]) {
        srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj line %d: malformed face corner", c.line);
        return false;
    }
    if (!at_line_end(c) && *c.p != ' ' && *c.p != '\t') {
        srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj line %d: malformed face corner", c.line);
        return false;
    }
    *out = Corner{resolved[0], resolved[1], resolved[2]};
    return true;
}

size_t hash_capacity(int max_vertices) {
    size_t cap = 16;
    while (cap < (size_t)max_vertices * 2) cap <<= 1;
    return cap;
}

// Scratch layout, all 4-byte aligned: positions (3f), texcoords (2f), normals (3f),
// per-position normal sums (3f), per-vertex bitangent sums (3f), per-vertex keys (3i),
// hash table (int, -1 = empty).
struct Scratch {
    float* positions;
    float* texcoords;
    float* normals;
    float* position_normals;
    float* bitangents;
    int* keys;
    int* table;
    size_t table_size;
};

size_t scratch_layout(const sepal_obj_info& info, void* base, Scratch* s) {
    const size_t cap = hash_capacity(info.max_vertices);
    const size_t counts[7] = {(size_t)info.positions * 3, (size_t)info.texcoords * 2,
                              (size_t)info.normals * 3,   (size_t)info.positions * 3,
                              (size_t)info.max_vertices * 3, (size_t)info.max_vertices * 3,
                              cap};
    char* p = (char*)base;
    size_t offset = 0;
    void* ptrs[7];
    for (int i = 0; i < 7; ++i) {
        ptrs[i] = p ? p + offset : nullptr;
        offset += counts[i] * 4;
    }
    if (s) {
        s->positions = (float*)ptrs[0];
        s->texcoords = (float*)ptrs[1];
        s->normals = (float*)ptrs[2];
        s->position_normals = (float*)ptrs[3];
        s->bitangents = (float*)ptrs[4];
        s->keys = (int*)ptrs[5];
        s->table = (int*)ptrs[6];
        s->table_size = cap;
    }
    return offset;
}

void cross3(const float* a, const float* b, float* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}
float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
bool normalize3(float* v) {
    const float l = sqrtf(dot3(v, v));
    if (!(l > 1e-20f) || !isfinite(l)) return false;
    v[0] /= l, v[1] /= l, v[2] /= l;
    return true;
}

// Any unit vector perpendicular to n (n unit).
void perpendicular(const float* n, float* t) {
    const float axis[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
    const float d = dot3(axis, n);
    for (int k = 0; k < 3; ++k) t[k] = axis[k] - d * n[k];
    normalize3(t);
}

}  // namespace

extern "C" sepal_result sepal_obj_measure(const char* text, size_t length, sepal_obj_info* info,
                                      sepal_error* err) {
    if ((!text && length > 0) || !info) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj: text or info is NULL");
    if (length == 0) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj: the file is empty (no faces)");
    memset(info, 0, sizeof *info);
    long corners = 0, triangles = 0;
    for (Cursor c = first_line(text, length); c.p < c.end; next_line(c)) {
        switch (keyword(c)) {
            case kV: ++info->positions; break;
            case kVt: ++info->texcoords; break;
            case kVn: ++info->normals; break;
            case kF: {
                const int k = count_corners(c);
                if (k < 3)
                    return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                     "obj line %d: a face needs at least 3 corners, has %d", c.line, k);
                corners += k;
                triangles += k - 2;
                break;
            }
            default: break;
        }
        if (info->positions > 10000000 || corners > 10000000)
            return srt::fail(err, SEPAL_ERR_CAPACITY, "obj: more than 10^7 positions or corners");
    }
    if (triangles == 0) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj: no faces");
    info->triangles = (int)triangles;
    info->max_vertices = (int)corners;
    info->max_indices = (int)(triangles * 3);
    info->scratch_bytes = scratch_layout(*info, nullptr, nullptr);
    return srt::ok(err);
}

extern "C" sepal_result sepal_obj_load(const char* text, size_t length, sepal_mesh* mesh, void* scratch,
                                   size_t scratch_bytes, sepal_obj_stats* stats, sepal_error* err) {
    sepal_obj_info info;
    sepal_result r = sepal_obj_measure(text, length, &info, err);
    if (r != SEPAL_OK) return r;
    if (!mesh || !mesh->vertices || !mesh->indices || !scratch)
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj: mesh storage or scratch is NULL");
    if (scratch_bytes < info.scratch_bytes || mesh->index_count < info.max_indices)
        return srt::fail(err, SEPAL_ERR_CAPACITY,
                         "obj: needs %zu scratch bytes and %d indices, given %zu and %d",
                         info.scratch_bytes, info.max_indices, scratch_bytes, mesh->index_count);
    Scratch s;
    scratch_layout(info, scratch, &s);
    for (size_t i = 0; i < s.table_size; ++i) s.table[i] = -1;
    memset(s.position_normals, 0, (size_t)info.positions * 3 * sizeof(float));
    sepal_obj_stats st = {};
    int np = 0, nt = 0, nn = 0, nv = 0, ni = 0;
    const int vertex_capacity = mesh->vertex_count < 65535 ? mesh->vertex_count : 65535;
    for (Cursor c = first_line(text, length); c.p < c.end; next_line(c)) {
        const Keyword k = keyword(c);
        if (k == kV || k == kVt || k == kVn) {
            float* dst = k == kV ? s.positions + 3 * np++ : k == kVt ? s.texcoords + 2 * nt++ : s.normals + 3 * nn++;
            const int want = k == kVt ? 2 : 3;
            for (int i = 0; i < want; ++i)
                if (!parse_float(c, dst + i))
                    return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT,
                                     "obj line %d: expected %d finite numbers", c.line, want);
            if (k == kVn && !normalize3(dst))
                return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "obj line %d: zero-length normal", c.line);
        } else if (k == kF) {
            int first = -1, prev = -1;
            for (int corner = 0; !at_line_end((skip_spaces(c), c)); ++corner) {
                Corner cr;
                if (!parse_corner(c, np, nt, nn, &cr, err)) return err ? err->code : SEPAL_ERR_INVALID_ARGUMENT;
                // Find or add the unified vertex for this (p, t, n) triple.
                size_t h = ((size_t)cr.p * 73856093u ^ (size_t)(cr.t + 1) * 19349663u ^
                            (size_t)(cr.n + 1) * 83492791u) & (s.table_size - 1);
                int vi = -1;
                while (s.table[h] >= 0) {
                    const int* key = s.keys + 3 * s.table[h];
                    if (key[0] == cr.p && key[1] == cr.t && key[2] == cr.n) {
                        vi = s.table[h];
                        break;
                    }
                    h = (h + 1) & (s.table_size - 1);
                }
                if (vi < 0) {
                    if (nv >= vertex_capacity)
                        return srt::fail(err, SEPAL_ERR_CAPACITY,
                                         "obj line %d: more than %d unique vertices (16-bit indices)",
                                         c.line, vertex_capacity);
                    vi = nv++;
                    s.table[h] = vi;
                    int* key = s.keys + 3 * vi;
                    key[0] = cr.p, key[1] = cr.t, key[2] = cr.n;
                    sepal_vertex& v = mesh->vertices[vi];
                    memset(&v, 0, sizeof v);
                    memcpy(v.position, s.positions + 3 * cr.p, 3 * sizeof(float));
                    if (cr.t >= 0) memcpy(v.uv, s.texcoords + 2 * cr.t, 2 * sizeof(float));
                    if (cr.n >= 0) memcpy(v.normal, s.normals + 3 * cr.n, 3 * sizeof(float));
                }
                if (corner == 0) {
                    first = vi;
                } else if (corner >= 2) {  // fan: (first, prev, this)
                    mesh->indices[ni++] = (uint16_t)first;
                    mesh->indices[ni++] = (uint16_t)prev;
                    mesh->indices[ni++] = (uint16_t)vi;
                }
                prev = vi;
            }
        }
    }
    // Face normals (area-weighted) summed per position, for vertices without a normal.
    memset(s.bitangents, 0, (size_t)nv * 3 * sizeof(float));
    for (int i = 0; i < nv; ++i) memset(mesh->vertices[i].tangent, 0, sizeof mesh->vertices[i].tangent);
    for (int t = 0; t < ni; t += 3) {
        const sepal_vertex* v[3] = {&mesh->vertices[mesh->indices[t]], &mesh->vertices[mesh->indices[t + 1]],
                                  &mesh->vertices[mesh->indices[t + 2]]};
        float e1[3], e2[3], fn[3];
        for (int k = 0; k < 3; ++k) e1[k] = v[1]->position[k] - v[0]->position[k], e2[k] = v[2]->position[k] - v[0]->position[k];
        cross3(e1, e2, fn);
        if (!(dot3(fn, fn) > 0.0f)) ++st.degenerate_triangles;
        for (int j = 0; j < 3; ++j) {
            float* pn = s.position_normals + 3 * s.keys[3 * mesh->indices[t + j]];
            for (int k = 0; k < 3; ++k) pn[k] += fn[k];
        }
        // Tangent and bitangent from the UV gradients (Lengyel 2001).
        const float du1 = v[1]->uv[0] - v[0]->uv[0], dv1 = v[1]->uv[1] - v[0]->uv[1];
        const float du2 = v[2]->uv[0] - v[0]->uv[0], dv2 = v[2]->uv[1] - v[0]->uv[1];
        const float det = du1 * dv2 - du2 * dv1;
        if (!(fabsf(det) > 1e-12f)) continue;
        float tan[3], bit[3];
        for (int k = 0; k < 3; ++k) {
            tan[k] = (e1[k] * dv2 - e2[k] * dv1) / det;
            bit[k] = (e2[k] * du1 - e1[k] * du2) / det;
        }
        for (int j = 0; j < 3; ++j) {
            sepal_vertex& vx = mesh->vertices[mesh->indices[t + j]];
            float* b = s.bitangents + 3 * mesh->indices[t + j];
            for (int k = 0; k < 3; ++k) vx.tangent[k] += tan[k], b[k] += bit[k];
        }
    }
    for (int i = 0; i < nv; ++i) {
        sepal_vertex& v = mesh->vertices[i];
        const int* key = s.keys + 3 * i;
        if (key[2] < 0) {
            memcpy(v.normal, s.position_normals + 3 * key[0], 3 * sizeof(float));
            ++st.computed_normals;
            if (!normalize3(v.normal)) v.normal[0] = 0, v.normal[1] = 0, v.normal[2] = 1;
        }
        float* t = v.tangent;
        const float d = dot3(t, v.normal);
        for (int k = 0; k < 3; ++k) t[k] -= d * v.normal[k];
        if (key[1] < 0 || !normalize3(t)) {
            perpendicular(v.normal, t);
            ++st.fallback_tangents;
            t[3] = 1.0f;
            continue;
        }
        float nxt[3];
        cross3(v.normal, t, nxt);
        t[3] = dot3(nxt, s.bitangents + 3 * i) < 0.0f ? -1.0f : 1.0f;
    }
    mesh->vertex_count = nv;
    mesh->index_count = ni;
    if (stats) *stats = st;
    return srt::ok(err);
}
