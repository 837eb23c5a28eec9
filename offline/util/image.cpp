#include "util/image.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <atomic>
#include <limits>

#include "util/io.h"

// stb_image / stb_image_write are the project's PNG codec (Debian's libstb-dev), compiled
// once in third_party/stb/stb.cpp.
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "sepal/sepal_asset.h"  // sepal_crc32: PNG's CRC-32

// stb_image_write's deflate (defined in its implementation, not declared by its header):
// the 16-bit PNG writer below feeds it the filtered rows.
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int data_len, int* out_len, int quality);

namespace sepal {
namespace {

constexpr uint64_t kMaxImageFileBytes = uint64_t(1) << 32;

bool fail(std::string* err, const std::string& msg) {
    if (err) *err = msg;
    return false;
}

std::atomic<int64_t> g_pixel_budget{kDefaultImagePixels};

// The side limit and the pixel budget, from the header's size (before decoding).
bool check_image_size(const std::string& path, const char* format, int64_t w, int64_t h, std::string* err) {
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
        return fail(err, path + ": " + format + " size " + std::to_string(w) + "x" + std::to_string(h) +
                             " out of range 1.." + std::to_string(kMaxImageSide));
    const int64_t budget = g_pixel_budget;
    if (w * h > budget)
        return fail(err, path + ": " + format + " of " + std::to_string(w) + "x" + std::to_string(h) + " = " +
                             std::to_string(w * h) + " pixels is over the pixel budget of " + std::to_string(budget) +
                             " (sepal diff --max-pixels raises it)");
    return true;
}

bool is_png(const std::vector<uint8_t>& b) {
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return b.size() >= 8 && std::memcmp(b.data(), sig, 8) == 0;
}

bool is_pfm(const std::vector<uint8_t>& b) {
    return b.size() >= 3 && b[0] == 'P' && (b[1] == 'F' || b[1] == 'f') &&
           std::isspace(b[2]);
}

uint32_t load_u32be(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

// The chunk structure of a PNG, checked before stb_image, whose messages cannot say where a
// file is cut ("corrupt PNG:" with no reason) or that it is too large ("unknown image type"):
// IHDR first with a size in range, every chunk inside the file with a matching CRC, and IEND.
bool check_png_chunks(const std::string& path, const std::vector<uint8_t>& b, std::string* err) {
    size_t pos = 8;
    for (int index = 0;; ++index) {
        if (b.size() - pos < 12)
            return fail(err, path + ": truncated PNG: the file ends at byte " + std::to_string(b.size()) +
                                 (index == 0 ? " before its IHDR chunk" : ", before the IEND chunk"));
        const uint32_t length = load_u32be(&b[pos]);
        char type[5] = {};
        for (int k = 0; k < 4; ++k) {
            const uint8_t c = b[pos + 4 + size_t(k)];
            type[k] = std::isalpha(c) ? char(c) : '?';
        }
        const std::string where = "chunk '" + std::string(type) + "' at byte " + std::to_string(pos);
        if (length > b.size() - pos - 12)
            return fail(err, path + ": truncated PNG: " + where + " needs " + std::to_string(uint64_t(length) + 12) +
                                 " bytes, the file has " + std::to_string(b.size() - pos) + " from there");
        if (load_u32be(&b[pos + 8 + length]) != sepal_crc32(0, &b[pos + 4], size_t(length) + 4))
            return fail(err, path + ": corrupt PNG: " + where + " fails its CRC check");
        // stb_image names an unknown critical chunk by its raw type bytes: a NUL among them
        // cut its message to "ID " (found by make fuzz). Chunk types are 4 ASCII letters.
        if (std::string(type).find('?') != std::string::npos) {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%02x %02x %02x %02x", b[pos + 4], b[pos + 5], b[pos + 6], b[pos + 7]);
            return fail(err, path + ": corrupt PNG: the chunk at byte " + std::to_string(pos) + " has type bytes " + hex +
                                 ", not 4 ASCII letters");
        }
        if (index == 0) {
            if (std::string(type) != "IHDR" || length != 13)
                return fail(err, path + ": corrupt PNG: the first chunk must be a 13-byte IHDR, not " + where);
            const uint32_t w = load_u32be(&b[pos + 8]), h = load_u32be(&b[pos + 12]);
            if (!check_image_size(path, "PNG", w, h, err)) return false;
        }
        pos += size_t(length) + 12;
        if (std::string(type) == "IEND") return true;
    }
}

bool decode_png(const std::string& path, const std::vector<uint8_t>& bytes, Image* out,
                std::string* err) {
    if (!is_png(bytes)) return fail(err, path + ": not a PNG file (bad signature)");
    if (bytes.size() > size_t(std::numeric_limits<int>::max()))
        return fail(err, path + ": PNG file too large");
    if (!check_png_chunks(path, bytes, err)) return false;
    int w = 0, h = 0, c = 0;
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c))
        return fail(err, path + ": corrupt PNG: " + stbi_failure_reason());
    if (!check_image_size(path, "PNG", w, h, err)) return false;
    const int want = (c == 2) ? 4 : c;  // grey+alpha becomes RGBA
    uint8_t* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c, want);
    if (!px) {
        const std::string why = stbi_failure_reason() ? stbi_failure_reason() : "";
        return fail(err, path + ": corrupt PNG: " + (why.empty() ? "its image data does not decode" : why));
    }
    *out = Image(w, h, want);
    for (size_t i = 0; i < out->data.size(); ++i) out->data[i] = float(px[i]) / 255.0f;
    stbi_image_free(px);
    return true;
}

