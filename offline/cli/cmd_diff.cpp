// sepal diff A B [--max-diff N] [--max-share P] [--min-psnr D] [--heatmap out.png]
//   [--sheet out.png [--sheet-scale LEVELS]]
#include <cmath>

#include "cli/cli.h"
#include "cli/options.h"
#include "util/image.h"
#include "util/io.h"
#include "util/plot.h"

namespace sepal {
namespace {

struct DiffArgs {
    std::string a, b, heatmap, sheet;
    int64_t max_pixels = kDefaultImagePixels;
    double sheet_scale = 32;
    Tolerance tol;
};

int run_diff(const DiffArgs& args, const CommandIO& io) {
    const Tolerance& tol = args.tol;
    Image a, b;
    std::string err;
    // The budget holds for this command only (commands also run in-process, one at a time).
    struct Budget {
        int64_t saved = image_pixel_budget();
        ~Budget() { set_image_pixel_budget(saved); }
    } restore;
    set_image_pixel_budget(args.max_pixels);
    if (!check_output("--heatmap", args.heatmap, &err) || !check_output("--sheet", args.sheet, &err) ||
        !read_image(args.a, &a, &err) || !read_image(args.b, &b, &err)) {
        std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
        return kExitBadInput;
    }
    // PASS and FAIL only against thresholds the user stated, and the thresholds are printed
    // with the verdict; without any, diff reports the numbers and judges nothing.
    const std::string stated = describe_tolerance(tol);
    const ImageDiff d = diff_images(a, b, tolerance_threshold(tol));
    if (!d.comparable) {
        std::fprintf(io.out, "images differ: %s\n%s", d.reason.c_str(), stated.empty() ? "" : "FAIL\n");
        return kExitCheckFailed;
    }
    std::fprintf(io.out, "size       %dx%d\n", a.width, a.height);
    if (std::isinf(d.psnr))
        std::fprintf(io.out, "psnr       inf dB (identical)\n");
    else
        std::fprintf(io.out, "psnr       %.2f dB (of this image pair; the bake's figures pool several views)\n", d.psnr);
    std::fprintf(io.out, "max diff   %.2f (8-bit units)\n", d.max_diff);
    std::fprintf(io.out, "over %-6g %.4f%% of pixels (%lld of %lld)\n", d.threshold,
                 100.0 * d.share_over, (long long)d.pixels_over, (long long)d.pixels);
    // Both pictures are PNGs (named so), written together or not at all.
    for (const std::string* p : {&args.heatmap, &args.sheet})
        if (!p->empty() && file_extension(*p) != "png") {
            std::fprintf(io.err, "sepal diff: %s: the heatmap and the sheet are PNG files (name them .png)\n",
                         p->c_str());
            return kExitBadInput;
        }
    OutputGuard written;
    if (!args.heatmap.empty()) {
        const double scale = d.max_diff > 0 ? d.max_diff : 1.0;
        if (!write_png(args.heatmap, diff_heatmap(a, b, scale), &err)) {
            std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "heatmap    %s (black 0, white %.2f)\n", args.heatmap.c_str(), scale);
    }
    if (!args.sheet.empty()) {
        // A | B | heatmap on a fixed scale (default 32 levels: comparable between runs).
        auto base = [](const std::string& p) { return p.substr(p.find_last_of('/') + 1); };
        char title[160];
        std::snprintf(title, sizeof title, "%s, %.2f dB", base(args.b).c_str(), d.psnr);
        if (!write_png(args.sheet, comparison_sheet(a, b, base(args.a), title, args.sheet_scale), &err)) {
            std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
            return kExitBadInput;
        }
        std::fprintf(io.out, "sheet      %s (A | B | |B - A|, 0..%g levels", args.sheet.c_str(), args.sheet_scale);
        SheetWindow win;
        if (sheet_window(a, b, &win))
            std::fprintf(io.out, "; under them the %dx%d window of the largest difference at x %d, y %d, %dx", win.side,
                         win.side, win.x, win.y, win.zoom);
        std::fprintf(io.out, ")\n");
    }
    if (!written.commit(&err)) {
        std::fprintf(io.err, "sepal diff: %s\n", err.c_str());
        return kExitBadInput;
    }
    if (stated.empty()) {
        std::fprintf(io.out, "tolerance  none given: no PASS or FAIL (state one with --max-diff, --max-share, "
                             "--min-psnr)\n");
        return kExitOk;
    }
    std::fprintf(io.out, "tolerance  %s\n", stated.c_str());
    std::string why;
    if (!tolerance_holds(d, tol, &why)) {
        std::fprintf(io.out, "FAIL: %s\n", why.c_str());
        return kExitCheckFailed;
    }
    std::fprintf(io.out, "PASS\n");
    return kExitOk;
}

}  // namespace

CommandRun setup_diff(CLI::App& app) {
    auto a = std::make_shared<DiffArgs>();
    app.add_option("A", a->a, "first image (PNG or PFM)")->required();
    app.add_option("B", a->b, "second image, the same size")->required();
    app.add_option("--max-diff", a->tol.max_diff, "largest channel difference allowed, 8-bit units")
        ->check(finite_range(0, 255 * 1e6));
    app.add_option("--max-share", a->tol.max_share, "share of pixels (0..1) allowed over --max-diff")
        ->check(finite_range(0, 1));
    app.add_option("--min-psnr", a->tol.min_psnr, "lowest PSNR allowed, dB")->check(finite_range(0, 1e6));
    app.add_option("--max-pixels", a->max_pixels,
                   "pixel budget per image: a larger image is refused before it is decoded")
        ->check(CLI::Range(int64_t(1), int64_t(kMaxImageSide) * kMaxImageSide))
        ->capture_default_str();
    app.add_option("--heatmap", a->heatmap, "write the per-pixel difference as a PNG");
    app.add_option("--sheet", a->sheet, "write A | B | their difference side by side as a PNG, under them the window of the largest difference magnified");
    app.add_option("--sheet-scale", a->sheet_scale, "the sheet's difference scale: 8-bit levels shown as white")
        ->check(positive())->capture_default_str();
    return [a](const CommandIO& io) { return run_diff(*a, io); };
}

}  // namespace sepal
