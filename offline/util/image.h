// Images for offline tools: 8-bit PNG and float PFM in and out, and comparison.
//
// Usage:
//   sepal::Image img; std::string err;
//   if (!sepal::read_image("a.png", &img, &err)) { fprintf(stderr, "%s\n", err.c_str()); }
//   sepal::ImageDiff d = sepal::diff_images(a, b, /*threshold=*/2.0);
//
// Values are floats, top row first, interleaved channels (1 = grey, 3 = RGB, 4 = RGBA).
// PNG values are stored as byte/255, so 1.0 is white; PFM values are kept as they are.
// Comparisons work on RGB (grey is expanded, alpha is ignored) in 8-bit units: a
// difference of 1.0 in value is 255 units, for PNG and PFM alike.
// Limits: images up to 16384 x 16384 and a pixel budget per image (image_pixel_budget, by
// default 4096 x 4096 = 16,777,216 pixels, what a float RGBA image of 256 MiB holds), checked
// against the header before any pixel is decoded: a small compressed PNG can claim a huge
// image. PFM files with NaN or inf values are refused.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {

struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> data;  // width * height * channels

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), data(size_t(w) * h * c) {}
    float& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
    bool empty() const { return data.empty(); }
};

constexpr int kMaxImageSide = 16384;
constexpr int64_t kDefaultImagePixels = int64_t(4096) * 4096;
// The readers' pixel budget (process-wide; `sepal diff --max-pixels` raises it): an image of
// more pixels is refused before decoding, naming its size and the budget.
int64_t image_pixel_budget();
void set_image_pixel_budget(int64_t pixels);

// Decides the format by content (PNG signature or "PF"/"Pf" header).
bool read_image(const std::string& path, Image* out, std::string* err);
bool read_png(const std::string& path, Image* out, std::string* err);
bool read_pfm(const std::string& path, Image* out, std::string* err);
// read_image on bytes already in memory; `name` stands for the path in messages.
bool decode_image(const std::vector<uint8_t>& bytes, const std::string& name, Image* out, std::string* err);
// Radiance .hdr (RGBE) as linear RGB floats; negative or non-finite values are refused.
bool read_hdr(const std::string& path, Image* out, std::string* err);
// 8-bit PNG with the image's channel count. Values outside [0,1] are clipped (an 8-bit
// encoding has no other choice); *clipped, if given, receives how many values were.
bool write_png(const std::string& path, const Image& img, std::string* err,
               int64_t* clipped = nullptr);
bool write_pfm(const std::string& path, const Image& img, std::string* err);
// 16-bit PNG: channels 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA); samples row by row,
// top row first, interleaved. read_png16 reads any PNG into 16-bit samples (8-bit ones
// scaled by 257).
bool write_png16(const std::string& path, int width, int height, int channels, const std::vector<uint16_t>& samples,
                 std::string* err);
bool read_png16(const std::string& path, int* width, int* height, int* channels, std::vector<uint16_t>* samples,
                std::string* err);
// Writes by extension: .png or .pfm.
bool write_image(const std::string& path, const Image& img, std::string* err);

// Copies src into dst with its top-left corner at (x0, y0), clipped to dst; channels are
// converted (grey expanded to RGB, alpha dropped or set to 1). `scale` >= 1 repeats each
// pixel scale x scale times (nearest), for small maps in figures.
void paste_image(Image* dst, const Image& src, int x0, int y0, int scale = 1);

// 8-bit RGBA pixels (as read back from GL, top row first) to an RGBA image.
Image image_from_rgba8(const uint8_t* pixels, int width, int height);
// A copy with 3 channels (grey expanded, alpha dropped).
Image to_rgb(const Image& img);
// An RGB image as a framebuffer of bits[c] bits a channel shows it at best: each value clamped
// to [0, 1], rounded to the nearest of its 2^bits levels and widened back to 8 bits by
// repeating its bits, as a read-back returns it (5/6/5: the limit of an RGB565 framebuffer).
Image nearest_at_bits(const Image& rgb, const int bits[3]);

struct ImageDiff {
    bool comparable = false;   // false when sizes differ; reason says how
    std::string reason;
    double max_diff = 0;       // largest channel difference, 8-bit units
    double mse = 0;            // mean squared channel difference, 8-bit units^2
    double psnr = 0;           // 10 log10(255^2 / mse); +inf for identical images
    int64_t pixels = 0;
    int64_t pixels_over = 0;   // pixels with some channel differing by more than threshold
    double share_over = 0;     // pixels_over / pixels
    double threshold = 0;
};
ImageDiff diff_images(const Image& a, const Image& b, double threshold);

// Per-pixel largest channel difference mapped through a black-red-yellow-white ramp;
// full_scale (8-bit units) maps to white. Sizes must match.
Image diff_heatmap(const Image& a, const Image& b, double full_scale);
// The heatmap's ramp at t in [0, 1] (clamped): black, red, yellow, white.
void heat_colour(double t, float rgb[3]);

struct Tolerance {
    double max_diff = -1;   // per-channel threshold in 8-bit units; < 0: not set
    double max_share = -1;  // allowed share (0..1) of pixels over max_diff; < 0: not set
    double min_psnr = -1;   // dB; < 0: not set
};
// Applies the tolerance to a diff: returns true when it holds, else false with the
// failed checks in *why. max_diff alone means no pixel may exceed it (share 0);
// max_share alone uses a threshold of 0.
bool tolerance_holds(const ImageDiff& d, const Tolerance& t, std::string* why);
// Threshold the diff should be computed with for this tolerance.
double tolerance_threshold(const Tolerance& t);
// The tolerance in words ("at most 1% of pixels over 10 (8-bit units); PSNR >= 40 dB"),
// or "" when none of its checks is set.
std::string describe_tolerance(const Tolerance& t);

}  // namespace sepal