bool decode_hdr(const std::string& path, const std::vector<uint8_t>& bytes, Image* out,
                std::string* err) {
    if (bytes.size() > size_t(std::numeric_limits<int>::max())) return fail(err, path + ": HDR file too large");
    if (!stbi_is_hdr_from_memory(bytes.data(), int(bytes.size())))
        return fail(err, path + ": not a Radiance HDR file (bad signature)");
    int w = 0, h = 0, c = 0;
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c))
        return fail(err, path + ": corrupt HDR: " + stbi_failure_reason());
    if (!check_image_size(path, "HDR", w, h, err)) return false;
    float* px = stbi_loadf_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c, 3);
    if (!px) return fail(err, path + ": corrupt HDR: " + stbi_failure_reason());
    *out = Image(w, h, 3);
    std::copy(px, px + out->data.size(), out->data.begin());
    stbi_image_free(px);
    for (size_t i = 0; i < out->data.size(); ++i)
        if (!std::isfinite(out->data[i]) || out->data[i] < 0)
            return fail(err, path + ": value at pixel (" + std::to_string(i / 3 % size_t(w)) + ", " +
                                 std::to_string(i / 3 / size_t(w)) + ") is negative or not finite");
    return true;
}

// Reads one whitespace-delimited token from a PFM header.
bool pfm_token(const std::vector<uint8_t>& b, size_t* pos, std::string* tok) {
    while (*pos < b.size() && std::isspace(b[*pos])) ++*pos;
    tok->clear();
    while (*pos < b.size() && !std::isspace(b[*pos]) && tok->size() < 64) tok->push_back(char(b[(*pos)++]));
    return !tok->empty() && *pos < b.size();
}

bool decode_pfm(const std::string& path, const std::vector<uint8_t>& b, Image* out,
                std::string* err) {
    if (!is_pfm(b)) return fail(err, path + ": not a PFM file (header must start PF or Pf)");
    const int channels = b[1] == 'F' ? 3 : 1;
    size_t pos = 2;
    std::string tw, th, ts;
    if (!pfm_token(b, &pos, &tw) || !pfm_token(b, &pos, &th) || !pfm_token(b, &pos, &ts))
        return fail(err, path + ": truncated PFM header");
    char* end = nullptr;
    const long w = std::strtol(tw.c_str(), &end, 10);
    if (*end) return fail(err, path + ": PFM width '" + tw + "' is not an integer");
    const long h = std::strtol(th.c_str(), &end, 10);
    if (*end) return fail(err, path + ": PFM height '" + th + "' is not an integer");
    const double scale = std::strtod(ts.c_str(), &end);
    if (*end || !std::isfinite(scale) || scale == 0)
        return fail(err, path + ": PFM scale '" + ts + "' is not a non-zero number");
    if (!check_image_size(path, "PFM", w, h, err)) return false;
    ++pos;  // exactly one whitespace character ends the header
    const size_t need = size_t(w) * size_t(h) * channels * 4;
    if (b.size() - pos != need)
        return fail(err, path + ": PFM data is " + std::to_string(b.size() - pos) +
                             " bytes, " + tw + "x" + th + "x" + std::to_string(channels) +
                             " floats need " + std::to_string(need));
    const bool little = scale < 0;
    *out = Image(int(w), int(h), channels);
    int64_t bad = 0;
    const size_t row = size_t(w) * channels;
    for (long y = 0; y < h; ++y) {
        // PFM rows go bottom to top.
        const uint8_t* src = b.data() + pos + size_t(h - 1 - y) * row * 4;
        for (size_t i = 0; i < row; ++i) {
            uint8_t q[4];
            std::memcpy(q, src + i * 4, 4);
            if (!little) std::swap(q[0], q[3]), std::swap(q[1], q[2]);
            float v;
            std::memcpy(&v, q, 4);
            if (!std::isfinite(v)) ++bad;
            out->data[size_t(y) * row + i] = v;
        }
    }
    if (bad) return fail(err, path + ": PFM holds " + std::to_string(bad) + " NaN or inf values");
    return true;
}

