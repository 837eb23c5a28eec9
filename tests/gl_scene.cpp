#include "gl_scene.h"

#include <vector>

#include "headless/sepal_headless.h"
#include "sepal/sepal_rt.h"

namespace sepal_test {

bool render_lit_quad(int gles, int width, int height, sepal::Image* out, std::string* err) {
    char msg[512];
    sepal_headless_desc hd = {};
    hd.width = width;
    hd.height = height;
    hd.gles_version = gles;
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    if (!ctx) {
        *err = msg;
        return false;
    }
    sepal_error e = {};
    sepal_caps caps;
    std::vector<sepal_vertex> v(17 * 17);
    std::vector<uint16_t> idx(16 * 16 * 6);
    sepal_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    std::vector<uint8_t> tex(32 * 32 * 4);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            uint8_t* p = &tex[(y * 32 + x) * 4];
            const bool dark = ((x / 4) + (y / 4)) % 2;
            p[0] = dark ? 60 : 255;
            p[1] = dark ? 120 : 240;
            p[2] = dark ? 200 : 220;
            p[3] = 255;
        }
    sepal_preview_desc d = {};
    d.mesh = &mesh;
    const float eye[3] = {0.4f, -2.2f, 1.6f}, target[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    sepal_mat4_look_at(eye, target, up, d.model_view);
    sepal_mat4_perspective(45.0f, float(width) / float(height), 0.5f, 10.0f, d.projection);
    d.light_dir_eye[0] = -0.3f;
    d.light_dir_eye[1] = 0.8f;
    d.light_dir_eye[2] = 0.5f;
    // base * (ambient + 1) stays below 1: drivers differ on where a lit colour over 1 is
    // clamped (the GL spec: per vertex; Mesa's fixed function: per fragment, after
    // interpolation), and the test compares GL ES 1.1 with GL ES 2 on one golden.
    d.base_color[0] = 0.9f;
    d.base_color[1] = 0.8f;
    d.base_color[2] = 0.65f;
    d.ambient = 0.1f;
    d.texture = tex.data();
    d.texture_width = d.texture_height = 32;
    d.clear_color[0] = 0.1f;
    d.clear_color[1] = 0.1f;
    d.clear_color[2] = 0.15f;
    d.clear_color[3] = 1.0f;
    bool ok = sepal_query_caps(gles, 0, sepal_headless_get_proc_address, &caps, &e) == SEPAL_OK && sepal_mesh_grid(16, &mesh, &e) == SEPAL_OK &&
              sepal_preview_draw(&caps, &d, &e) == SEPAL_OK;
    if (!ok) *err = e.message;
    std::vector<uint8_t> px(size_t(width) * height * 4);
    if (ok && !sepal_headless_read_rgba(ctx, px.data())) {
        ok = false;
        *err = "glReadPixels failed";
    }
    sepal_headless_destroy(ctx);
    if (ok) *out = sepal::image_from_rgba8(px.data(), width, height);
    return ok;
}

}  // namespace sepal_test
