// u_op: 0 constant (colour), 1 texture (colour x tex0), 2 product (colour x tex0 x tex1);
// times the diffuse map at the mesh's UVs when u_use_map is 1 (a tree's blend map: a factor
// of every pass, so the sum needs no headroom for it).
// mediump suffices: 8-bit operands and an 8-bit framebuffer.
precision mediump float;
uniform sampler2D u_tex0;
uniform sampler2D u_tex1;
uniform int u_op;
uniform float u_scale;  // the pass's rgb_scale (1, 2 or 4)
uniform sampler2D u_map;
uniform float u_use_map;
varying vec4 v_color;
varying vec2 v_uv0;
varying vec2 v_uv1;
varying vec2 v_uvm;
void main() {
    vec3 c = v_color.rgb;
    if (u_op >= 1) c *= texture2D(u_tex0, v_uv0).rgb;
    if (u_op == 2) c *= texture2D(u_tex1, v_uv1).rgb;
    if (u_use_map > 0.5) c *= texture2D(u_map, v_uvm).rgb;
    gl_FragColor = vec4(c * u_scale, 1.0);
}
