// The MERL .binary reader (measured/merl.h, parse_merl). Inputs starting with 'M' become a
// whole file (the 90 x 90 x 180 header, then the rest of the input repeated over the 35 MB of
// samples), so the sample checks run too; other inputs go in as they are (the header
// checks). An accepted table gives finite, non-negative values at every lookup.
#include <cmath>
#include <string>
#include <vector>

#include "fuzz/fuzz.h"
#include "measured/merl.h"

extern "C" int sepal_fuzz_merl(const uint8_t* data, size_t size) {
    const char* h = "merl";
    std::vector<uint8_t> bytes;
    if (size >= 1 && data[0] == 'M') {
        bytes.resize(sepal::kMerlFileBytes);
        const uint32_t dims[3] = {uint32_t(sepal::kMerlThetaH), uint32_t(sepal::kMerlThetaD), uint32_t(sepal::kMerlPhiD)};
        for (int k = 0; k < 3; ++k)
            for (int b = 0; b < 4; ++b) bytes[size_t(4 * k + b)] = uint8_t(dims[k] >> (8 * b));
        const size_t n = size - 1;
        for (size_t i = 12; i < bytes.size(); ++i) bytes[i] = n ? data[1 + (i - 12) % n] : 0;
    } else {
        bytes.assign(data, data + size);
    }
    sepal::Tabulated table;
    sepal::MerlStats stats;
    std::string err;
    if (!sepal::parse_merl(bytes, "m.binary", &table, &stats, &err)) {
        sepal_fuzz::check(err.compare(0, 10, "m.binary: ") == 0 && err.size() > 10, h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(stats.cells == sepal::kMerlCells && stats.missing_cells <= stats.cells, h, "counts");
    for (size_t i = 0; i < sepal::kMerlCells; i += 9973) {
        glm::dvec3 wi, wo;
        sepal::merl_bin_center_dirs(i, &wi, &wo);
        const glm::dvec3 f = table.eval(wi, wo);
        for (int c = 0; c < 3; ++c) sepal_fuzz::check(std::isfinite(f[c]) && f[c] >= 0, h, "a lookup not finite or < 0");
    }
    return 0;
}
