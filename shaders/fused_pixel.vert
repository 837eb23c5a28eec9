// Fused material, per-pixel: the vertex frame is interpolated and everything else is
// computed per fragment (fused_pixel.frag), which also allows the rusinkiewicz and
// elevation/azimuth parameterizations.
attribute vec3 a_position;
attribute vec3 a_normal;
attribute vec4 a_tangent;
uniform mat4 u_mvp;
// Object to shading space: identity, or the model matrix where shading runs in world space
// (a model that is not a similarity); the normals and tangents come moved already.
uniform mat4 u_shade_from_object;
// Every mesh pass tests depth EQUAL against the pre-pass (drawn with pass.vert): the
// position must come out bit-identical across programs.
invariant gl_Position;
varying vec3 v_position;
varying vec3 v_normal;
varying vec4 v_tangent;
void main() {
    v_position = (u_shade_from_object * vec4(a_position, 1.0)).xyz;
    v_normal = a_normal;
    v_tangent = a_tangent;
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
