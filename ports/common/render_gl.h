// Rendering a .sepal asset headless on GL ES, shared by sepal-view and `sepal render`.
//
// Usage:
//   std::vector<uint8_t> rgba; sepal_draw_stats stats; std::string err;
//   sepal_ports::GlRenderOptions opt;  // GL ES 1.1, no mask, multipass
//   if (!sepal_ports::render_asset_headless(bytes.data(), bytes.size(), setup, opt, &rgba,
//                                          &info, &err)) ...
//
// Creates an offscreen context of the scene's size (ports/headless), queries its
// capabilities with `mask` applied, uploads the material, draws one frame and reads it
// back (RGBA8, top row first). Also reports which path the runtime took.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/scene_flags.h"
#include "headless/sepal_headless.h"
#include "sepal/sepal_material.h"

namespace sepal_ports {

struct GlRenderInfo {
    sepal_draw_stats stats = {};
    std::string device;  // EGL platform, renderer and version
    std::string path;    // e.g. "two texture units, blend subtract"
    double ms = 0;       // time of sepal_draw plus glFinish per frame (median over options.frames)
    sepal_caps caps = {};  // the context's capabilities (framebuffer bits, dither), mask applied
    // With options.float_target: the frame as linear RGB floats, top row first (values the
    // half-float target overflowed are clamped and counted in stats.nonfinite_clamped).
    std::vector<float> float_rgb;
};

// An RGBA8 image, top row first, power-of-two sides (a diffuse texture map).
struct Rgba8Image {
    int width = 0, height = 0;
    std::vector<uint8_t> pixels;
};

struct GlRenderOptions {
    int gles_version = 1;                 // 1 or 2
    uint32_t mask = 0;                    // SEPAL_MASK_* bits
    sepal_draw_mode mode = SEPAL_MODE_MULTIPASS;
    const Rgba8Image* diffuse = nullptr;  // optional diffuse map
    bool float_target = false;            // GL ES 2: draw into a half-float target
    int framebuffer = 8888;               // the pbuffer's colour buffer: 8888 or 565 (sepal_headless.h)
    // Frames to draw: with more than 1, two extra warm-up frames come first and
    // GlRenderInfo::ms is the median of the timed ones (benchmarks).
    int frames = 1;
    // A context to draw in, made current here and left alive (a sweep of many renders pays
    // for EGL set-up and the driver's shader compiles once): its size must be the scene's and
    // its version gles_version. Null: a context is made for this render and destroyed after.
    sepal_headless_context* context = nullptr;
};

bool render_asset_headless(const void* bytes, size_t size, const SceneSetup& setup,
                           const GlRenderOptions& options, std::vector<uint8_t>* rgba,
                           GlRenderInfo* info, std::string* err);
// The frame loop every headless render shares (materials here, trees in render_tree.h):
// an offscreen context of the scene's size, its capabilities (options' version and mask)
// handed to `create`, `draw` run options.frames times (with more than 1, two warm-up frames
// first and info->ms the median), the pixels read back, then `finish` (while the context is
// current: float read-back, info->path), and `destroy` whenever create was called (also after it failed: it must
// accept what create left half made). Each
// callback fills e->message when it fails; *err gets it.
struct HeadlessJob {
    std::function<bool(sepal_caps* caps, sepal_error* e)> create;
    std::function<bool(sepal_draw_stats* stats, sepal_error* e)> draw;
    std::function<bool(sepal_error* e)> finish;  // optional
    std::function<void()> destroy;               // optional
};
bool run_headless(const SceneSetup& setup, const GlRenderOptions& options, const HeadlessJob& job,
                  std::vector<uint8_t>* rgba, GlRenderInfo* info, std::string* err);
// Reads a PNG (stb_image) as RGBA8, any size.
bool read_png_rgba8(const std::string& path, Rgba8Image* out, std::string* err);
// The same, refusing non-power-of-two sizes (diffuse maps).
bool read_diffuse_png(const std::string& path, Rgba8Image* out, std::string* err);
// Linear RGB floats (the CPU backend's output) as displayed: clamped to [0,1], rounded to
// 8 bits, alpha 255.
void rgb_to_rgba8(const float* rgb, size_t pixels, uint8_t* rgba);
// The CPU backend: linear radiance floats (RGB, top row first), no GL. stats (optional)
// receives the frame's counters.
bool render_asset_cpu(const void* bytes, size_t size, const SceneSetup& setup, const Rgba8Image* diffuse,
                      std::vector<float>* rgb, double* ms, std::string* err, sepal_draw_stats* stats = nullptr);
// The GL ES 1.1 emulator (sepal_emulate_draw): what gles1 (gles_version 1) or the gles2
// multipass path (2) shows, computed on the CPU; RGBA8, top row first. mask: SEPAL_MASK_*.
// framebuffer: 8888 or 565, the colour buffer's bits (the passes summed in 8 bits and written
// once, rounded, unless mask has SEPAL_MASK_FBO: then every pass is rounded to them).
bool render_asset_emulated(const void* bytes, size_t size, const SceneSetup& setup, int gles_version, uint32_t mask,
                           std::vector<uint8_t>* rgba, std::string* err, sepal_draw_stats* stats = nullptr,
                           int framebuffer = 8888);
// Parses --framebuffer's value: "565" or "8888"; false with a message naming both otherwise.
bool parse_framebuffer(const std::string& text, int* framebuffer, std::string* err);
// Parses a backend name (gles1, gles2, gles2-fused, gles2-fused-pixel) into options;
// false for others (cpu is not a GL backend).
bool parse_gl_backend(const std::string& name, GlRenderOptions* options);
// Reads a whole asset file (bounded by the format's maximum size).
bool read_asset_file(const std::string& path, std::vector<uint8_t>* bytes, std::string* err);
// The frame's nonzero repair, skip and clamp counters ("fallback_tangents 13, ..."), or
// "none", then the horizon count in words ("; 5897 vertex-light pairs below the horizon
// (shaded 0, as a lit sphere's dark side is)"): what sepal-view prints so that nothing the
// runtime did is silent, without a correct frame reading like a failed one.
std::string describe_counters(const sepal_draw_stats& s);
// One line naming the asset's light range when the frame drew lights dimmer than it was
// baked for (stats.dim_lights > 0), else "": what `sepal render` and sepal-view print.
std::string light_range_warning(const void* bytes, size_t size, const sepal_draw_stats& s, const std::string& name);
// One line naming what of the context (caps) is weaker than the device profile the asset
// was judged for (stats.weaker_context > 0: sepal_profile_check's message), else "": what
// `sepal render` and sepal-view print.
std::string profile_warning(const void* bytes, size_t size, const sepal_caps& caps, const sepal_draw_stats& s);
// Those counters by name, every one (zero or not), in one order: for messages and reports.
struct DrawCounter {
    const char* name;
    int value;
};
std::vector<DrawCounter> draw_counters(const sepal_draw_stats& s);
// Parses "subtract,multitexture,fbo,npot" into SEPAL_MASK_* bits.
bool parse_mask(const std::string& text, uint32_t* mask, std::string* err);
// The reverse: SEPAL_MASK_* bits as the comma-separated names parse_mask reads.
std::string mask_names(uint32_t mask);

}  // namespace sepal_ports
