// One pass of a material's plan (GL ES 2 multipass): the GL ES 1.1 fixed-function
// pipeline's work, tex0 x tex1 x vertex colour, with per-vertex factor coordinates.
attribute vec3 a_position;
attribute vec4 a_color;
attribute vec2 a_uv0;
attribute vec2 a_uv1;
attribute vec2 a_uvm;  // the mesh's UVs, for the diffuse map (when u_use_map is 1)
uniform mat4 u_mvp;
// Every mesh pass tests depth EQUAL against the pre-pass (drawn with pass.vert): the
// position must come out bit-identical across programs.
invariant gl_Position;
varying vec4 v_color;
varying vec2 v_uv0;
varying vec2 v_uv1;
varying vec2 v_uvm;
void main() {
    v_color = a_color;
    v_uvm = a_uvm;
    v_uv0 = a_uv0;
    v_uv1 = a_uv1;
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
