// PNG through the offline image reader (util/image.h, decode_image: its chunk check, then
// stb_image): an accepted image has its size in range, width x height x channels values in
// [0,1]; a refusal says why.
#include <cstring>
#include <string>
#include <vector>

#include "fuzz/fuzz.h"
#include "sepal/sepal_asset.h"
#include "util/image.h"

namespace {

void decode(const std::vector<uint8_t>& bytes) {
    const char* h = "png";
    sepal::Image img;
    std::string err;
    if (!sepal::decode_image(bytes, "i.png", &img, &err)) {
        sepal_fuzz::check(err.compare(0, 7, "i.png: ") == 0 && err.size() > 7, h, "a refusal without a message");
        sepal_fuzz::check(err.back() != ' ', h, "a message without a reason");
        return;
    }
    sepal_fuzz::check(img.width >= 1 && img.height >= 1 && img.width <= sepal::kMaxImageSide &&
                          img.height <= sepal::kMaxImageSide && img.channels >= 1 && img.channels <= 4,
                      h, "size out of range");
    sepal_fuzz::check(img.data.size() == size_t(img.width) * img.height * img.channels, h, "data size");
    for (float v : img.data) sepal_fuzz::check(v >= 0.0f && v <= 1.0f, h, "value outside [0,1]");
}

}  // namespace

// The input is a PNG without its 8-byte signature (forced, so every input reaches the PNG
// path); it is decoded as it is, then with every chunk's CRC recomputed, so mutations reach
// the chunk contents behind the reader's CRC check.
extern "C" int sepal_fuzz_png(const uint8_t* data, size_t size) {
    static const uint8_t kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<uint8_t> bytes(8 + size);
    std::memcpy(bytes.data(), kSig, 8);
    if (size) std::memcpy(bytes.data() + 8, data, size);
    decode(bytes);
    for (size_t pos = 8; bytes.size() - pos >= 12;) {
        const uint32_t length = uint32_t(bytes[pos]) << 24 | uint32_t(bytes[pos + 1]) << 16 |
                                uint32_t(bytes[pos + 2]) << 8 | bytes[pos + 3];
        if (length > bytes.size() - pos - 12) break;
        const uint32_t crc = sepal_crc32(0, &bytes[pos + 4], size_t(length) + 4);
        for (int k = 0; k < 4; ++k) bytes[pos + 8 + length + size_t(k)] = uint8_t(crc >> (24 - 8 * k));
        pos += size_t(length) + 12;
    }
    decode(bytes);
    return 0;
}
