// The 8-bit sum of an object's passes (srt::accumulates) written once to a framebuffer with
// fewer bits: each pixel reads its own texel of the sum, times k plus h per channel
// (draw_internal.h's write_scale and write_bias), so that the framebuffer's truncation to its
// bits rounds to nearest. highp where the GPU has it: at mediump, gl_FragCoord past 1024
// pixels cannot name a texel.
#ifdef GL_FRAGMENT_PRECISION_HIGH
precision highp float;
#else
precision mediump float;
#endif
uniform sampler2D u_sum;
uniform vec2 u_origin;    // the viewport's corner: the target's texel (0, 0)
uniform vec2 u_inv_size;  // 1 / the target's size
uniform vec3 u_scale;
uniform vec3 u_bias;
void main() {
    vec3 v = texture2D(u_sum, (gl_FragCoord.xy - u_origin) * u_inv_size).rgb;
    gl_FragColor = vec4(v * u_scale + u_bias, 1.0);
}
