#include "bake/picture.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bake/light_range.h"
#include "brdf/cie.h"
#include "reference/render_exact.h"

namespace sepal {

bool picture_views(std::vector<BakeView>* views, std::string* err) {
    views->clear();
    views->push_back(default_bake_views().front());
    std::vector<BakeView> held;
    if (!condition_views(held_out_conditions(LightRange{}), &held, err)) return false;
    for (BakeView& v : held) views->push_back(std::move(v));
    return true;
}

double mean_delta_e(const Image& truth, const Image& test, double lit_threshold) {
    if (truth.width != test.width || truth.height != test.height || truth.channels < 3 || test.channels < 3)
        return 0.0;
    double sum = 0.0;
    size_t n = 0;
    const size_t pixels = size_t(truth.width) * size_t(truth.height);
    for (size_t i = 0; i < pixels; ++i) {
        const float* a = &truth.data[i * size_t(truth.channels)];
        const float* b = &test.data[i * size_t(test.channels)];
        if (std::max(a[0], std::max(a[1], a[2])) <= lit_threshold) continue;
        sum += ciede2000(srgb_display_to_lab({a[0], a[1], a[2]}), srgb_display_to_lab({b[0], b[1], b[2]}));
        ++n;
    }
    return n ? sum / double(n) : 0.0;
}

bool compare_pictures(const Brdf& truth, const Brdf& approx, const std::vector<BakeView>& views, int size,
                      PictureComparison* out, std::string* err) {
    *out = PictureComparison();
    double held_mse = 0.0, worst = 1e300;
    for (size_t i = 0; i < views.size(); ++i) {
        const BakeView& v = views[i];
        const sepal_mesh mesh = v.mesh();
        Image a, b;
        if (!render_exact(truth, v.scene, mesh, size, size, &a, nullptr, err) ||
            !render_exact(approx, v.scene, mesh, size, size, &b, nullptr, err))
            return false;
        for (Image* im : {&a, &b})
            for (float& x : im->data) x = std::min(1.0f, std::max(0.0f, x));
        const ImageDiff d = diff_images(a, b, 16);
        PictureFigures f;
        f.view = v.name;
        f.psnr = d.psnr;
        f.max_diff = d.max_diff;
        f.share_over16 = d.share_over;
        f.delta_e = mean_delta_e(a, b);
        worst = std::min(worst, f.psnr);
        if (i > 0) {
            held_mse += d.mse;
            out->held_out_delta_e += f.delta_e;
        }
        out->views.push_back(f);
        if (i == 0) {
            out->truth = std::move(a);
            out->approx = std::move(b);
        }
    }
    const size_t held = views.size() > 1 ? views.size() - 1 : 0;
    if (held) {
        held_mse /= double(held);
        out->held_out_psnr = held_mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / held_mse) : std::numeric_limits<double>::infinity();
        out->held_out_delta_e /= double(held);
    }
    out->worst_psnr = views.empty() ? 0.0 : worst;
    return true;
}

}  // namespace sepal
