// Preview: texture x interpolated vertex colour (GL_MODULATE). mediump is enough: 8-bit
// inputs and output.
precision mediump float;
uniform sampler2D u_texture;
varying vec4 v_color;
varying vec2 v_uv;
void main() {
    gl_FragColor = v_color * texture2D(u_texture, v_uv);
}
