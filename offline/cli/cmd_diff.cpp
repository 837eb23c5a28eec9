// sepal diff A B [--max-diff N] [--max-share P] [--min-psnr D] [--heatmap out.png]
//   [--sheet out.png [--sheet-scale LEVELS]]
#include <cmath>

#include "cli/cli.h"
#include "util/image.h"
#include "util/plot.h"

namespace sepal {

int cmd_diff(const std::vector<std::string>& argv, const CommandIO& io) {
    Args args(argv, {"max-diff", "max-share", "min-psnr", "heatmap", "sheet", "sheet-scale"});
    Tolerance tol;
    if (args.ok() && args.has("max-diff")) args.number("max-diff", &tol.max_diff);
    if (args.ok() && args.has("max-share")) args.number("max-share", &tol.max_share);
    if (args.ok() && args.has("min-psnr")) args.number("min-psnr", &tol.min_psnr);
    if (args.ok() && args.positional().size() != 2) {
        std::fprintf(io.err, "sepal diff: expected two images, got %zu arguments\n",
                     args.positional().size());
        return kExitBadInput;
    }
    if (!args.ok()) {
        std::fprintf(io.err, "sepal diff: %s\n", args.error().c_str());
        return kExitBadInput;
    }
    if ((args.has("max-diff") && tol.max_diff < 0) || (args.has("max-share") && (tol.max_share < 0 || tol.max_share > 1)) ||
        (args.has("min-psnr") && tol.min_psnr < 0)) {
        std::fprintf(io.err,
                     "sepal diff: --max-diff and --min-psnr must be >= 0, --max-share in 0..1\n");
        return kExitBadInput;
    }
    Image a, b;
    std::string err;
    if (!read_image(args.positional()[0], &a, &err) || !read_image(args.positional()[1], &b, &err)) {
        std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
        return kExitBadInput;
    }
    const ImageDiff d = diff_images(a, b, tolerance_threshold(tol));
    if (!d.comparable) {
        std::fprintf(io.out, "images differ: %s\nFAIL\n", d.reason.c_str());
        return kExitCheckFailed;
    }
    std::fprintf(io.out, "size       %dx%d\n", a.width, a.height);
    if (std::isinf(d.psnr))
        std::fprintf(io.out, "psnr       inf dB (identical)\n");
    else
        std::fprintf(io.out, "psnr       %.2f dB\n", d.psnr);
    std::fprintf(io.out, "max diff   %.2f (8-bit units)\n", d.max_diff);
    std::fprintf(io.out, "over %-6g %.4f%% of pixels (%lld of %lld)\n", d.threshold,
                 100.0 * d.share_over, (long long)d.pixels_over, (long long)d.pixels);
    if (args.has("heatmap")) {
        const double scale = d.max_diff > 0 ? d.max_diff : 1.0;
        if (!write_png(args.get("heatmap"), diff_heatmap(a, b, scale), &err)) {
            std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "heatmap    %s (black 0, white %.2f)\n", args.get("heatmap").c_str(),
                     scale);
    }
    if (args.has("sheet")) {
        // A | B | heatmap on a fixed scale (default 32 levels: comparable between runs).
        double scale = 32;
        if (args.has("sheet-scale") && (!args.number("sheet-scale", &scale) || !(scale > 0))) {
            std::fprintf(io.err, "sepal diff: --sheet-scale: 8-bit levels > 0\n");
            return kExitBadInput;
        }
        auto base = [](const std::string& p) { return p.substr(p.find_last_of('/') + 1); };
        char title[160];
        std::snprintf(title, sizeof title, "%s, %.2f dB", base(args.positional()[1]).c_str(), d.psnr);
        if (!write_png(args.get("sheet"), comparison_sheet(a, b, base(args.positional()[0]), title, scale), &err)) {
            std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "sheet      %s (A | B | |B - A|, 0..%g levels)\n", args.get("sheet").c_str(), scale);
    }
    std::string why;
    if (!tolerance_holds(d, tol, &why)) {
        std::fprintf(io.out, "FAIL: %s\n", why.c_str());
        return kExitCheckFailed;
    }
    std::fprintf(io.out, "PASS\n");
    return kExitOk;
}

}  // namespace sepal
