// Fused material, per-vertex factor coordinates (as in the paper): one pass per light
// sums every term. a_irradiance is E cos(theta_i) for version-1 materials and E for radiance
// materials, E = I / d^2 for this light (0 below the horizon); a_diffuse is the radiance of
// the diffuse part, E cos(theta_i) diffuse profile (radiance materials, first group only).
attribute vec3 a_position;
attribute vec2 a_uv_g;
attribute vec2 a_uv_h;
attribute vec4 a_irradiance;
attribute vec4 a_diffuse;
attribute vec2 a_uv_g2;  // reciprocal materials: G's second lookup (x~, format 2.1)
uniform mat4 u_mvp;
// Every mesh pass tests depth EQUAL against the pre-pass (drawn with pass.vert): the
// position must come out bit-identical across programs.
invariant gl_Position;
varying vec2 v_uv_g;
varying vec2 v_uv_h;
varying vec3 v_irradiance;
varying vec3 v_diffuse;
varying vec2 v_uv_g2;
void main() {
    v_uv_g2 = a_uv_g2;
    v_uv_g = a_uv_g;
    v_uv_h = a_uv_h;
    v_irradiance = a_irradiance.rgb;
    v_diffuse = a_diffuse.rgb;
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
