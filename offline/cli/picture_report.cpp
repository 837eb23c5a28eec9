#include "cli/picture_report.h"

namespace sepal {

bool report_picture(const Brdf& truth, const Brdf& approx, FILE* out, Json* json, std::string* err) {
    constexpr int kSize = 256;
    std::vector<BakeView> views;
    PictureComparison pc;
    if (!picture_views(&views, err) || !compare_pictures(truth, approx, views, kSize, &pc, err)) return false;
    const PictureFigures& d = pc.views.front();
    std::fprintf(out, "picture    default scene %.1f dB (largest difference %.0f levels), mean Delta E %.2f; "
                 "held out %.1f dB pooled, mean Delta E %.2f (exact renders, %d x %d, against %s)\n",
                 d.psnr, d.max_diff, d.delta_e, pc.held_out_psnr, pc.held_out_delta_e, kSize, kSize,
                 truth.spec().c_str());
    const PictureFigures* worst = &d;
    for (const PictureFigures& f : pc.views)
        if (f.psnr < worst->psnr) worst = &f;
    std::fprintf(out, "           worst view %s: %.1f dB, largest difference %.0f levels\n", worst->view.c_str(),
                 worst->psnr, worst->max_diff);
    Json views_json = Json::array();
    for (const PictureFigures& f : pc.views)
        views_json.push_back({{"view", f.view}, {"psnr_db", f.psnr}, {"max_diff_8bit", f.max_diff},
                              {"share_over_16", f.share_over16}, {"mean_delta_e2000", f.delta_e}});
    *json = {{"size", kSize}, {"truth", truth.spec()}, {"held_out_psnr_db", pc.held_out_psnr},
             {"held_out_mean_delta_e2000", pc.held_out_delta_e}, {"views", views_json}};
    return true;
}

}  // namespace sepal
