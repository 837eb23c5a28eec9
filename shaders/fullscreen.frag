precision mediump float;
uniform vec4 u_color;
uniform sampler2D u_texture;
uniform int u_textured;
varying vec2 v_uv;
void main() {
    gl_FragColor = u_textured == 1 ? u_color * texture2D(u_texture, v_uv) : u_color;
}
