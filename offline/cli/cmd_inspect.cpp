// sepal inspect FILE.sepal: validate an asset with the runtime's own reader and print it.
#include <cmath>
#include <memory>

#include "cli/cli.h"
#include "cli/options.h"
#include "util/io.h"
#include "sepal/sepal_format.h"

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
    static const char* kParams[] = {"iv", "gs-half", "vh", "rusinkiewicz", "elev-azim", "axis"};
    const sepal_fmt_material& m = a->material;
    std::fprintf(io.out, "file        %s: %zu bytes, format %u.%u, %u chunks, checksums good\n", path.c_str(),
                 bytes.size(), a->header.version_major, a->header.version_minor, a->header.chunk_count);
    std::fprintf(io.out, "material    %s, %s map, %s, %u terms, ratio %g %g %g\n", kParams[m.param],
                 m.param == SEPAL_PARAM_ELEV_AZIM || m.param == SEPAL_PARAM_AXIS ? "angle"
                 : m.map == SEPAL_MAP_XY                                          ? "xy"
                                                                                  : "parabolic", m.color_mode == SEPAL_COLOR_PER_CHANNEL ? "rgb" : "luminance",
                 m.terms, double(m.ratio[0]), double(m.ratio[1]), double(m.ratio[2]));
    if (m.flags & SEPAL_MATERIAL_RADIANCE)
        std::fprintf(io.out, "radiance    factors hold f cos(theta_i); diffuse part %g %g %g /sr%s\n", double(m.diffuse[0]),
                     double(m.diffuse[1]), double(m.diffuse[2]),
                     a->diffuse_profile ? (" times a " + std::to_string(a->diffuse_side) + "x" +
                                           std::to_string(a->diffuse_side) + " profile over the two cosines")
                                              .c_str()
                                        : "");
    if (m.flags & SEPAL_MATERIAL_RECIPROCAL)
        std::fprintf(io.out, "reciprocal  each term is G(x) H(y) G(x~), x~ from the swapped pair (homomorphic: "
                             "p(wo) q(h) p(wi))\n");
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
    std::fprintf(io.out, "plan        %u passes per light, %u doublings, peak partial sum %.4f\n", a->plan.pass_count,
                 a->plan.doublings, double(a->plan.peak_partial_sum));
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
    if (a->meta && a->meta_bytes <= 512) {
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
