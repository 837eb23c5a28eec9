// Sampler files (.smp, sepal_sampler.h: sepal_sampler_parse). The checksums are fixed up first
// (file size, payload CRC, header CRC) so mutated fields reach the checks behind them. An
// accepted sampler keeps the header's promises at every view: sample() gives a unit direction
// and a finite pdf >= 0, pdf() and eval() finite values >= 0: never NaN or inf.
#include <cmath>
#include <cstring>
#include <vector>

#include "fuzz/fuzz.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_sampler.h"

extern "C" int sepal_fuzz_smp(const uint8_t* data, size_t size) {
    const char* h = "smp";
    std::vector<uint8_t> b(data, data + size);
    b.resize((b.size() + 3) / 4 * 4);  // the parser wants float-aligned arrays: so does its caller
    if (b.size() >= sizeof(sepal_smp_header)) {
        sepal_smp_header hd;
        std::memcpy(&hd, b.data(), sizeof hd);
        hd.file_bytes = b.size();
        hd.payload_crc = sepal_crc32(0, b.data() + sizeof hd, b.size() - sizeof hd);
        hd.header_crc = 0;
        std::memcpy(b.data(), &hd, sizeof hd);
        hd.header_crc = sepal_crc32(0, b.data(), sizeof hd);
        std::memcpy(b.data(), &hd, sizeof hd);
    }
    sepal_sampler s;
    sepal_error err = {};
    if (sepal_sampler_parse(b.data(), b.size(), &s, &err) != SEPAL_OK) {
        sepal_fuzz::check(err.message[0] != 0, h, "a refusal without a message");
        return 0;
    }
    const float views[][3] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {0, -0.995f, 0.0998f}, {0.48f, 0.36f, 0.8f}, {0, 0, -1}};
    const float us[][2] = {{0.01f, 0.5f}, {0.37f, 0.91f}, {0.5f, 0.02f}, {0.77f, 0.33f}, {0.999f, 0.999f}};
    for (const float* wo : views) {
        sepal_sampler_view v;
        sepal_sampler_set_view(&s, wo, &v);
        sepal_fuzz::check(std::isfinite(v.defensive) && v.defensive >= 0 && v.defensive <= 1, h,
                          "the view's cosine share is outside [0, 1]");
        for (const float* u : us) {
            float wi[3], pdf = -1;
            const int r = sepal_sampler_sample(&v, u, wi, &pdf);
            sepal_fuzz::check(std::isfinite(pdf) && pdf >= 0, h, "sample() gave a pdf that is not finite or < 0");
            if (r < 0) continue;
            const float len = std::sqrt(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
            sepal_fuzz::check(std::isfinite(len) && std::fabs(len - 1) < 1e-3f, h, "sample() gave no unit direction");
            const float p2 = sepal_sampler_pdf(&v, wi);
            sepal_fuzz::check(std::isfinite(p2) && p2 >= 0, h, "pdf() not finite or < 0");
            float rgb[3];
            sepal_sampler_eval(&v, wi, rgb);
            for (float c : rgb) sepal_fuzz::check(std::isfinite(c) && c >= 0, h, "eval() not finite or < 0");
        }
    }
    return 0;
}
