// f = sum_k (scale_g q_g + bias_g)(scale_h q_h + bias_h) over a group of terms, times the
// irradiance (E cos(theta_i) for version-1 factors of f, E for radiance factors, which hold
// the cosine) plus the diffuse part times E cos(theta_i), times the frame's exposure. MAX_TERMS is defined by the runtime when it
// compiles this (a prefix line): the texture units available / 2, at most 8.
precision mediump float;
uniform sampler2D u_g[MAX_TERMS];
uniform sampler2D u_h[MAX_TERMS];
uniform vec3 u_g_scale[MAX_TERMS];
uniform vec3 u_g_bias[MAX_TERMS];
uniform vec3 u_h_scale[MAX_TERMS];
uniform vec3 u_h_bias[MAX_TERMS];
uniform int u_terms;
uniform vec3 u_ratio;  // per-channel multiplier (luminance materials)
uniform float u_out_scale;
uniform int u_reciprocal;  // 1: each term is G(x) H(y) G(x~) (format 2.1)
varying vec2 v_uv_g;
varying vec2 v_uv_h;
varying vec3 v_irradiance;  // E cos(theta_i) for factors of f, E for radiance factors
varying vec3 v_diffuse;     // the diffuse part's radiance
varying vec2 v_uv_g2;       // x~ (reciprocal materials)
void main() {
    vec3 f = vec3(0.0);
    for (int k = 0; k < MAX_TERMS; ++k) {
        if (k >= u_terms) break;
        vec3 g = texture2D(u_g[k], v_uv_g).rgb * u_g_scale[k] + u_g_bias[k];
        vec3 h = texture2D(u_h[k], v_uv_h).rgb * u_h_scale[k] + u_h_bias[k];
        if (u_reciprocal == 1) h *= texture2D(u_g[k], v_uv_g2).rgb * u_g_scale[k] + u_g_bias[k];
        f += g * h;
    }
    gl_FragColor = vec4((max(f * u_ratio, 0.0) * v_irradiance + v_diffuse) * u_out_scale, 1.0);
}
