#include "common/render_gl.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>

#include <GLES/gl.h>

#include "common/scene_draw.h"
#include "headless/sepal_headless.h"

// stb_image reads diffuse maps (compiled once: third_party/stb/stb.cpp).
#include <stb/stb_image.h>
#include "sepal/internal/sepal_emulate.h"

namespace sepal_ports {

bool read_asset_file(const std::string& path, std::vector<uint8_t>* bytes, std::string* err) {
    return read_bounded_file(path, SEPAL_FMT_MAX_FILE_BYTES, bytes, err);
}

std::vector<DrawCounter> draw_counters(const sepal_draw_stats& s) {
    return {{"below_horizon", s.below_horizon},
            {"dim_lights", s.dim_lights},
            {"fallback_tangents", s.fallback_tangents},
            {"bad_vertices", s.bad_vertices},
            {"skipped_triangles", s.skipped_triangles},
            {"zero_area_triangles", s.zero_area_triangles},
            {"param_fallbacks", s.param_fallbacks},
            {"exposure_clamped", s.exposure_clamped},
            {"nonfinite_clamped", s.nonfinite_clamped},
            {"negative_clamped", s.negative_clamped},
            {"pixel_frame_fallbacks", s.pixel_frame_fallbacks},
            {"weaker_context", s.weaker_context}};
}

std::string describe_counters(const sepal_draw_stats& s) {
    const std::vector<DrawCounter> counters = draw_counters(s);
    std::string out;
    for (const auto& c : counters)
        if (c.value != 0 && std::string(c.name) != "below_horizon")
            out += (out.empty() ? "" : ", ") + std::string(c.name) + " " + std::to_string(c.value);
    if (out.empty()) out = "none";
    // Not a fault: every vertex (or pixel) facing away from a light is one.
    if (s.below_horizon != 0)
        out += "; " + std::to_string(s.below_horizon) +
               " vertex-light pairs below the horizon (shaded 0, as a lit sphere's dark side is)";
    return out;
}

std::string light_range_warning(const void* bytes, size_t size, const sepal_draw_stats& s, const std::string& name) {
    if (s.dim_lights <= 0) return "";
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    if (sepal_asset_parse(bytes, size, asset.get(), &e) != SEPAL_OK) return "";
    const sepal_fmt_material& m = asset->material;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "warning: %d light%s dimmer than %s was baked for (irradiance at the object %.3g..%.3g, white "
                  "level %.3g/sr): highlights may show a flat grey plateau; bake with a wider --light-range",
                  s.dim_lights, s.dim_lights == 1 ? " is" : "s are", name.c_str(), (double)m.irradiance_min,
                  (double)m.irradiance_max, (double)m.white_level);
    return buf;
}

std::string profile_warning(const void* bytes, size_t size, const sepal_caps& caps, const sepal_draw_stats& s) {
    if (s.weaker_context <= 0) return "";
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    if (sepal_asset_parse(bytes, size, asset.get(), &e) != SEPAL_OK) return "";
    if (sepal_profile_check(&caps, asset.get(), nullptr, &e) == SEPAL_OK) return "";
    return std::string("warning: ") + e.message;
}

namespace {
const struct {
    const char* name;
    uint32_t bit;
} kMaskNames[] = {{"subtract", SEPAL_MASK_BLEND_SUBTRACT},
                  {"multitexture", SEPAL_MASK_MULTITEXTURE},
                  {"fbo", SEPAL_MASK_FBO},
                  {"npot", SEPAL_MASK_NPOT},
                  {"third-unit", SEPAL_MASK_THIRD_UNIT}};
}  // namespace

bool parse_mask(const std::string& text, uint32_t* mask, std::string* err) {
    *mask = 0;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = text.find(',', start);
        const std::string word = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        bool known = word.empty();
        for (const auto& m : kMaskNames)
            if (word == m.name) *mask |= m.bit, known = true;
        if (!known) {
            *err = "--mask '" + text + "': use a comma-separated list of subtract, multitexture, fbo, npot, third-unit";
            return false;
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return true;
}

std::string mask_names(uint32_t mask) {
    std::string out;
    for (const auto& m : kMaskNames)
        if (mask & m.bit) out += (out.empty() ? "" : ",") + std::string(m.name);
    return out;
}

bool read_png_rgba8(const std::string& path, Rgba8Image* out, std::string* err) {
    int w = 0, h = 0, c = 0;
    std::vector<uint8_t> bytes;
    if (!read_bounded_file(path, size_t(64) << 20, &bytes, err)) return false;
    unsigned char* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &c, 4);
    if (!px) {
        *err = path + ": cannot read PNG: " + stbi_failure_reason();
        return false;
    }
    out->width = w;
    out->height = h;
    out->pixels.assign(px, px + size_t(w) * h * 4);
    stbi_image_free(px);
    return true;
}