void append_to_vector(void* context, void* data, int size) {
    auto* v = static_cast<std::vector<uint8_t>*>(context);
    const uint8_t* p = static_cast<const uint8_t*>(data);
    v->insert(v->end(), p, p + size);
}

}  // namespace

int64_t image_pixel_budget() { return g_pixel_budget; }
void set_image_pixel_budget(int64_t pixels) { g_pixel_budget = pixels; }

bool decode_image(const std::vector<uint8_t>& bytes, const std::string& name, Image* out, std::string* err) {
    if (is_png(bytes)) return decode_png(name, bytes, out, err);
    if (is_pfm(bytes)) return decode_pfm(name, bytes, out, err);
    return fail(err, name + ": unknown image format (expected PNG or PFM)");
}

bool read_image(const std::string& path, Image* out, std::string* err) {
    std::vector<uint8_t> bytes;
    return read_file(path, &bytes, err, kMaxImageFileBytes) && decode_image(bytes, path, out, err);
}

bool read_png(const std::string& path, Image* out, std::string* err) {
    std::vector<uint8_t> bytes;
    return read_file(path, &bytes, err, kMaxImageFileBytes) && decode_png(path, bytes, out, err);
}

bool read_pfm(const std::string& path, Image* out, std::string* err) {
    std::vector<uint8_t> bytes;
    return read_file(path, &bytes, err, kMaxImageFileBytes) && decode_pfm(path, bytes, out, err);
}

bool read_hdr(const std::string& path, Image* out, std::string* err) {
    std::vector<uint8_t> bytes;
    return read_file(path, &bytes, err, kMaxImageFileBytes) && decode_hdr(path, bytes, out, err);
}

bool write_png(const std::string& path, const Image& img, std::string* err, int64_t* clipped) {
    if (img.width < 1 || img.height < 1 || img.channels < 1 || img.channels > 4 ||
        img.data.size() != size_t(img.width) * img.height * img.channels)
        return fail(err, path + ": cannot write an empty or malformed image");
    std::vector<uint8_t> px(img.data.size());
    int64_t clip = 0;
    for (size_t i = 0; i < px.size(); ++i) {
        float v = img.data[i];
        if (!(v >= 0.0f)) v = 0.0f, ++clip;  // also catches NaN
        if (v > 1.0f) v = 1.0f, ++clip;
        px[i] = uint8_t(std::lround(v * 255.0f));
    }
    if (clipped) *clipped = clip;
    std::vector<uint8_t> png;
    if (!stbi_write_png_to_func(append_to_vector, &png, img.width, img.height, img.channels,
                                px.data(), img.width * img.channels))
        return fail(err, path + ": PNG encoding failed");
    return write_file_atomic(path, png.data(), png.size(), err);
}

// stb_image_write has no 16-bit PNG (the asset's 16-bit textures need one): the chunks are
// written here, the deflate is stb's.
bool write_png16(const std::string& path, int width, int height, int channels, const std::vector<uint16_t>& samples,
                 std::string* err) {
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide || channels < 1 || channels > 4 ||
        samples.size() != size_t(width) * height * channels)
        return fail(err, path + ": cannot write an empty or malformed 16-bit image");
    const size_t row = size_t(width) * channels * 2;
    std::vector<uint8_t> filtered(size_t(height) * (row + 1));
    for (int y = 0; y < height; ++y) {
        uint8_t* out = &filtered[size_t(y) * (row + 1)];
        *out++ = 0;  // filter: none
        for (size_t i = 0; i < size_t(width) * channels; ++i) {
            const uint16_t v = samples[size_t(y) * width * channels + i];
            *out++ = uint8_t(v >> 8), *out++ = uint8_t(v & 0xff);  // big-endian
        }
    }
    int zlen = 0;
    unsigned char* z = stbi_zlib_compress(filtered.data(), int(filtered.size()), &zlen, 8);
    if (!z) return fail(err, path + ": PNG encoding failed");
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    auto be32 = [&](uint32_t v) {
        for (int k = 3; k >= 0; --k) png.push_back(uint8_t(v >> (8 * k)));
    };
    auto chunk = [&](const char* type, const uint8_t* data, size_t n) {
        be32(uint32_t(n));
        const size_t start = png.size();
        png.insert(png.end(), type, type + 4);
        png.insert(png.end(), data, data + n);
        be32(sepal_crc32(0, &png[start], n + 4));
    };
    static const uint8_t kColourType[5] = {0, 0, 4, 2, 6};  // by channel count
    const uint8_t ihdr[13] = {uint8_t(width >> 24), uint8_t(width >> 16), uint8_t(width >> 8), uint8_t(width),
                              uint8_t(height >> 24), uint8_t(height >> 16), uint8_t(height >> 8), uint8_t(height),
                              16, kColourType[channels], 0, 0, 0};
    chunk("IHDR", ihdr, sizeof ihdr);
    chunk("IDAT", z, size_t(zlen));
    chunk("IEND", nullptr, 0);
    std::free(z);  // stb allocates with malloc (STBIW_MALLOC is not overridden)
    return write_file_atomic(path, png.data(), png.size(), err);
}

