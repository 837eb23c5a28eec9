// The virtual acquisition setup: a camera and a point light on a sphere of positions around
// a known object, one "photograph" per view (Lensch et al. 2003, section 3 and 6.2).
//
// Usage:
//   sepal::RigOptions rig;                                   // distances, light, noise
//   sepal::ViewPair v = sepal::view_from_angles(rig, 30, 60, 0, 80);  // camera / light: azimuth, elevation (deg)
//   sepal::Capture c;
//   sepal::capture_atlas(obj, truth, v, rig, /*seed=*/7, &c);          // one sample per visible, lit texel
//   sepal::Image img;  sepal::render_svbrdf(obj, truth, sepal::scene_for_view(obj, v, rig), 256, 256, opts, &img);
//
// A capture is what the paper keeps after registering a photograph and resampling it into
// the atlas: for every texel that the camera sees and the light reaches (object.h) with both
// angles within max_angle_deg of the normal (80: the paper's cut-off for unreliable grazing
// samples), the local directions, the measured BRDF value and its weight. Measurement model:
// the sensor reads radiance L = f(wi, wo) E + noise, E = I cos(theta_i) / d^2 the irradiance
// of the point light (intensity I at distance d), Gaussian noise of standard deviation
// noise_read + noise_shot * L (read noise and a signal-proportional term) per channel, no
// clipping (an HDR capture, as the paper's). The BRDF value is L / E; its weight is
// cos(theta_o) / std(L / E): the inverse standard deviation, times the paper's cosine of the
// view angle (registration is least reliable at grazing views). Noise is a pure function of
// (seed, texel): captures are reproducible.
// Photographs (render_svbrdf with noise and shadows): the same model per image pixel, the
// texel of the pixel's UV (nearest) giving the sample. Exact renders (no noise, no shadows:
// the radiance of sepal_scene.h) are what planned and random reconstructions are compared by.
// Limits: camera and light outside the object's bounding sphere; images up to 4096^2.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "acquire/object.h"
#include "acquire/known.h"
#include "util/image.h"
#include "sepal/sepal_scene.h"

namespace sepal {

struct RigOptions {
    double camera_distance = 4;  // in object radii
    double light_distance = 4;   // in object radii
    // Point-light intensity, in units of (distance / radius)^2: 16 puts an irradiance of
    // pi at normal incidence from 4 radii, so a white Lambertian surface reads L ~ 1.
    double light_intensity = 16 * 3.14159265358979323846;
    double noise_read = 0.005;   // std of L, absolute
    double noise_shot = 0.02;    // std of L per unit L
    double max_angle_deg = 80;   // samples beyond this angle (light or view) are not used
    double min_separation_deg = 10;  // camera and light closer than this: no view
    int depth_res = kDefaultDepthRes;
};

// Unit directions from the object's centre to the camera and to the light; their
// positions are these times the rig's distances (times the object's radius).
struct ViewPair {
    glm::dvec3 camera{0, -1, 0}, light{0, -1, 0};
};

// Degrees: azimuth around +z from +x, elevation above the xy plane.
glm::dvec3 direction_from_angles(double azimuth_deg, double elevation_deg);
ViewPair view_from_angles(double cam_azimuth, double cam_elevation, double light_azimuth, double light_elevation);
double separation_deg(const ViewPair& v);

// Camera position, light position and intensity of a view for this object.
glm::dvec3 camera_position(const AcqObject& obj, const ViewPair& v, const RigOptions& rig);
glm::dvec3 light_position(const AcqObject& obj, const ViewPair& v, const RigOptions& rig);
double light_intensity(const AcqObject& obj, const RigOptions& rig);

// The standard deviation of a radiance reading L (one channel).
inline double radiance_std(const RigOptions& rig, double L) {
    return rig.noise_read + rig.noise_shot * (L > 0 ? L : 0);
}

struct Capture {
    ViewPair view;
    std::vector<int> texel;         // atlas texel index per sample
    std::vector<glm::vec3> wi, wo;  // local directions
    std::vector<glm::vec3> value;   // measured f (per steradian, linear RGB)
    std::vector<float> weight;      // 1 / std, times cos(theta_o)
    size_t size() const { return texel.size(); }
};

// The view's capture. cam/light (optional) receive what each point sees, for reuse.
void capture_atlas(const AcqObject& obj, const BlendSvbrdf& truth, const ViewPair& view, const RigOptions& rig,
                   uint64_t seed, Capture* out, PointView* cam = nullptr, PointView* light = nullptr);

// A sepal_scene for this view: the camera framing the object, the point light.
sepal_scene scene_for_view(const AcqObject& obj, const ViewPair& view, const RigOptions& rig);

struct RenderSvbrdfOptions {
    bool shadows = false;  // darken what the light does not reach (texel visibility)
    bool noise = false;    // the sensor noise of the rig
    uint64_t seed = 0;
    const RigOptions* rig = nullptr;  // needed for noise and shadows
};
// One pixel of a photograph with what it measured.
struct PhotoSample {
    int x = 0, y = 0, texel = 0;
    glm::vec3 wi{0.0f}, wo{0.0f}, value{0.0f};
    float weight = 0;
};
// Renders the SVBRDF (per pixel: interpolated frame, weights bilinear at the pixel's UV);
// samples (optional) receives the pixels that measure a sample (visible, lit, within the
// angle limit) when shadows are on.
bool render_svbrdf(const AcqObject& obj, const BlendSvbrdf& svbrdf, const sepal_scene& scene, int width,
                   int height, const RenderSvbrdfOptions& options, Image* out, std::string* err,
                   std::vector<PhotoSample>* samples = nullptr);

// A standard normal deviate from a counter (Box-Muller): the noise of sample i of stream seed.
double counter_gauss(uint64_t seed, uint64_t i);

}  // namespace sepal
