// The 8-bit sum of an object's passes (srt::accumulates) written once to a framebuffer with
// fewer bits: each pixel reads its own texel of the sum and writes the nearest value the
// framebuffer holds, exactly N / (2^n - 1), which a driver stores as N whether it converts
// fragments to n bits rounding to nearest (the GL ES specification's rule) or rounds them to
// 8 bits and keeps the top n (llvmpipe); the GL ES 1.1 write, without a shader, is tuned to
// the second (draw_internal.h). highp where the GPU has it, the sampler too (its default,
// lowp, came back from llvmpipe as half floats): v (2^n - 1) comes within 1/510 of a half,
// and at mediump gl_FragCoord past 1024 pixels cannot name a texel.
#ifdef GL_FRAGMENT_PRECISION_HIGH
precision highp float;
precision highp sampler2D;  // the default is lowp: its texels came back as half floats
#else
precision mediump float;
#endif
uniform sampler2D u_sum;
uniform vec2 u_origin;    // the viewport's corner: the target's texel (0, 0)
uniform vec2 u_inv_size;  // 1 / the target's size
uniform vec3 u_levels;    // 2^n - 1 per channel
void main() {
    vec3 v = texture2D(u_sum, (gl_FragCoord.xy - u_origin) * u_inv_size).rgb;
    gl_FragColor = vec4(floor(v * u_levels + 0.5) / u_levels, 1.0);
}
