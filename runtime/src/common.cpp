// Error reporting and small helpers shared by the runtime.
#include "internal.h"
#include "sepal/sepal_version.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

namespace srt {

sepal_result fail(sepal_error* err, sepal_result code, const char* fmt, ...) {
    if (err) {
        err->code = code;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return code;
}

bool has_extension(const char* list, const char* name) {
    if (!list || !name || !*name) return false;
    const size_t n = strlen(name);
    for (const char* p = list; (p = strstr(p, name)) != nullptr; p += n) {
        const bool start = (p == list) || p[-1] == ' ';
        const bool end = p[n] == '\0' || p[n] == ' ';
        if (start && end) return true;
    }
    return false;
}

int shading_frame(const float normal[3], const float tangent[4], ShadingFrame* f) {
    int fallbacks = 0;
    float* n = f->n;
    float* t = f->t;
    n[0] = normal[0], n[1] = normal[1], n[2] = normal[2];
    if (!normalize3(n)) {
        n[0] = 0, n[1] = 0, n[2] = 1;
        fallbacks |= kFrameNormalFallback;
    }
    t[0] = tangent[0], t[1] = tangent[1], t[2] = tangent[2];
    float d = dot3(t, n);
    for (int k = 0; k < 3; ++k) t[k] -= d * n[k];
    // Within 1e-6 of parallel (or zero, or NaN): the threshold of the exact renderer.
    if (!(dot3(t, t) > 1e-12f) || !normalize3(t)) {
        const float axis[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
        d = dot3(axis, n);
        for (int k = 0; k < 3; ++k) t[k] = axis[k] - d * n[k];
        normalize3(t);
        fallbacks |= kFrameTangentFallback;
    }
    if (!isfinite(tangent[3])) fallbacks |= kFrameTangentFallback;  // handedness: +1 below
    const float hand = tangent[3] < 0.0f ? -1.0f : 1.0f;
    f->s[0] = hand * (n[1] * t[2] - n[2] * t[1]);
    f->s[1] = hand * (n[2] * t[0] - n[0] * t[2]);
    f->s[2] = hand * (n[0] * t[1] - n[1] * t[0]);
    return fallbacks;
}

bool vertex_usable(const sepal_vertex& v) {
    for (int k = 0; k < 3; ++k)
        if (!isfinite(v.position[k]) || !isfinite(v.normal[k])) return false;
    return dot3(v.normal, v.normal) > 1e-30f;
}

bool repaired_attributes(const sepal_vertex& v, float normal[3], float tangent[4], ShadingFrame* frame) {
    for (int k = 0; k < 3; ++k) normal[k] = v.normal[k];
    ShadingFrame& fr = *frame;
    if (!(shading_frame(v.normal, v.tangent, &fr) & kFrameTangentFallback)) {
        for (int k = 0; k < 4; ++k) tangent[k] = v.tangent[k];
        return false;
    }
    for (int k = 0; k < 3; ++k) tangent[k] = fr.t[k];
    tangent[3] = v.tangent[3] < 0.0f ? -1.0f : 1.0f;
    return true;
}

float light_direction(const sepal_light& light, const float position[3], float dir[3]) {
    float falloff = 1.0f;
    if (light.type == SEPAL_LIGHT_POINT) {
        for (int k = 0; k < 3; ++k) dir[k] = light.position[k] - position[k];
        const float d2 = dot3(dir, dir);
        falloff = d2 > 1e-12f ? 1.0f / d2 : 0.0f;
    } else {
        for (int k = 0; k < 3; ++k) dir[k] = light.position[k];
    }
    normalize3(dir);
    return falloff;
}

}  // namespace srt

extern "C" void sepal_mat4_perspective(float fovy_degrees, float aspect, float z_near,
                                     float z_far, float out[16]) {
    const float f = 1.0f / tanf(fovy_degrees * 3.14159265358979f / 360.0f);
    memset(out, 0, 16 * sizeof(float));
    out[0] = f / aspect;
    out[5] = f;
    out[10] = (z_far + z_near) / (z_near - z_far);
    out[11] = -1.0f;
    out[14] = 2.0f * z_far * z_near / (z_near - z_far);
}

extern "C" void sepal_mat4_look_at(const float eye[3], const float target[3], const float up[3],
                                 float out[16]) {
    float f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (float& c : f) c /= fl;
    float s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2],
                  f[0] * up[1] - f[1] * up[0]};
    float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (float& c : s) c /= sl;
    const float u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2],
                        s[0] * f[1] - s[1] * f[0]};
    const float m[16] = {s[0], u[0], -f[0], 0,  s[1], u[1], -f[1], 0,
                         s[2], u[2], -f[2], 0,  0,    0,    0,     1};
    memcpy(out, m, sizeof m);
    for (int r = 0; r < 3; ++r)
        out[12 + r] = -(m[r] * eye[0] + m[4 + r] * eye[1] + m[8 + r] * eye[2]);
}

extern "C" uint32_t sepal_version(void) { return SEPAL_VERSION; }
extern "C" const char* sepal_version_string(void) { return SEPAL_VERSION_STRING; }
