#include "bake/devices.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace sepal {
namespace {

// Sources (docs/devices.md gives them in full):
//   [android]  AOSP GLSurfaceView (frameworks/base, opengl/java/android/opengl/GLSurfaceView.java,
//              Android 2.x-4.1 reference): by default an RGB_565 EGLConfig.
//   [es11]     Khronos OpenGL ES 1.1.12 specification, section 6.2 (implementation-dependent
//              values): MAX_TEXTURE_SIZE at least 64, MAX_TEXTURE_UNITS at least 2;
//              OES_blend_subtract, OES_texture_npot and OES_compressed_ETC1_RGB8_texture optional.
//   [arm]      ARM Mali GPU OpenGL ES Application Development Guide (DUI0363D) 2.6.12: Mali-200
//              and Mali-400 MP support up to eight textures in OpenGL ES 1.1.
//   [lima]     Mesa lima driver (src/gallium/drivers/lima/lima_screen.h: max texture 4096x4096;
//              lima_screen.c: PIPE_CAP_NPOT_TEXTURES).
//   [fd]       Mesa freedreno (src/gallium/drivers/freedreno/freedreno_screen.c: a2xx/a3xx
//              max_texture_2d_size 8192).
//   [vc4]      Mesa vc4 (src/gallium/drivers/vc4/vc4_screen.c: max_texture_2d_size 2048,
//              npot_textures, ETC1 where the kernel reports it).
//   [mesa-es1] Mesa (src/mesa/main/extensions_table.h): OES_blend_subtract and
//              OES_framebuffer_object on every ES1 context.
//   [ti]       TI AM335x Technical Reference Manual (SPRUH73), SGX530 3D features: texture
//              maximum 2048 x 2048, PVRTC1/2 and ETC1, non-square textures.
//   [bb]       BlackBerry, "Understand the PowerVR SGX540 platform" (BB10 native docs): OpenGL ES
//              1.1 limits, GL_MAX_TEXTURE_UNITS 4, GL_MAX_TEXTURE_SIZE 2048.
//   [droid]    rbgrn.net, "Hands on Motorola Droid OpenGL ES specs" (SGX530, OMAP3430): the ES 1.1
//              driver's extension string (OES_blend_subtract, OES_compressed_ETC1_RGB8_texture).
//   [rpi]      raspberrypi/userland, Broadcom's GL ES driver: interface/khronos/glxx/gl11_int_config.h
//              (GL11_CONFIG_MAX_TEXTURE_UNITS 4), glxx_client.c (the ES 1.1 extension string:
//              OES_texture_npot, OES_framebuffer_object and ETC1, no OES_blend_subtract).
//   [xoom]     Motorola's OpenGL ES 1.1 extension list for the Xoom (Tegra 2), as republished by
//              cdm.link: NV_texture_npot_2D_mipmap (no OES_texture_npot), DXT1, S3TC and ETC1,
//              no OES_blend_subtract.
//   [a205]     An Adreno 205 phone's SurfaceFlinger log (pastebin.com/W4qUgiUv, 2011,
//              libGLESv1_CM_adreno200.so, "OpenGL ES-CM 1.1"): AMD_compressed_ATC_texture,
//              AMD_compressed_3DC_texture.
//   [mali-es2] es2_info of a Mali-400 MP (pastebin.com/HE112jCZ): OES_compressed_ETC1_RGB8_texture.
//   Throughput: vendors' and press figures, peak triangles per second (docs/devices.md).
const std::vector<DeviceProfile> kProfiles = {
    {"default", "today's bake: an 8-bit framebuffer", 8, 8, 8, 2, kBakeMaxTexture, 0, 1, 1, "none",
     "n/a", "this project: the 8-bit emulator, the GL ES 1.1 plan's 2 units, the bake's 256-texel limit"},
    {"gles1-minimum", "any conformant GL ES 1.1 device", 5, 6, 5, 2, 64, 0, 0, 0, "none", "unknown",
     "[es11] (5/6/5 assumed: the spec sets no colour-buffer minimum)"},
    {"mali400", "ARM Mali-400 MP", 5, 6, 5, 8, 4096, 1, 1, 1, "ETC1", "23-55 M triangles/s (210-500 MHz)",
     "[android] [arm] [lima] [mesa-es1] [mali-es2]"},
    {"adreno200", "Qualcomm Adreno 200/205", 5, 6, 5, kUnknown, 8192, kUnknown, 1, 1, "ATC, 3DC", "unknown",
     "[android] [fd] [mesa-es1] [a205]"},
    {"sgx530", "Imagination PowerVR SGX530/540", 5, 6, 5, 4, 2048, kUnknown, 1, kUnknown, "PVRTC, ETC1",
     "unknown", "[android] [ti] [bb] [droid] (units: SGX540's; SGX530 not found)"},
    {"videocore4", "Broadcom VideoCore IV", 5, 6, 5, 4, 2048, 1, 0, 1, "ETC1", "unknown",
     "[vc4] [rpi] (5/6/5 assumed; Broadcom's driver has no blend subtraction, Mesa's vc4 has)"},
    {"tegra2", "NVIDIA Tegra 2", 5, 6, 5, kUnknown, kUnknown, 0, 0, kUnknown, "DXT1, S3TC, ETC1", "71 M triangles/s",
     "[android] [xoom] (units and texture limit: no public source found)"},
};

std::string figure(int v) { return v == kUnknown ? "?" : std::to_string(v); }
std::string yes_no(int v) { return v == kUnknown ? "?" : v ? "yes" : "no"; }

}  // namespace

