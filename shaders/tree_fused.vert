// Inverse shade trees in one pass (tree_fused.frag): the frame and the mesh's UVs per pixel.
attribute vec3 a_position;
attribute vec3 a_normal;
attribute vec4 a_tangent;
attribute vec2 a_uv;
uniform mat4 u_mvp;
varying vec3 v_position;
varying vec3 v_normal;
varying vec4 v_tangent;
varying vec2 v_uv;
void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_tangent = a_tangent;
    v_uv = a_uv;
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
