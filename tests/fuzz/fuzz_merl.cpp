// The MERL .binary reader (measured/merl.h). Inputs starting with 'M' drive the sample
// decoding (decode_merl_planes) on a small table: the rest of the input as three planes of
// (size - 1) / 24 cells, so the value checks run on every input (a whole 35 MB file took
// seconds per input under ASan: the full-size path is tested in tests/offline/measured);
// other inputs go to parse_merl as they are (the header and size checks). Every decoded
// cell is either missing or finite and non-negative, the counts add up, and an accepted
// table gives finite, non-negative values at every lookup.
#include <cmath>
#include <string>
#include <vector>

#include "fuzz/fuzz.h"
#include "measured/merl.h"

extern "C" int sepal_fuzz_merl(const uint8_t* data, size_t size) {
    const char* h = "merl";
    std::string err;
    if (size >= 1 && data[0] == 'M') {
        const size_t n = (size - 1) / 24;
        size_t seen = 0, missing = 0;
        sepal::MerlStats st;
        const bool ok = sepal::decode_merl_planes(
            data + 1, n,
            [&](size_t i, const glm::dvec3& rgb, bool miss) {
                sepal_fuzz::check(i == seen++, h, "cells out of order");
                missing += miss;
                for (int c = 0; c < 3; ++c)
                    sepal_fuzz::check(std::isfinite(rgb[c]) && rgb[c] >= 0 && (!miss || rgb[c] == 0), h,
                                      "a decoded value not finite, < 0, or set on a missing cell");
            },
            &st, &err);
        if (!ok) {
            sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
            return 0;
        }
        sepal_fuzz::check(seen == n && st.cells == n && st.missing_cells == missing &&
                              st.nan + st.inf + st.negative + st.huge >= missing,
                          h, "counts");
        return 0;
    }
    const std::vector<uint8_t> bytes(data, data + size);
    sepal::Tabulated table;
    sepal::MerlStats stats;
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
