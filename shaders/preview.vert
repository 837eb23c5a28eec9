// Preview: Gouraud lighting by one directional light, the maths of GL ES 1.1's
// fixed-function lighting with light ambient 0 and no specular, so the GL ES 1.1 and
// GL ES 2 previews can be pixel-compared.
attribute vec3 a_position;
attribute vec3 a_normal;
attribute vec2 a_uv;
uniform mat4 u_model_view;
uniform mat4 u_projection;
uniform vec3 u_light_dir;   // eye space, unit length, towards the light
uniform vec3 u_base_color;
uniform float u_ambient;
varying vec4 v_color;
varying vec2 v_uv;
void main() {
    vec3 n = normalize(mat3(u_model_view) * a_normal);
    float diffuse = max(dot(n, u_light_dir), 0.0);
    v_color = vec4(clamp(u_base_color * (u_ambient + diffuse), 0.0, 1.0), 1.0);
    v_uv = a_uv;
    gl_Position = u_projection * (u_model_view * vec4(a_position, 1.0));
}
