#include "sampling/sampler_file.h"

#include <cstring>

#include "util/io.h"

namespace sepal {

double masses_to_cdf(const double* masses, int n, float* cdf) {
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += masses[i] > 0 ? masses[i] : 0.0;
    double acc = 0;
    cdf[0] = 0.0f;
    for (int i = 0; i < n; ++i) {
        acc += sum > 0 ? (masses[i] > 0 ? masses[i] : 0.0) : 1.0;
        const double c = acc / (sum > 0 ? sum : double(n));
        cdf[i + 1] = float(c < 1.0 ? c : 1.0);
        if (cdf[i + 1] < cdf[i]) cdf[i + 1] = cdf[i];  // rounding can never make it fall
    }
    cdf[n] = 1.0f;
    return sum;
}

bool encode_sampler(const SamplerData& d, std::vector<uint8_t>* out, std::string* err) {
    uint64_t off[SEPAL_SMP_ARRAY_COUNT], sizes[SEPAL_SMP_ARRAY_COUNT];
    const uint64_t size = sepal_sampler_layout(d.kind, &d.desc, off, sizes);
    if (size == 0 || size > SEPAL_SMP_MAX_FILE_BYTES) {
        if (err) *err = "sampler: counts out of range or over " + std::to_string(SEPAL_SMP_MAX_FILE_BYTES) + " bytes";
        return false;
    }
    std::vector<uint8_t> file(size, 0);
    std::memcpy(file.data() + sizeof(sepal_smp_header), &d.desc, sizeof d.desc);
    struct Part {
        int array;
        const void* data;
        size_t bytes;
    };
    const Part parts[] = {
        {SEPAL_SMP_ARRAY_Z_EDGES, d.z_edges.data(), d.z_edges.size() * 4},
        {SEPAL_SMP_ARRAY_F, d.F.data(), d.F.size() * 4},
        {SEPAL_SMP_ARRAY_U_CDF, d.u_cdf.data(), d.u_cdf.size() * 4},
        {SEPAL_SMP_ARRAY_V_CDF, d.v_cdf.data(), d.v_cdf.size() * 4},
        {SEPAL_SMP_ARRAY_COLOUR_A, d.colour_a.data(), d.colour_a.size() * 4},
        {SEPAL_SMP_ARRAY_COLOUR_B, d.colour_b.data(), d.colour_b.size() * 4},
        {SEPAL_SMP_ARRAY_COLOUR_C, d.colour_c.data(), d.colour_c.size() * 4},
        {SEPAL_SMP_ARRAY_LOBES, d.lobes.data(), d.lobes.size() * sizeof(sepal_smp_lobe)},
        {SEPAL_SMP_ARRAY_TABLES, d.tables.data(), d.tables.size() * 4},
    };
    // Each array must have exactly the size the layout gives it.
    for (const Part& p : parts) {
        const uint64_t at = off[p.array];
        if (p.bytes != sizes[p.array]) {
            if (err)
                *err = "sampler: array " + std::to_string(p.array) + " holds " + std::to_string(p.bytes) +
                       " bytes, the layout has " + std::to_string(sizes[p.array]);
            return false;
        }
        if (!p.bytes) continue;
        std::memcpy(file.data() + at, p.data, p.bytes);
    }
    sepal_smp_header h{};
    std::memcpy(h.magic, SEPAL_SMP_MAGIC, 8);
    h.version_major = SEPAL_SMP_VERSION_MAJOR;
    // The lowest version holding the file's fields (1.1: the diffuse part, 1.2: an axis, 1.3: a view or mirror axis),
    // so older samplers keep their bytes.
    const bool diffuse = d.desc.diffuse[0] != 0.0f || d.desc.diffuse[1] != 0.0f || d.desc.diffuse[2] != 0.0f;
    h.version_minor = d.desc.axis >= SEPAL_SMP_AXIS_T_VIEW ? 3
                      : d.desc.axis != SEPAL_SMP_AXIS_N                                          ? 2
                      : diffuse                                                                  ? 1
                                                                                                 : 0;
    h.header_bytes = sizeof h;
    h.file_bytes = size;
    h.kind = d.kind;
    h.payload_crc = sepal_crc32(0, file.data() + sizeof h, size - sizeof h);
    h.header_crc = sepal_crc32(0, &h, sizeof h);
    std::memcpy(file.data(), &h, sizeof h);
    Sampler check;  // the runtime's reader is the judge of what a valid sampler is
    std::string why;
    if (!check.load(file.data(), file.size(), &why)) {
        if (err) *err = "sampler encoder produced an invalid file: " + why;
        return false;
    }
    *out = std::move(file);
    return true;
}

bool write_sampler(const std::string& path, const SamplerData& d, std::string* err) {
    std::vector<uint8_t> bytes;
    return encode_sampler(d, &bytes, err) && write_file_atomic(path, bytes.data(), bytes.size(), err);
}

bool Sampler::load(const uint8_t* bytes, size_t size, std::string* err) {
    storage_.assign((size + 7) / 8, 0);
    std::memcpy(storage_.data(), bytes, size);
    sepal_error e{};
    if (sepal_sampler_parse(storage_.data(), size, &s_, &e) != SEPAL_OK) {
        if (err) *err = e.message;
        storage_.clear();
        size_ = 0;
        return false;
    }
    size_ = size;
    return true;
}

bool Sampler::build(const SamplerData& d, std::string* err) {
    std::vector<uint8_t> bytes;
    return encode_sampler(d, &bytes, err) && load(bytes.data(), bytes.size(), err);
}

bool Sampler::read(const std::string& path, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, SEPAL_SMP_MAX_FILE_BYTES + 1ull)) return false;
    if (!load(bytes.data(), bytes.size(), err)) {
        if (err) *err = path + ": " + *err;
        return false;
    }
    return true;
}

}  // namespace sepal