bool read_png16(const std::string& path, int* width, int* height, int* channels, std::vector<uint16_t>* samples,
                std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, kMaxImageFileBytes)) return false;
    if (!is_png(bytes)) return fail(err, path + ": not a PNG file (bad signature)");
    if (bytes.size() > size_t(std::numeric_limits<int>::max())) return fail(err, path + ": PNG file too large");
    if (!check_png_chunks(path, bytes, err)) return false;
    int w = 0, h = 0, c = 0;
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c))
        return fail(err, path + ": corrupt PNG: " + stbi_failure_reason());
    if (!check_image_size(path, "PNG", w, h, err)) return false;
    uint16_t* px = stbi_load_16_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c, 0);
    if (!px) return fail(err, path + ": corrupt PNG: " + stbi_failure_reason());
    samples->assign(px, px + size_t(w) * h * c);
    stbi_image_free(px);
    *width = w, *height = h, *channels = c;
    return true;
}

bool write_pfm(const std::string& path, const Image& img, std::string* err) {
    if (img.width < 1 || img.height < 1 || (img.channels != 1 && img.channels != 3) ||
        img.data.size() != size_t(img.width) * img.height * img.channels)
        return fail(err, path + ": PFM holds 1 or 3 channels of a non-empty image");
    std::string header = std::string(img.channels == 3 ? "PF" : "Pf") + "\n" +
                         std::to_string(img.width) + " " + std::to_string(img.height) +
                         "\n-1.0\n";
    std::vector<uint8_t> bytes(header.begin(), header.end());
    const size_t row = size_t(img.width) * img.channels;
    for (int y = img.height - 1; y >= 0; --y) {  // bottom row first; little-endian floats
        const uint8_t* p = reinterpret_cast<const uint8_t*>(&img.data[size_t(y) * row]);
        bytes.insert(bytes.end(), p, p + row * 4);
    }
    return write_file_atomic(path, bytes.data(), bytes.size(), err);
}

bool write_image(const std::string& path, const Image& img, std::string* err) {
    const std::string ext = file_extension(path);
    if (ext == "png") return write_png(path, img, err);
    if (ext == "pfm") return write_pfm(path, img, err);
    return fail(err, path + ": unknown image extension (use .png or .pfm)");
}

Image image_from_rgba8(const uint8_t* pixels, int width, int height) {
    Image img(width, height, 4);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(pixels[i]) / 255.0f;
    return img;
}

Image to_rgb(const Image& img) {
    Image out(img.width, img.height, 3);
    const size_t n = size_t(img.width) * img.height;
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < 3; ++c)
            out.data[p * 3 + c] = img.data[p * img.channels + (img.channels >= 3 ? c : 0)];
    return out;
}

Image nearest_at_bits(const Image& rgb, const int bits[3]) {
    Image q = rgb;
    for (size_t i = 0; i < q.data.size(); ++i) {
        const int n = bits[i % 3], top = (1 << n) - 1;
        const int code = int(std::lround(std::min(1.0f, std::max(0.0f, q.data[i])) * float(top)));
        int wide = 0;
        for (int filled = 0; filled < 8; filled += n) wide |= (code << (8 - n)) >> filled;
        q.data[i] = float(wide & 255) / 255.0f;
    }
    return q;
}