bool read_diffuse_png(const std::string& path, Rgba8Image* out, std::string* err) {
    if (!read_png_rgba8(path, out, err)) return false;
    const int w = out->width, h = out->height;
    if (!(w & (w - 1)) && !(h & (h - 1)) && w <= 4096 && h <= 4096) return true;
    *err = path + ": " + std::to_string(w) + "x" + std::to_string(h) +
           " diffuse map: sides must be powers of two up to 4096 (GL ES 1.1)";
    *out = Rgba8Image{};
    return false;
}

void rgb_to_rgba8(const float* rgb, size_t pixels, uint8_t* rgba) {
    for (size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) {
            const float v = rgb[p * 3 + c];
            rgba[p * 4 + c] = (uint8_t)(v <= 0.0f ? 0 : v >= 1.0f ? 255 : (int)(v * 255.0f + 0.5f));
        }
        rgba[p * 4 + 3] = 255;
    }
}

bool run_headless(const SceneSetup& setup, const GlRenderOptions& options, const HeadlessJob& job,
                  std::vector<uint8_t>* rgba, GlRenderInfo* info, std::string* err) {
    sepal_headless_context* ctx = options.context;
    if (ctx) {
        if (sepal_headless_width(ctx) != setup.width || sepal_headless_height(ctx) != setup.height ||
            sepal_headless_gles_version(ctx) != options.gles_version) {
            *err = "the context given is " + std::to_string(sepal_headless_width(ctx)) + "x" +
                   std::to_string(sepal_headless_height(ctx)) + " GL ES " +
                   std::to_string(sepal_headless_gles_version(ctx)) + ", not the scene's " +
                   std::to_string(setup.width) + "x" + std::to_string(setup.height) + " GL ES " +
                   std::to_string(options.gles_version);
            return false;
        }
        if (!sepal_headless_make_current(ctx)) {
            *err = "the context given cannot be made current";
            return false;
        }
        // An earlier render's error flags are not this one's. Bounded: GL keeps one flag per
        // error kind, and a lost context may report an error on every call.
        for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
        }
    } else {
        sepal_headless_desc hd = {};
        hd.width = setup.width;
        hd.height = setup.height;
        hd.gles_version = options.gles_version;
        hd.framebuffer = options.framebuffer;
        char msg[512];
        ctx = sepal_headless_create(&hd, msg, sizeof msg);
        if (!ctx) {
            *err = msg;
            return false;
        }
    }
    sepal_error e = {};
    sepal_caps caps;
    const bool have_caps =
        sepal_query_caps(options.gles_version, options.mask, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK;
    if (have_caps) info->caps = caps;
    bool ok = have_caps && job.create(&caps, &e);
    if (ok) {
        const int timed = options.frames > 1 ? options.frames : 1, warm = options.frames > 1 ? 2 : 0;
        std::vector<double> times;
        for (int i = 0; ok && i < warm + timed; ++i) {
            const auto start = std::chrono::steady_clock::now();
            ok = job.draw(&info->stats, &e);
            glFinish();  // the frame is done when the GPU is, not when the calls return
            if (i >= warm)
                times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        }
        std::sort(times.begin(), times.end());
        info->ms = times.empty() ? 0.0 : times[times.size() / 2];
        rgba->resize(size_t(setup.width) * setup.height * 4);
        if (ok && !sepal_headless_read_rgba(ctx, rgba->data())) {
            ok = false;
            std::snprintf(e.message, sizeof e.message, "reading the framebuffer back failed");
        }
        info->device = sepal_headless_describe(ctx);
        if (ok && job.finish) ok = job.finish(&e);
    }
    if (have_caps && job.destroy) job.destroy();
    if (!options.context) sepal_headless_destroy(ctx);
    if (!ok) *err = e.message;
    return ok;
}

