// PFM through the offline image reader (util/image.h, decode_image): an accepted image has
// its size in range and only finite values.
#include <cmath>
#include <string>
#include <vector>

#include "fuzz/fuzz.h"
#include "util/image.h"

extern "C" int sepal_fuzz_pfm(const uint8_t* data, size_t size) {
    const char* h = "pfm";
    std::vector<uint8_t> bytes(data, data + size);
    sepal::Image img;
    std::string err;
    if (!sepal::decode_image(bytes, "i.pfm", &img, &err)) {
        sepal_fuzz::check(err.compare(0, 7, "i.pfm: ") == 0 && err.size() > 7, h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(img.width >= 1 && img.height >= 1 && img.width <= sepal::kMaxImageSide &&
                          img.height <= sepal::kMaxImageSide && (img.channels == 1 || img.channels == 3),
                      h, "size out of range");
    sepal_fuzz::check(img.data.size() == size_t(img.width) * img.height * img.channels, h, "data size");
    for (float v : img.data) sepal_fuzz::check(std::isfinite(v), h, "a non-finite value");
    return 0;
}
