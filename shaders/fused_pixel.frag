// Per-pixel evaluation of a factored material: frame, directions, factor coordinates
// (runtime/param.cpp's maths), sum over terms and lights.
// highp where the GPU has it: mediump (fp16 on most GPUs, and for part of the arithmetic
// on llvmpipe) holds values up to 65504 with 3 decimal digits, and the extremes need more: a point
// light bright enough to light a surface at 89.9 degrees (intensity 1.8e5 at 4 units)
// turned the whole quad white (9.7 dB against the CPU backend), and cos(theta_i) at
// 89.99 degrees is 1.7e-4, below the absolute error of a mediump dot product. Without
// highp the shader still runs, with those limits (README, "The runtime's backends").
#ifdef GL_FRAGMENT_PRECISION_HIGH
precision highp float;
#else
precision mediump float;
#endif
uniform sampler2D u_g[MAX_TERMS];
uniform sampler2D u_h[MAX_TERMS];
uniform vec3 u_g_scale[MAX_TERMS];
uniform vec3 u_g_bias[MAX_TERMS];
uniform vec3 u_h_scale[MAX_TERMS];
uniform vec3 u_h_bias[MAX_TERMS];
uniform int u_terms;
uniform vec3 u_ratio;  // per-channel multiplier (luminance materials)
uniform float u_out_scale;
uniform float u_factor_cosine;  // 1: factors of f (times cos); 0: radiance factors
uniform float u_horizon;        // radiance factors' horizon window c0 (format 2.7); 0: none
uniform vec3 u_diffuse;         // radiance materials' diffuse part (first group only)
uniform sampler2D u_profile;    // its profile over (cos theta_i, cos theta_o), if u_profile_on
uniform float u_profile_on;
uniform float u_profile_side;
uniform int u_reciprocal;  // 1: each term is G(x) H(y) G(x~), x~ from the swapped pair (format 2.1)
uniform int u_param;  // sepal_param
uniform int u_map;    // sepal_hemi_map
uniform vec3 u_eye;
uniform vec4 u_light_pos[8];  // w = 1: point light at xyz; w = 0: direction towards it
uniform vec3 u_light_intensity[8];
uniform int u_light_count;
varying vec3 v_position;
varying vec3 v_normal;
varying vec4 v_tangent;

vec2 hemi(vec3 a) {
    if (u_map == 0) return 0.5 * (a.xy + 1.0);
    return 0.5 * (a.xy / max(1.0 + a.z, 1e-4) + 1.0);
}

void coords(vec3 wi, vec3 wo, out vec2 g, out vec2 h) {
    vec3 hv = normalize(wi + wo);
    if (u_param == 0) {  // iv
        g = hemi(wi);
        h = hemi(wo);
    } else if (u_param == 1 || u_param == 6) {
        // gs-half (Kautz-McCool eq. 6): h, then wi in the frame about h; gs-mirror: the mirror
        // direction r of wi, then wo in the frame about r.
        // t - (a.t) a with 1 - a.x^2 written as a.y^2 + a.z^2 (no cancellation near a = t);
        // within 1e-3 rad of t (|t'|^2 = 1 - a.x^2 <= 1e-6) Gram-Schmidt on s instead.
        vec3 a = u_param == 1 ? hv : vec3(-wi.xy, wi.z);
        vec3 v = u_param == 1 ? wi : wo;
        vec3 tp = vec3(a.y * a.y + a.z * a.z, -a.x * a.y, -a.x * a.z);
        tp = tp.x > 1e-6 ? normalize(tp) : normalize(vec3(-a.x * a.y, a.x * a.x + a.z * a.z, -a.y * a.z));
        vec3 sp = cross(a, tp);
        g = hemi(a);
        vec3 d = vec3(dot(v, tp), dot(v, sp), dot(v, a));
        // gs-mirror: wo behind r's horizon goes to the rim (runtime/src/internal.h's mirror_rim).
        if (u_param == 6 && d.z < 0.0) d = dot(d.xy, d.xy) > 1e-24 ? vec3(normalize(d.xy), 0.0) : vec3(1.0, 0.0, 0.0);
        h = hemi(d);
    } else if (u_param == 2) {  // vh
        g = hemi(wo);
        h = hemi(hv);
    } else if (u_param == 3) {  // rusinkiewicz: h rotated to the pole
        // cos and sin of phi_h from h itself: atan(0, 0) is undefined in GLSL, and h = n
        // happens (light and eye in the mirror direction). At the pole phi_h = 0.
        float ct = hv.z;
        float st2 = dot(hv.xy, hv.xy);
        float st = sqrt(st2);
        vec2 cs = st2 > 1e-12 ? hv.xy / st : vec2(1.0, 0.0);
        float cp = cs.x, sn = cs.y;
        float x1 = wi.x * cp + wi.y * sn, y1 = -wi.x * sn + wi.y * cp;
        g = hemi(hv);
        h = hemi(vec3(x1 * ct - wi.z * st, y1, x1 * st + wi.z * ct));
    } else if (u_param == 5) {  // axis: G(alpha_i, alpha_o), H(beta_i, beta_o) about the tangent
        // beta = atan(y, z) is undefined at y = z = 0 (w = +-t, on the horizon): 0 there,
        // clamped to +-pi/2 below the horizon, as runtime/src/internal.h's axis_uv does.
        const float kPi = 3.14159265;
        g = vec2(atan(wi.x, length(wi.yz)), atan(wo.x, length(wo.yz))) / kPi + 0.5;  // asin(w.x)
        float bi = dot(wi.yz, wi.yz) > 0.0 ? atan(wi.y, wi.z) : 0.0;
        float bo = dot(wo.yz, wo.yz) > 0.0 ? atan(wo.y, wo.z) : 0.0;
        h = clamp(vec2(bi, bo) / kPi + 0.5, 0.0, 1.0);
    } else {  // elevation/azimuth: G(theta_i, theta_o), H(phi_i, phi_o), H wraps
        const float kPi = 3.14159265;
        g = vec2(acos(clamp(wi.z, -1.0, 1.0)), acos(clamp(wo.z, -1.0, 1.0))) / (0.5 * kPi);
        vec2 p = vec2(atan(wi.y, wi.x), atan(wo.y, wo.x));
        p += vec2(p.x < 0.0 ? 2.0 * kPi : 0.0, p.y < 0.0 ? 2.0 * kPi : 0.0);
        h = p / (2.0 * kPi);
    }
}

