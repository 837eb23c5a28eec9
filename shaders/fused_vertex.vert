// Fused material, per-vertex factor coordinates (as in the paper): one pass per light
// sums every term. a_irradiance is (E cos(theta_i), 1) for version-1 materials and
// (E, cos(theta_i)) for radiance materials, E = I / d^2 for this light (0 below the horizon).
attribute vec3 a_position;
attribute vec2 a_uv_g;
attribute vec2 a_uv_h;
attribute vec4 a_irradiance;
uniform mat4 u_mvp;
// Every mesh pass tests depth EQUAL against the pre-pass (drawn with pass.vert): the
// position must come out bit-identical across programs.
invariant gl_Position;
varying vec2 v_uv_g;
varying vec2 v_uv_h;
varying vec4 v_irradiance;
void main() {
    v_uv_g = a_uv_g;
    v_uv_h = a_uv_h;
    v_irradiance = a_irradiance;
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