const std::vector<DeviceProfile>& device_profiles() { return kProfiles; }

const DeviceProfile& default_device_profile() { return kProfiles.front(); }

const DeviceProfile* find_device_profile(const std::string& name) {
    for (const DeviceProfile& p : kProfiles)
        if (name == p.name) return &p;
    return nullptr;
}

std::string device_profile_names() {
    std::string out;
    for (const DeviceProfile& p : kProfiles) out += (out.empty() ? "" : ", ") + std::string(p.name);
    return out;
}

ProfileLimits profile_limits(const DeviceProfile& p) {
    ProfileLimits l;
    l.bits[0] = p.red_bits, l.bits[1] = p.green_bits, l.bits[2] = p.blue_bits;
    // The GL ES 1.1 plan draws a product on two units (the emulator has no one-unit path):
    // what the asset is judged with, whatever more the device has.
    l.texture_units = 2;
    l.texture_limit = p.max_texture_size == kUnknown ? kBakeMaxTexture : std::min(p.max_texture_size, kBakeMaxTexture);
    l.blend_subtract = p.blend_subtract == 1;
    l.fbo = p.fbo == 1;
    return l;
}

sepal_fmt_profile profile_record(const DeviceProfile& p) {
    const ProfileLimits l = profile_limits(p);
    sepal_fmt_profile f{};
    std::strncpy(f.name, p.name, sizeof f.name - 1);
    f.red_bits = uint32_t(l.bits[0]), f.green_bits = uint32_t(l.bits[1]), f.blue_bits = uint32_t(l.bits[2]);
    f.texture_units = uint32_t(l.texture_units);
    f.max_texture_size = uint32_t(l.texture_limit);
    f.flags = l.blend_subtract ? SEPAL_PROFILE_BLEND_SUBTRACT : 0u;
    return f;
}

std::string describe_device_profiles() {
    std::string out = "profile        framebuffer units max-texture npot subtract fbo compressed       family\n";
    char line[256];
    for (const DeviceProfile& p : kProfiles) {
        std::snprintf(line, sizeof line, "%-14s %d/%d/%d       %-5s %-11s %-4s %-8s %-3s %-16s %s\n", p.name, p.red_bits,
                      p.green_bits, p.blue_bits, figure(p.texture_units).c_str(), figure(p.max_texture_size).c_str(),
                      yes_no(p.npot).c_str(), yes_no(p.blend_subtract).c_str(), yes_no(p.fbo).c_str(), p.compressed,
                      p.family);
        out += line;
    }
    out += "? = no public source found: the bake assumes 2 units, its own 256-texel limit, no blend "
           "subtraction and no framebuffer objects (docs/devices.md lists the sources and what is uncertain)\n";
    return out;
}

}  // namespace sepal
