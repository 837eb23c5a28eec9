// Inverse shade trees in one pass: sum over bases j and their terms k of
// w_j(uv) G_jk(x) H_jk(y), per pixel and per light. Compiled after fused_pixel.frag with
// its main renamed (runtime/src/tree_gles2.cpp), so hemi() and coords() are that file's:
// one definition of the parameterizations for every per-pixel shader.
#undef main
uniform sampler2D u_atlas_g;
uniform sampler2D u_atlas_h;
uniform sampler2D u_blend[MAX_BASES];  // one luminance map per basis
uniform vec3 u_tile[MAX_TILES];  // atlas origin (x, y) of each term's tiles, and its basis
uniform vec3 u_tg_scale[MAX_TILES];
uniform vec3 u_tg_bias[MAX_TILES];
uniform vec3 u_th_scale[MAX_TILES];
uniform vec3 u_th_bias[MAX_TILES];
uniform vec2 u_tile_size;   // a tile's size in atlas coordinates
uniform float u_half_texel;  // lookups stay this far inside their tile (no bleeding)
uniform int u_tiles;
varying vec2 v_uv;

vec2 in_tile(vec2 uv, vec3 tile) {
    return tile.xy + clamp(uv, vec2(u_half_texel), vec2(1.0 - u_half_texel)) * u_tile_size;
}

void main() {
    vec3 t, s, n, wo;
    pixel_frame(t, s, n, wo);
    float w[MAX_BASES];
    for (int j = 0; j < MAX_BASES; ++j) w[j] = texture2D(u_blend[j], v_uv).r;
    vec3 sum = vec3(0.0);
    for (int l = 0; l < 8; ++l) {
        if (l >= u_light_count) break;
        vec3 to_light = u_light_pos[l].xyz - u_light_pos[l].w * v_position;
        float falloff = u_light_pos[l].w > 0.5 ? 1.0 / max(dot(to_light, to_light), 1e-6) : 1.0;
        vec3 li = normalize(to_light);
        vec3 wi = vec3(dot(li, t), dot(li, s), dot(li, n));
        if (wi.z <= 0.0 || wo.z <= 0.0) continue;
        vec2 g, h;
        coords(wi, wo, g, h);
        vec3 f = vec3(0.0);
        for (int k = 0; k < MAX_TILES; ++k) {
            if (k >= u_tiles) break;
            float wj = 0.0;
            for (int j = 0; j < MAX_BASES; ++j)
                if (float(j) == u_tile[k].z) wj = w[j];
            vec3 gv = texture2D(u_atlas_g, in_tile(g, u_tile[k])).rgb * u_tg_scale[k] + u_tg_bias[k];
            vec3 hv2 = texture2D(u_atlas_h, in_tile(h, u_tile[k])).rgb * u_th_scale[k] + u_th_bias[k];
            f += wj * gv * hv2;
        }
        sum += max(f, 0.0) * wi.z * falloff * u_light_intensity[l];
    }
    gl_FragColor = vec4(sum, 1.0);
}
