// sepal_profile_check: the context's caps against the device profile the asset was judged for.
#include <stdio.h>
#include <string.h>

#include "draw_internal.h"

namespace {

// Appends ", what" (or "what" first) to buf.
void append(char* buf, size_t size, const char* what) {
    const size_t n = strlen(buf);
    if (n + 1 < size) snprintf(buf + n, size - n, "%s%s", n ? ", " : "", what);
}

}  // namespace

extern "C" sepal_result sepal_profile_check(const sepal_caps* caps, const sepal_asset* asset, uint32_t* weaker,
                                            sepal_error* err) {
    if (weaker) *weaker = 0;
    if (!caps || !asset) return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "profile check: NULL argument");
    if (!srt::asset_parsed(*asset))
        return srt::fail(err, SEPAL_ERR_INVALID_ARGUMENT, "profile check: the asset was not filled by sepal_asset_parse");
    const sepal_fmt_profile& p = asset->profile;
    uint32_t bits = 0;
    char what[200] = "";
    char item[96];
    const int have[3] = {caps->red_bits, caps->green_bits, caps->blue_bits};
    const uint32_t want[3] = {p.red_bits, p.green_bits, p.blue_bits};
    bool fewer_bits = false;
    for (int c = 0; c < 3; ++c) fewer_bits = fewer_bits || (have[c] > 0 && (uint32_t)have[c] < want[c]);
    if (fewer_bits) {
        bits |= SEPAL_WEAKER_BITS;
        snprintf(item, sizeof item, "framebuffer %d/%d/%d bits (the profile's %u/%u/%u)", have[0], have[1], have[2],
                 want[0], want[1], want[2]);
        append(what, sizeof what, item);
    }
    if (caps->max_texture_size > 0 && (uint32_t)caps->max_texture_size < p.max_texture_size) {
        bits |= SEPAL_WEAKER_TEXTURE_SIZE;
        snprintf(item, sizeof item, "texture limit %d (the profile's %u)", caps->max_texture_size, p.max_texture_size);
        append(what, sizeof what, item);
    }
    if (caps->texture_units >= 0 && (uint32_t)caps->texture_units < p.texture_units) {
        bits |= SEPAL_WEAKER_UNITS;
        snprintf(item, sizeof item, "%d texture unit%s (the profile's %u)", caps->texture_units,
                 caps->texture_units == 1 ? "" : "s", p.texture_units);
        append(what, sizeof what, item);
    }
    bool subtracts = false;
    for (uint32_t i = 0; i < asset->plan.pass_count; ++i) subtracts = subtracts || asset->passes[i].blend == SEPAL_BLEND_SUBTRACT;
    if (subtracts && (p.flags & SEPAL_PROFILE_BLEND_SUBTRACT) && !caps->has_blend_subtract) {
        bits |= SEPAL_WEAKER_SUBTRACT;
        append(what, sizeof what, "no blend subtraction (subtracted by inversion)");
    }
    if (weaker) *weaker = bits;
    if (bits == 0) return srt::ok(err);
    return srt::fail(err, SEPAL_ERR_UNSUPPORTED,
                     "the context is weaker than the device profile '%s' the asset was judged for: %s; it draws, "
                     "but not as judged (bake with --target gles1:PROFILE for this device)",
                     p.name, what);
}
