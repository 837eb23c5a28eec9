// sepal inspect FILE.sepal: validate an asset with the runtime's own reader and print it.
#include <cmath>
#include <cstdlib>
#include <memory>

#include "cli/cli.h"
#include "common/render_gl.h"
#include "common/scene_flags.h"
#include "cli/options.h"
#include "util/io.h"
#include "util/json.h"
#include "sepal/sepal_asset.h"

namespace sepal {

namespace {

int run_inspect(const std::string& path, const CommandIO& io) {
    std::vector<uint8_t> bytes;
    std::string err;
    if (!read_file(path, &bytes, &err, uint64_t(SEPAL_FMT_MAX_FILE_BYTES) + 1)) {
        std::fprintf(io.err, "sepal inspect: %s\n", err.c_str());
        return kExitBadInput;
    }
    auto a = std::make_unique<sepal_asset>();
    sepal_error e{};
    if (sepal_asset_parse(bytes.data(), bytes.size(), a.get(), &e) != SEPAL_OK) {
        std::fprintf(io.err, "sepal inspect: %s: invalid: %s\n", path.c_str(), e.message);
        return kExitBadInput;
    }
    static const char* kParams[] = {"iv", "gs-half", "vh", "rusinkiewicz", "elev-azim", "axis", "gs-mirror"};
    const sepal_fmt_material& m = a->material;
    std::fprintf(io.out, "file        %s: %zu bytes, format %u.%u, %u chunks, checksums good\n", path.c_str(),
                 bytes.size(), a->header.version_major, a->header.version_minor, a->header.chunk_count);
    std::fprintf(io.out, "material    %s, %s map, %s, %u terms, ratio %g %g %g\n", kParams[m.param],
                 m.param == SEPAL_PARAM_ELEV_AZIM || m.param == SEPAL_PARAM_AXIS ? "angle"
                 : m.map == SEPAL_MAP_XY                                          ? "xy"
                                                                                  : "parabolic", m.color_mode == SEPAL_COLOR_PER_CHANNEL ? "rgb" : "luminance",
                 m.terms, double(m.ratio[0]), double(m.ratio[1]), double(m.ratio[2]));
    char window[96] = "";
    if (m.horizon > 0)  // format 2.7
        std::snprintf(window, sizeof window, " over min(1, cos(theta_i) / %g) (the horizon window)", double(m.horizon));
    if (m.flags & SEPAL_MATERIAL_RADIANCE)
        std::fprintf(io.out, "radiance    factors hold f cos(theta_i)%s; diffuse part %g %g %g /sr%s\n", window,
                     double(m.diffuse[0]),
                     double(m.diffuse[1]), double(m.diffuse[2]),
                     a->diffuse_profile ? (" times a " + std::to_string(a->diffuse_side) + "x" +
                                           std::to_string(a->diffuse_side) + " profile over the two cosines (" +
                                           (a->diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_F32   ? "RGB floats"
                                            : a->diffuse_layout == SEPAL_FMT_DIFFUSE_RGB_U16 ? "RGB, 16 bits"
                                                                                             : "grey, 16 bits") +
                                           ")")
                                              .c_str()
                                        : "");
    if (m.flags & SEPAL_MATERIAL_RECIPROCAL)
        std::fprintf(io.out, "reciprocal  each term is G(x) H(y) G(x~), x~ from the swapped pair (homomorphic: "
                             "p(wo) q(h) p(wi))\n");
    // The lighting it holds under (2.3's light range; an older asset's white level from its META).
    const bool ranged = a->header.version_major > 2 ||
                        (a->header.version_major == 2 && a->header.version_minor >= SEPAL_FMT_VERSION_MINOR_LIGHT_RANGE);
    if (m.white_level > 0 || m.irradiance_min > 0 || m.max_lights > 0) {
        char white[64] = "no white level (nothing capped)";
        if (m.white_level > 0) std::snprintf(white, sizeof white, "white level %.4g/sr", double(m.white_level));
        if (ranged)
            std::fprintf(io.out, "lights      holds for irradiance %.4g..%.4g at the object (%.3g:1), cone %g deg, up to %u "
                                 "light%s; %s\n",
                         double(m.irradiance_min), double(m.irradiance_max),
                         m.irradiance_min > 0 ? double(m.irradiance_max / m.irradiance_min) : 0.0, double(m.cone_degrees),
                         m.max_lights, m.max_lights == 1 ? "" : "s", white);
        else
            std::fprintf(io.out, "lights      %s (from META, format %u.%u: no light range); dimmer than irradiance %.4g "
                                 "at the object shows the cap grey\n",
                         white, a->header.version_major, a->header.version_minor, double(m.irradiance_min));
    } else if (m.flags & SEPAL_MATERIAL_RADIANCE)
        std::fprintf(io.out, "lights      no light range or white level recorded\n");
    // The device profile it was judged for (2.4; without the chunk, the default).
    const sepal_fmt_profile& dp = a->profile;
    std::fprintf(io.out, "device      judged for profile %s%s: framebuffer %u/%u/%u bits, textures at or under %u, %u "
                         "texture units, %s\n",
                 dp.name, a->has_profile ? "" : " (no PROF chunk)", dp.red_bits, dp.green_bits, dp.blue_bits,
                 dp.max_texture_size, dp.texture_units,
                 (dp.flags & SEPAL_PROFILE_BLEND_SUBTRACT) ? "blend subtraction" : "subtraction by inversion");
    // The image figures the bake measured: held out first (conditions the search never saw).
    if (a->meta) {
        Json meta;
        std::string jerr;
        if (parse_json(std::string(a->meta, a->meta_bytes), "META", &meta, &jerr) && meta.is_object() &&
            meta.contains("fit") && meta["fit"].is_object()) {
            const Json& fit = meta["fit"];
            const double in = fit.contains("psnr") && fit["psnr"].is_number() ? fit["psnr"].get<double>() : -1;
            const std::string target = fit.contains("target") && fit["target"].is_string() ? fit["target"].get<std::string>() : "?";
            double held = -1, worst = -1;
            if (fit.contains("held_out_psnr") && fit["held_out_psnr"].is_string())
                held = std::strtod(fit["held_out_psnr"].get<std::string>().c_str(), nullptr);
            if (fit.contains("held_out_worst") && fit["held_out_worst"].is_string())
                worst = std::strtod(fit["held_out_worst"].get<std::string>().c_str(), nullptr);
            if (held >= 0)
                std::fprintf(io.out,
                             "image       held-out %.2f dB on %s, emulated at the bake's judge size, pooled over its "
                             "held-out conditions (worst %.2f dB), in-sample %.2f dB pooled over its training views "
                             "(sepal diff: one image pair)\n",
                             held, target.c_str(), worst, in);
            else if (in >= 0)
                std::fprintf(io.out, "image       in-sample %.2f dB on %s pooled over the views the bake chose on (no held-out figure)\n",
                             in, target.c_str());
        }
    }
    // Direction-space figures (RMS over direction pairs) are diagnostics: what a viewer sees is the
    // image error, which `sepal render` + `sepal diff` (or the bake's candidate table) measure.
    std::fprintf(io.out,
                 "errors      direction-space diagnostics (not image PSNR): float rms %.6g, quantized rms %.6g, "
                 "quantized relative %.6g\n",
                 double(m.error_float), double(m.error_quantized), double(m.error_relative));
    for (uint32_t i = 0; i < a->texture_count; ++i) {
        const sepal_fmt_texture& d = a->textures[i].desc;
        std::fprintf(io.out, "texture %-3u term %u %s  %ux%u x%u ch, %u bits, %u levels; scale", i, d.term,
                     d.role == SEPAL_ROLE_G ? "G" : "H", d.width, d.height, d.channels, d.bits, d.levels);
        for (uint32_t c = 0; c < d.channels; ++c) std::fprintf(io.out, " %.5g", double(d.scale[c]));
        std::fprintf(io.out, "; bias");
        for (uint32_t c = 0; c < d.channels; ++c) std::fprintf(io.out, " %.5g", double(d.bias[c]));
        std::fprintf(io.out, "\n");
    }
    // One meaning of "doublings" everywhere: the framebuffer doublings a frame draws (what the
    // bake's table and `sepal render` print), the plan's own 2^k scale and the lights' exposure
    // together; here the default scene's on gles1, through the emulator.
    std::fprintf(io.out, "plan        %u passes per light, scale 2^%u, peak partial sum %.4f\n", a->plan.pass_count,
                 a->plan.doublings, double(a->plan.peak_partial_sum));
    sepal_ports::SceneSetup setup;
    // The count follows from the mesh's vertices and the lights, not the image's size: a
    // small frame costs a fraction of the default 512x512 one.
    setup.width = setup.height = 64;
    std::vector<uint8_t> rgba;
    sepal_draw_stats frame = {};
    if (sepal_ports::load_scene_mesh(&setup, &err) &&
        sepal_ports::render_asset_emulated(bytes.data(), bytes.size(), setup, 1, 0, &rgba, &err, &frame))
        std::fprintf(io.out, "doublings   %d in the default scene's frame on gles1 (sepal render prints its own scene's)\n",
                     frame.doublings);
    for (uint32_t i = 0; i < a->plan.pass_count; ++i) {
        const sepal_fmt_pass& p = a->passes[i];
        std::fprintf(io.out, "  pass %-3u %-8s %-8s", i, p.blend == SEPAL_BLEND_ADD ? "add" : "subtract",
                     p.op == SEPAL_OP_PRODUCT   ? "product"
                     : p.op == SEPAL_OP_TEXTURE ? "texture"
                     : p.op == SEPAL_OP_DIFFUSE ? "diffuse"
                     : p.op == SEPAL_OP_RECIPROCAL ? "reciprocal"
                                                : "constant");
        if (p.tex0 != SEPAL_FMT_NO_TEXTURE) std::fprintf(io.out, " tex%u", p.tex0);
        if (p.tex1 != SEPAL_FMT_NO_TEXTURE) std::fprintf(io.out, " x tex%u", p.tex1);
        std::fprintf(io.out, "  colour %.5g %.5g %.5g\n", double(p.color[0]), double(p.color[1]), double(p.color[2]));
    }
    // The bake writes a few hundred bytes of provenance; another writer's long META is only counted.
    if (a->meta && a->meta_bytes <= 1024) {
        std::string text(a->meta, a->meta_bytes);
        for (char& ch : text)
            if (ch < 0x20 || ch > 0x7e) ch = '?';  // a corrupt asset's bytes never reach the terminal raw
        std::fprintf(io.out, "meta        %s\n", text.c_str());
    } else if (a->meta)
        std::fprintf(io.out, "meta        %u bytes of JSON\n", a->meta_bytes);
    return kExitOk;
}

}  // namespace

CommandRun setup_inspect(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    app.add_option("FILE", *path, "the .sepal asset to validate and print")->required();
    return [path](const CommandIO& io) { return run_inspect(*path, io); };
}

}  // namespace sepal