ImageDiff diff_images(const Image& a, const Image& b, double threshold) {
    ImageDiff d;
    d.threshold = threshold;
    if (a.width != b.width || a.height != b.height) {
        d.reason = "sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                   " vs " + std::to_string(b.width) + "x" + std::to_string(b.height);
        return d;
    }
    d.comparable = true;
    const Image ra = to_rgb(a), rb = to_rgb(b);
    d.pixels = int64_t(a.width) * a.height;
    double sum = 0;
    for (int64_t p = 0; p < d.pixels; ++p) {
        double worst = 0;
        for (int c = 0; c < 3; ++c) {
            const double diff = std::fabs(double(ra.data[p * 3 + c]) - rb.data[p * 3 + c]) * 255.0;
            sum += diff * diff;
            worst = std::max(worst, diff);
        }
        d.max_diff = std::max(d.max_diff, worst);
        if (worst > threshold) ++d.pixels_over;
    }
    d.mse = sum / (3.0 * double(d.pixels));
    d.psnr = d.mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / d.mse)
                       : std::numeric_limits<double>::infinity();
    d.share_over = double(d.pixels_over) / double(d.pixels);
    return d;
}

Image diff_heatmap(const Image& a, const Image& b, double full_scale) {
    const Image ra = to_rgb(a), rb = to_rgb(b);
    Image out(a.width, a.height, 3);
    const double scale = full_scale > 0 ? full_scale : 1.0;
    for (size_t p = 0; p < size_t(a.width) * a.height; ++p) {
        double worst = 0;
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::fabs(double(ra.data[p * 3 + c]) - rb.data[p * 3 + c]) * 255.0);
        heat_colour(worst / scale, &out.data[p * 3]);
    }
    return out;
}

std::string describe_tolerance(const Tolerance& t) {
    std::string s;
    char buf[160];
    if (t.max_diff >= 0 || t.max_share >= 0) {
        const double share = t.max_share >= 0 ? t.max_share : 0.0;
        if (share > 0)
            std::snprintf(buf, sizeof buf, "at most %g%% of pixels over %g (8-bit units)", 100.0 * share,
                          tolerance_threshold(t));
        else
            std::snprintf(buf, sizeof buf, "no pixel over %g (8-bit units)", tolerance_threshold(t));
        s = buf;
    }
    if (t.min_psnr >= 0) {
        std::snprintf(buf, sizeof buf, "PSNR >= %g dB", t.min_psnr);
        s += (s.empty() ? "" : "; ") + std::string(buf);
    }
    return s;
}

void heat_colour(double t, float rgb[3]) {
    // black -> red -> yellow -> white over [0, 1/3, 2/3, 1].
    const float x = float(std::clamp(t, 0.0, 1.0)) * 3.0f;
    rgb[0] = std::min(1.0f, x);
    rgb[1] = std::clamp(x - 1.0f, 0.0f, 1.0f);
    rgb[2] = std::clamp(x - 2.0f, 0.0f, 1.0f);
}

double tolerance_threshold(const Tolerance& t) { return t.max_diff >= 0 ? t.max_diff : 0.0; }

bool tolerance_holds(const ImageDiff& d, const Tolerance& t, std::string* why) {
    std::string reasons;
    auto add = [&](const std::string& s) { reasons += (reasons.empty() ? "" : "; ") + s; };
    char buf[160];
    if (!d.comparable) add(d.reason);
    if (d.comparable && (t.max_diff >= 0 || t.max_share >= 0)) {
        const double allowed = t.max_share >= 0 ? t.max_share : 0.0;
        if (d.share_over > allowed) {
            std::snprintf(buf, sizeof buf,
                          "%.4f%% of pixels differ by more than %g (allowed %.4f%%; max %g)",
                          100.0 * d.share_over, d.threshold, 100.0 * allowed, d.max_diff);
            add(buf);
        }
    }
    if (d.comparable && t.min_psnr >= 0 && d.psnr < t.min_psnr) {
        std::snprintf(buf, sizeof buf, "PSNR %.2f dB below %.2f dB", d.psnr, t.min_psnr);
        add(buf);
    }
    if (why) *why = reasons;
    return reasons.empty();
}

void paste_image(Image* dst, const Image& src, int x0, int y0, int scale) {
    scale = std::max(1, scale);
    for (int y = 0; y < src.height * scale; ++y)
        for (int x = 0; x < src.width * scale; ++x) {
            const int dx = x0 + x, dy = y0 + y;
            if (dx < 0 || dy < 0 || dx >= dst->width || dy >= dst->height) continue;
            for (int c = 0; c < dst->channels; ++c) {
                const int sc = src.channels >= 3 ? std::min(c, src.channels - 1) : 0;
                const float v = c == 3 && src.channels != 4 ? 1.0f : src.at(x / scale, y / scale, c < 3 ? sc : 3);
                dst->at(dx, dy, c) = v;
            }
        }
}

}  // namespace sepal
