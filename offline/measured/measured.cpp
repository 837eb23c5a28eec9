#include "measured/measured.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

#include "measured/cornell.h"
#include "util/io.h"
#include "measured/merl.h"

namespace sepal {

namespace {
bool looks_like_merl(const std::vector<uint8_t>& b) {
    if (b.size() == kMerlFileBytes) return true;
    if (b.size() < 12) return false;
    // 90, 90, 180 as little- or big-endian int32.
    static const uint8_t le[12] = {90, 0, 0, 0, 90, 0, 0, 0, 180, 0, 0, 0};
    static const uint8_t be[12] = {0, 0, 0, 90, 0, 0, 0, 90, 0, 0, 0, 180};
    bool is_le = true, is_be = true;
    for (int k = 0; k < 12; ++k) {
        is_le = is_le && b[k] == le[k];
        is_be = is_be && b[k] == be[k];
    }
    return is_le || is_be;
}
// BRDF Explorer (Disney) also uses .brdf, for GLSL shader text: "analytic", then
// "::begin parameters" ... "::begin shader" blocks. Cornell files are numbers and '#' comments.
bool looks_like_brdf_explorer(const std::vector<uint8_t>& b) {
    const std::string head(b.begin(), b.begin() + long(std::min<size_t>(b.size(), 1 << 16)));
    size_t i = 0;
    while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
    return head.compare(i, 8, "analytic") == 0 || head.find("::begin shader") != std::string::npos ||
           head.find("::begin parameters") != std::string::npos;
}
}  // namespace

std::unique_ptr<Brdf> load_measured_brdf(const std::string& path, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 64u << 20)) return nullptr;
    if (looks_like_merl(bytes) || file_extension(path) == "binary")
        return make_merl_brdf(bytes, path, err);
    if (looks_like_brdf_explorer(bytes)) {
        if (err)
            *err = path + ": a BRDF Explorer file (GLSL shader text: 'analytic', '::begin shader'), not Cornell "
                          "measured data. sepal reads measured data (Cornell .brdf, MERL .binary); for an analytic "
                          "model give a spec such as blinn:n=20 (sepal info --models)";
        return nullptr;
    }
    return make_cornell_brdf(std::string(bytes.begin(), bytes.end()), path, err);
}

}  // namespace sepal
