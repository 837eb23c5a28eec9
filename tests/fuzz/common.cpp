// Helpers shared by the fuzz harnesses (fuzz.h).
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fuzz/fuzz.h"
#include "sepal/sepal_format.h"

namespace sepal_fuzz {

void check(bool ok, const char* harness, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "fuzz %s: %s\n", harness, what);
    std::abort();
}

void fix_asset_checksums(std::vector<uint8_t>* bytes) {
    std::vector<uint8_t>& b = *bytes;
    if (b.size() < sizeof(sepal_fmt_header)) return;
    sepal_fmt_header h;
    std::memcpy(&h, b.data(), sizeof h);
    h.file_bytes = b.size();
    const size_t room = (b.size() - sizeof h) / sizeof(sepal_fmt_chunk);
    const size_t count = h.chunk_count < room ? h.chunk_count : room;
    for (size_t i = 0; i < count; ++i) {
        uint8_t* entry = b.data() + sizeof h + i * sizeof(sepal_fmt_chunk);
        sepal_fmt_chunk c;
        std::memcpy(&c, entry, sizeof c);
        if (c.offset > b.size() || c.size > b.size() - c.offset) continue;
        c.crc = sepal_crc32(0, b.data() + c.offset, size_t(c.size));
        std::memcpy(entry, &c, sizeof c);
    }
    h.header_crc = 0;
    std::memcpy(b.data(), &h, sizeof h);
    const size_t table = h.chunk_count <= room ? size_t(h.chunk_count) * sizeof(sepal_fmt_chunk) : 0;
    uint32_t crc = sepal_crc32(0, b.data(), sizeof h);
    crc = sepal_crc32(crc, b.data() + sizeof h, table);
    h.header_crc = crc;
    std::memcpy(b.data(), &h, sizeof h);
}

}  // namespace sepal_fuzz