// The frame as runtime/common.cpp's shading_frame builds it, fallbacks included (a
// normal or tangent interpolated between opposite corners cancels out), and the view
// direction in it. Shared with tree_fused.frag.
void pixel_frame(out vec3 t, out vec3 s, out vec3 n, out vec3 wo) {
    float nn = dot(v_normal, v_normal);
    n = nn > 0.0 ? v_normal * inversesqrt(nn) : vec3(0.0, 0.0, 1.0);
    t = v_tangent.xyz - n * dot(n, v_tangent.xyz);
    t = dot(t, t) > 1e-12 ? normalize(t) : normalize(abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) - n * n.x
                                                                  : vec3(0.0, 1.0, 0.0) - n * n.y);
    s = (v_tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    vec3 e = normalize(u_eye - v_position);
    wo = vec3(dot(e, t), dot(e, s), dot(e, n));
}

void main() {
    vec3 t, s, n, wo;
    pixel_frame(t, s, n, wo);
    vec3 sum = vec3(0.0);
    for (int l = 0; l < 8; ++l) {
        if (l >= u_light_count) break;
        vec3 to_light = u_light_pos[l].xyz - u_light_pos[l].w * v_position;
        float falloff = u_light_pos[l].w > 0.5 ? 1.0 / max(dot(to_light, to_light), 1e-6) : 1.0;
        vec3 li = normalize(to_light);
        vec3 wi = vec3(dot(li, t), dot(li, s), dot(li, n));
        if (wi.z <= 0.0 || wo.z <= 0.0) continue;
        vec2 g, h, g2, h2;
        coords(wi, wo, g, h);
        if (u_reciprocal == 1) coords(wo, wi, g2, h2);
        vec3 f = vec3(0.0);
        // Level 0, as the CPU backend samples: per-pixel coordinates change fast where the
        // BRDF does (silhouettes, near the highlight), and GL's derivative-based MIP choice
        // read coarse levels there (measured: 8 dB below multipass on NMF assets, 46 against
        // 64 dB to the CPU backend on a torus). A bias of -16 keeps lambda <= 0: level 0 with
        // the magnification filter (bilinear), for any texture up to 65536 texels per side.
        for (int k = 0; k < MAX_TERMS; ++k) {
            if (k >= u_terms) break;
            vec3 gv = texture2D(u_g[k], g, -16.0).rgb * u_g_scale[k] + u_g_bias[k];
            vec3 hv2 = texture2D(u_h[k], h, -16.0).rgb * u_h_scale[k] + u_h_bias[k];
            if (u_reciprocal == 1) hv2 *= texture2D(u_g[k], g2, -16.0).rgb * u_g_scale[k] + u_g_bias[k];
            f += gv * hv2;
        }
        vec3 profile = vec3(1.0);
        if (u_profile_on > 0.5)
            profile = texture2D(u_profile, (vec2(wi.z, wo.z) * (u_profile_side - 1.0) + 0.5) / u_profile_side).rgb;
        float window = u_horizon > 0.0 ? min(1.0, wi.z / u_horizon) : 1.0;
        sum += (max(f * u_ratio, 0.0) * mix(window, wi.z, u_factor_cosine) + u_diffuse * profile * wi.z) * falloff *
               u_light_intensity[l];
    }
    gl_FragColor = vec4(sum * u_out_scale, 1.0);
}
