// Judging a baked asset by the images it gives on its target, against the exact render.
//
// Usage:
//   std::vector<sepal::BakeView> views = sepal::default_bake_views();   // or a scene's
//   sepal::ImageJudge judge;
//   if (!judge.init(*brdf, views, 128, threads, &err)) ...               // exact references
//   sepal::ImageScore s;
//   if (!judge.score(asset_bytes, sepal::Target::Gles1, &s, &err)) ...  // s.psnr, s.per_view
//
// The score is the PSNR of the pooled mean squared error over every view, of 8-bit images
// (what a display shows: the exact render clamped to [0, 1] and rounded, against the target's
// 8-bit image). Targets: gles1 and gles2 are the GL ES pipeline emulated on the CPU
// (sepal_emulate_draw: GL ES 1.1, or the GL ES 2 multipass path), cpu is the CPU backend
// (float, shown clamped). Deterministic; no GL context.
// The default views are the default scene (sepal render's sphere, camera and light) and
// the same sphere lit from the side and behind (the terminator across the sphere, grazing
// light and grazing highlights), both with irradiance ~3 at the sphere, so a white
// Lambertian surface facing the light shows as 1.
#pragma once
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "util/image.h"
#include "sepal/sepal_rt.h"
#include "sepal/sepal_scene.h"

namespace sepal {

enum class Target { Gles1, Gles2, Cpu };
const char* target_name(Target t);  // "gles1", "gles2", "cpu"
bool parse_target(const std::string& name, Target* t);

struct BakeView {
    std::string name;
    sepal_scene scene{};
    std::vector<sepal_vertex> vertices;  // the mesh, world space
    std::vector<uint16_t> indices;
    sepal_mesh mesh() const;
};

// "default" (the default scene) and "grazing" (the same sphere and camera, one point light
// from the side and behind).
std::vector<BakeView> default_bake_views();
// A view of the unit sphere (64 x 32, as `--mesh sphere`) in the given scene.
BakeView sphere_view(const std::string& name, const sepal_scene& scene);

struct ImageScore {
    double psnr = 0;               // pooled over the views
    std::vector<double> per_view;  // PSNR of each view
    std::vector<double> share_over16;  // per view: share of pixels more than 16 levels off
    int doublings = 0;             // the frame's doublings in the first view (GL targets)
};

class ImageJudge {
  public:
    // Renders the exact reference of every view at size x size (threads as parallel.h).
    bool init(const Brdf& brdf, const std::vector<BakeView>& views, int size, int threads, std::string* err);
    bool score(const std::vector<uint8_t>& asset_bytes, Target target, ImageScore* out, std::string* err) const;
    // The target's image of one view (RGB floats in [0, 1], 8-bit levels), for pictures.
    bool render(const std::vector<uint8_t>& asset_bytes, Target target, size_t view, Image* out,
                std::string* err, int* doublings = nullptr) const;
    const Image& reference(size_t view) const { return refs_[view]; }
    size_t view_count() const { return views_.size(); }
    int size() const { return size_; }
    // The smallest irradiance I / d^2 (largest channel) a lit, visible vertex gets in any
    // view: f cos(theta_i) above 1 / this shows white everywhere.
    double min_irradiance() const { return min_irradiance_; }
    // The GL targets' framebuffer (the emulator's red/green/blue bits; 8 unless set) and
    // capability mask (SEPAL_MASK_BLEND_SUBTRACT: subtraction by inversion): a device
    // profile's (devices.h).
    void set_framebuffer(const int bits[3], uint32_t mask) {
        for (int c = 0; c < 3; ++c) bits_[c] = bits[c];
        mask_ = mask;
    }

  private:
    std::vector<BakeView> views_;
    std::vector<Image> refs_;  // 8-bit levels as floats
    int size_ = 0;
    double min_irradiance_ = 0;
    int bits_[3] = {8, 8, 8};
    uint32_t mask_ = 0;
};

// The smallest irradiance of a lit, visible vertex (see ImageJudge::min_irradiance).
double min_lit_irradiance(const std::vector<BakeView>& views);

}  // namespace sepal
