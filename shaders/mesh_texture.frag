// A mesh pass drawing one texture at the mesh's UVs (the diffuse map), with pass.vert.
precision mediump float;
uniform sampler2D u_tex0;
varying vec2 v_uv0;
void main() {
    gl_FragColor = texture2D(u_tex0, v_uv0);
}
