// Device profiles: what a family of GL ES 1.1-class devices offers the pass plan, one row per
// family, each figure with its public source (docs/devices.md prints the table and says
// what is uncertain).
//
// Usage:
//   const sepal::DeviceProfile* p = sepal::find_device_profile("mali400");   // or nullptr
//   sepal::ProfileLimits lim = sepal::profile_limits(*p);   // what the bake judges with
//   o.profile = p->name;                                     // sepal::BakeOptions
//
// A profile's figures are the device's; kUnknown marks one no public source gave. The bake
// judges on profile_limits(): the framebuffer's bits (every profile has them), two texture
// units (what the GL ES 1.1 plan draws with; GL ES 1.1's minimum), the texture limit (the
// profile's, or unknown, at most the bake's own kBakeMaxTexture), blend subtraction
// (unknown: absent, so plans that subtract are judged drawn by inversion). NPOT, compressed
// formats and the vertex throughput class are listed for people: the asset stores
// power-of-two 8/16-bit textures and its cost model is its own (cost_model.h).
// "default" is the bake before profiles: 8/8/8, two units, the bake's own limit.
#pragma once
#include <string>
#include <vector>

#include "sepal/sepal_format.h"

namespace sepal {

constexpr int kUnknown = -1;
// The largest texture side the bake makes (resolutions 1..256, bake.h).
constexpr int kBakeMaxTexture = 256;

struct DeviceProfile {
    const char* name;        // what --target gles1:NAME takes
    const char* family;      // the GPUs it stands for
    int red_bits, green_bits, blue_bits;  // the framebuffer the family's devices draw into
    int texture_units;       // GL ES 1.1 fixed-function units (GL_MAX_TEXTURE_UNITS), or kUnknown
    int max_texture_size;    // GL_MAX_TEXTURE_SIZE, or kUnknown
    int npot;                // full non-power-of-two textures: 1, 0 or kUnknown
    int blend_subtract;      // GL_OES_blend_subtract: 1, 0 or kUnknown
    int fbo;                 // GL_OES_framebuffer_object (a 565 frame summed in 8 bits): 1, 0 or kUnknown
    const char* compressed;  // compressed texture formats ("ETC1, PVRTC"), "none" or "unknown"
    const char* throughput;  // vertex throughput class, or "unknown"
    const char* source;      // where each figure comes from (docs/devices.md has the full list)
};

// Every profile, "default" first.
const std::vector<DeviceProfile>& device_profiles();
const DeviceProfile* find_device_profile(const std::string& name);
const DeviceProfile& default_device_profile();
// "default, gles1-minimum, mali400, ..." for messages.
std::string device_profile_names();

// What the bake judges a profile with (see the top).
struct ProfileLimits {
    int bits[3] = {8, 8, 8};
    int texture_units = 2;  // the plan's
    int texture_limit = kBakeMaxTexture;
    bool blend_subtract = true;
    // The runtime sums a GL ES 1.1 frame in an 8-bit target on a framebuffer with fewer bits
    // where the context has framebuffer objects; judged so only where the profile says yes.
    bool fbo = true;
};
ProfileLimits profile_limits(const DeviceProfile& p);
// The asset's record of it (format 2.4's PROF chunk).
sepal_fmt_profile profile_record(const DeviceProfile& p);

// "mali400" -> "ARM Mali-400 MP ...": the table as text, one row per profile (sepal info --devices).
std::string describe_device_profiles();

}  // namespace sepal