bool render_asset_headless(const void* bytes, size_t size, const SceneSetup& setup,
                           const GlRenderOptions& options, std::vector<uint8_t>* rgba,
                           GlRenderInfo* info, std::string* err) {
    const int gles_version = options.gles_version;
    const Rgba8Image* diffuse = options.diffuse;
    // Large runtime structs live on the heap here: this is port code, not the runtime.
    auto asset = std::make_unique<sepal_asset>();
    auto material = std::make_unique<sepal_material>();
    sepal_error pe = {};
    if (sepal_asset_parse(bytes, size, asset.get(), &pe) != SEPAL_OK) {
        *err = pe.message;
        return false;
    }
    std::vector<float> scratch;
    sepal_draw_desc d = {};
    HeadlessJob job;
    job.create = [&](sepal_caps* caps, sepal_error* e) {
        if (options.float_target) {
            if (!caps->has_float_target || gles_version != 2) {
                std::snprintf(e->message, sizeof e->message,
                              "no half-float render target here (needs GL ES 3 with "
                              "GL_EXT_color_buffer_half_float; use --backend gles2*)");
                return false;
            }
        }
        const sepal_result made =
            options.float_target
                ? sepal_material_create_float_target(caps, asset.get(), setup.width, setup.height, material.get(), e)
                : sepal_material_create(caps, asset.get(), setup.width, setup.height, material.get(), e);
        if (made != SEPAL_OK) return false;
        d = scene_draw_desc(material.get(), setup, options.mode, &scratch);
        return !diffuse || sepal_texture_create_rgba8(diffuse->pixels.data(), diffuse->width, diffuse->height,
                                                      &d.diffuse_texture, e) == SEPAL_OK;
    };
    job.draw = [&](sepal_draw_stats* stats, sepal_error* e) { return sepal_draw(&d, stats, e) == SEPAL_OK; };
    job.finish = [&](sepal_error* e) {
        sepal_material_info mi;
        sepal_material_get_info(material.get(), &mi);
        if (mi.float_target) {
            std::vector<float> f(size_t(setup.width) * setup.height * 4);
            int clamped = 0;
            if (sepal_read_float(material.get(), setup.width, setup.height, f.data(), &clamped, e) != SEPAL_OK)
                return false;
            info->stats.nonfinite_clamped += clamped;
            info->float_rgb.resize(size_t(setup.width) * setup.height * 3);
            for (int y = 0; y < setup.height; ++y)  // GL rows go bottom up
                for (int x = 0; x < setup.width; ++x)
                    for (int c = 0; c < 3; ++c)
                        info->float_rgb[(size_t(setup.height - 1 - y) * setup.width + x) * 3 + c] =
                            f[(size_t(y) * setup.width + x) * 4 + c];
        }
        static const char* const kModes[] = {"multipass", "fused, per-vertex coordinates", "fused, per pixel"};
        info->path = std::string(gles_version == 2 ? "GL ES 2 " : "GL ES 1.1 ") + kModes[int(options.mode) % 3] + ", " +
                     std::string(mi.single_unit ? "one texture unit (copy texture)" : "two texture units") +
                     (mi.subtracts ? (mi.subtract_by_inversion ? ", subtraction by inversion" : ", blend subtract")
                                   : ", no subtraction") +
                     (mi.accumulates ? ", passes summed in an 8-bit target" : "");
        return true;
    };
    job.destroy = [&] {
        sepal_texture_destroy(d.diffuse_texture);
        sepal_material_destroy(material.get());
    };
    return run_headless(setup, options, job, rgba, info, err);
}

}  // namespace sepal_ports

namespace sepal_ports {

bool render_asset_cpu(const void* bytes, size_t size, const SceneSetup& setup, const Rgba8Image* diffuse,
                      std::vector<float>* rgb, double* ms, std::string* err, sepal_draw_stats* stats) {
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    if (sepal_asset_parse(bytes, size, asset.get(), &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    CpuFrame frame;
    sepal_cpu_desc d = scene_cpu_desc(asset.get(), setup, &frame, stats);
    if (diffuse) {
        d.diffuse_rgba = diffuse->pixels.data();
        d.diffuse_width = diffuse->width;
        d.diffuse_height = diffuse->height;
    }
    const auto start = std::chrono::steady_clock::now();
    const bool ok = sepal_draw_cpu(&d, &e) == SEPAL_OK;
    if (ms) *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!ok) *err = e.message;
    rgb->swap(frame.rgb);
    return ok;
}

bool render_asset_emulated(const void* bytes, size_t size, const SceneSetup& setup, int gles_version, uint32_t mask,
                           std::vector<uint8_t>* rgba, std::string* err, sepal_draw_stats* stats,
                           int framebuffer) {
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    if (sepal_asset_parse(bytes, size, asset.get(), &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    EmulatedFrame frame;
    sepal_emulate_desc d = scene_emulate_desc(asset.get(), setup, gles_version, mask, &frame, stats);
    if (framebuffer == 565) d.red_bits = 5, d.green_bits = 6, d.blue_bits = 5;
    if (sepal_emulate_draw(&d, &e) != SEPAL_OK) {
        *err = e.message;
        return false;
    }
    rgba->swap(frame.rgba);
    return true;
}

bool parse_framebuffer(const std::string& text, int* framebuffer, std::string* err) {
    if (text == "565" || text == "8888") {
        *framebuffer = std::stoi(text);
        return true;
    }
    *err = "--framebuffer '" + text + "': give 8888 (8 bits per channel) or 565 (RGB565: 5/6/5 bits)";
    return false;
}

bool parse_gl_backend(const std::string& name, GlRenderOptions* o) {
    if (name == "gles1") {
        o->gles_version = 1;
        o->mode = SEPAL_MODE_MULTIPASS;
    } else if (name == "gles2") {
        o->gles_version = 2;
        o->mode = SEPAL_MODE_MULTIPASS;
    } else if (name == "gles2-fused") {
        o->gles_version = 2;
        o->mode = SEPAL_MODE_FUSED_VERTEX;
    } else if (name == "gles2-fused-pixel") {
        o->gles_version = 2;
        o->mode = SEPAL_MODE_FUSED_PIXEL;
    } else {
        return false;
    }
    return true;
}

}  // namespace sepal_ports
