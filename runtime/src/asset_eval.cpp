// One direction pair of an asset, as the CPU backend draws it (see sepal_asset_eval in
// sepal_asset.h): the CPU backend's pixels and `sepal eval ASSET` share this code, so they
// agree by construction.
#include <math.h>
#include <string.h>

#include "internal.h"

namespace {

float texel(const sepal_asset_texture& t, int i, int j, int c) {
    const sepal_fmt_texture& d = t.desc;
    const size_t idx = ((size_t)j * d.width + (size_t)i) * d.channels + (size_t)c;
    float q;
    if (d.bits == 8) {
        q = (float)t.level_data[0][idx] / 255.0f;
    } else {
        uint16_t v;
        memcpy(&v, t.level_data[0] + 2 * idx, 2);
        q = (float)v / 65535.0f;
    }
    return d.scale[c] * q + d.bias[c];
}

// GL_LINEAR at level 0: texel centres at (i + 0.5) / N, clamped or wrapped at the edges.
float sample(const sepal_asset_texture& t, float u, float v, int c, bool wrap) {
    const int w = (int)t.desc.width, h = (int)t.desc.height;
    const float x = u * (float)w - 0.5f, y = v * (float)h - 0.5f;
    const float fx = floorf(x), fy = floorf(y);
    const float ax = x - fx, ay = y - fy;
    int x0 = (int)fx, y0 = (int)fy, x1 = x0 + 1, y1 = y0 + 1;
    auto fix = [wrap](int k, int n) {
        if (wrap) return ((k % n) + n) % n;
        return k < 0 ? 0 : k >= n ? n - 1 : k;
    };
    x0 = fix(x0, w), x1 = fix(x1, w), y0 = fix(y0, h), y1 = fix(y1, h);
    return (1 - ay) * ((1 - ax) * texel(t, x0, y0, c) + ax * texel(t, x1, y0, c)) +
           ay * ((1 - ax) * texel(t, x0, y1, c) + ax * texel(t, x1, y1, c));
}

}  // namespace

namespace srt {

void find_terms(const sepal_asset& a, AssetTerms* t) {
    memset(t, 0, sizeof *t);
    for (uint32_t i = 0; i < a.texture_count; ++i) {
        const sepal_fmt_texture& d = a.textures[i].desc;
        (d.role == SEPAL_ROLE_G ? t->g : t->h)[d.term] = &a.textures[i];
    }
}

bool eval_pair(const sepal_asset& a, const AssetTerms& t, const float wi[3], const float wo[3], float f_cos[3],
               PairCounts* counts) {
    f_cos[0] = f_cos[1] = f_cos[2] = 0.0f;
    const sepal_param param = (sepal_param)a.material.param;
    const sepal_hemi_map map = (sepal_hemi_map)a.material.map;
    float guv[2], huv[2];
    if (param_texcoords(param, map, wi, wo, guv, huv, true, &counts->param_fallbacks) <= 0) return false;
    // Reciprocal materials (format 2.1) read G a second time at the swapped pair (wo, wi).
    const bool reciprocal = (a.material.flags & SEPAL_MATERIAL_RECIPROCAL) != 0;
    float g2uv[2] = {0, 0}, unused[2];
    if (reciprocal) param_texcoords(param, map, wo, wi, g2uv, unused, true, nullptr);
    const bool wraps_h = param == SEPAL_PARAM_ELEV_AZIM;
    const int channels = (int)a.material.channels;
    float f[3] = {0, 0, 0};
    for (uint32_t k = 0; k < a.material.terms; ++k)
        for (int c = 0; c < channels; ++c)
            f[c] += sample(*t.g[k], guv[0], guv[1], c, false) * sample(*t.h[k], huv[0], huv[1], c, wraps_h) *
                    (reciprocal ? sample(*t.g[k], g2uv[0], g2uv[1], c, false) : 1.0f);
    if (channels == 1) f[1] = f[2] = f[0];
    for (int c = 0; c < 3; ++c) f[c] *= a.material.ratio[c];
    // A signed factorization can dip below 0 where f is near 0: clamp, as the fused shaders
    // do (a BRDF is never negative).
    if (f[0] < 0.0f || f[1] < 0.0f || f[2] < 0.0f) ++counts->negative_clamped;
    // Radiance materials hold cos(theta_i) in their factors (divided by the horizon window,
    // format 2.7) and add the diffuse part.
    const bool radiance = (a.material.flags & SEPAL_MATERIAL_RADIANCE) != 0;
    float prof[3];
    diffuse_profile_rgb(a.diffuse_profile, a.diffuse_side, a.diffuse_layout, wi[2], wo[2], prof);
    const float factor_weight = radiance ? sepal_horizon_window(a.material.horizon, wi[2]) : wi[2];
    for (int c = 0; c < 3; ++c)
        f_cos[c] = (f[c] > 0.0f ? f[c] : 0.0f) * factor_weight + a.material.diffuse[c] * wi[2] * prof[c];
    return true;
}

}  // namespace srt

extern "C" int sepal_asset_eval(const sepal_asset* asset, const float wi[3], const float wo[3], float f_cos[3]) {
    if (!asset || !wi || !wo || !f_cos || !srt::asset_parsed(*asset)) return -1;
    srt::AssetTerms t;
    srt::find_terms(*asset, &t);
    srt::PairCounts counts;
    return srt::eval_pair(*asset, t, wi, wo, f_cos, &counts) ? 1 : 0;
}
