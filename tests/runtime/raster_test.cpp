// runtime/include/sepal/sepal_raster.h: coverage identical to GL's, shared edges drawn once,
// perspective-correct varyings, near-plane clipping, argument checks.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "headless/sepal_headless.h"
#include "sepal/sepal_raster.h"
#include "sepal/sepal_rt.h"

namespace {

struct Coverage {
    int width;
    std::vector<int> hits;  // per pixel, top row first
    std::vector<float> var;  // last varyings written, 2 per pixel
};

void count_hit(void* user, int x, int y, float, const float* v) {
    auto* c = static_cast<Coverage*>(user);
    c->hits[size_t(y) * c->width + x] += 1;
    c->var[(size_t(y) * c->width + x) * 2 + 0] = v[0];
    c->var[(size_t(y) * c->width + x) * 2 + 1] = v[1];
}

// Transforms mesh positions to clip space with the preview's matrices.
std::vector<float> clip_positions(const sepal_mesh& mesh, const float* mv, const float* proj) {
    const glm::mat4 m = glm::make_mat4(proj) * glm::make_mat4(mv);
    std::vector<float> clip;
    for (int i = 0; i < mesh.vertex_count; ++i) {
        const float* p = mesh.vertices[i].position;
        const glm::vec4 c = m * glm::vec4(p[0], p[1], p[2], 1.0f);
        clip.insert(clip.end(), {c.x, c.y, c.z, c.w});
    }
    return clip;
}

}  // namespace

TEST_CASE("raster: a sphere covers exactly the pixels GL ES 2 covers") {
    const int W = 97, H = 73;  // odd sizes: no symmetry to hide off-by-one errors
    std::vector<sepal_vertex> v(25 * 13);
    std::vector<uint16_t> idx(24 * 12 * 6);
    sepal_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    sepal_error err = {};
    REQUIRE(sepal_mesh_sphere(24, 12, &mesh, &err) == SEPAL_OK);
    sepal_preview_desc d = {};
    d.mesh = &mesh;
    const float eye[3] = {0.3f, -2.6f, 1.1f}, target[3] = {0.1f, 0, 0}, up[3] = {0, 0, 1};
    sepal_mat4_look_at(eye, target, up, d.model_view);
    sepal_mat4_perspective(50.0f, float(W) / H, 0.5f, 10.0f, d.projection);
    d.light_dir_eye[2] = 1;
    d.base_color[0] = d.base_color[1] = d.base_color[2] = 1;
    d.ambient = 1;  // lit colour saturates: the object is white, the background black
    d.clear_color[3] = 1;

    sepal_headless_desc hd = {};
    hd.width = W;
    hd.height = H;
    hd.gles_version = 2;
    char msg[512];
    sepal_headless_context* ctx = sepal_headless_create(&hd, msg, sizeof msg);
    REQUIRE_MESSAGE(ctx, msg);
    sepal_caps caps;
    REQUIRE(sepal_query_caps(2, 0, sepal_headless_get_proc_address, &caps, &err) == SEPAL_OK);
    REQUIRE_MESSAGE(sepal_preview_draw(&caps, &d, &err) == SEPAL_OK, err.message);
    std::vector<uint8_t> px(size_t(W) * H * 4);
    REQUIRE(sepal_headless_read_rgba(ctx, px.data()));
    sepal_headless_destroy(ctx);

    const std::vector<float> clip = clip_positions(mesh, d.model_view, d.projection);
    std::vector<float> uv;
    for (const sepal_vertex& vx : v) uv.insert(uv.end(), {vx.uv[0], vx.uv[1]});
    std::vector<float> depth(size_t(W) * H);
    sepal_raster_target t = {W, H, depth.data()};
    sepal_raster_clear_depth(&t);
    Coverage cov{W, std::vector<int>(size_t(W) * H), std::vector<float>(size_t(W) * H * 2)};
    sepal_raster_desc rd = {};
    rd.clip = clip.data();
    rd.vertex_count = mesh.vertex_count;
    rd.varyings = uv.data();
    rd.varying_count = 2;
    rd.varying_stride = 2;
    rd.indices = idx.data();
    rd.index_count = mesh.index_count;
    rd.cull = SEPAL_CULL_BACK;
    rd.depth_func = SEPAL_DEPTH_LEQUAL;
    rd.fragment = count_hit;
    rd.user = &cov;
    REQUIRE_MESSAGE(sepal_raster_triangles(&t, &rd, &err) == SEPAL_OK, err.message);

    int gl_covered = 0, mismatched = 0, double_hits = 0;
    for (int i = 0; i < W * H; ++i) {
        const bool gl = px[size_t(i) * 4] > 127;
        gl_covered += gl;
        mismatched += gl != (cov.hits[size_t(i)] > 0);
        double_hits += cov.hits[size_t(i)] > 1;  // back faces culled: at most one hit
    }
    CHECK(gl_covered > W * H / 4);
    CHECK(double_hits == 0);
    // Same snapping and fill rule as llvmpipe: identical coverage. Another GL driver may
    // round differently on a few silhouette pixels.
    CHECK_MESSAGE(mismatched == 0, mismatched << " of " << gl_covered << " pixels differ");
}

TEST_CASE("raster: shared edges are drawn exactly once; perspective-correct varyings") {
    const int W = 64, H = 48;
    // A grid quad seen in perspective: 2 triangles per cell, many shared edges, some of
    // them passing exactly through pixel centres.
    std::vector<sepal_vertex> v(9 * 9);
    std::vector<uint16_t> idx(8 * 8 * 6);
    sepal_mesh mesh = {v.data(), idx.data(), int(v.size()), int(idx.size())};
    sepal_error err = {};
    REQUIRE(sepal_mesh_grid(8, &mesh, &err) == SEPAL_OK);
    float mv[16], proj[16];
    const float eye[3] = {0.0f, -1.5f, 1.2f}, target[3] = {0, 0.2f, 0}, up[3] = {0, 0, 1};
    sepal_mat4_look_at(eye, target, up, mv);
    sepal_mat4_perspective(70.0f, float(W) / H, 0.1f, 10.0f, proj);
    const std::vector<float> clip = clip_positions(mesh, mv, proj);
    std::vector<float> pos_xy;  // varyings: object-space x, y
    for (const sepal_vertex& vx : v) pos_xy.insert(pos_xy.end(), {vx.position[0], vx.position[1]});
    std::vector<float> depth(size_t(W) * H);
    sepal_raster_target t = {W, H, depth.data()};
    sepal_raster_clear_depth(&t);
    Coverage cov{W, std::vector<int>(size_t(W) * H), std::vector<float>(size_t(W) * H * 2)};
    sepal_raster_desc rd = {};
    rd.clip = clip.data();
    rd.vertex_count = mesh.vertex_count;
    rd.varyings = pos_xy.data();
    rd.varying_count = 2;
    rd.varying_stride = 2;
    rd.indices = idx.data();
    rd.index_count = mesh.index_count;
    rd.depth_func = SEPAL_DEPTH_ALWAYS;  // count every fragment
    rd.fragment = count_hit;
    rd.user = &cov;
    REQUIRE(sepal_raster_triangles(&t, &rd, &err) == SEPAL_OK);
    int covered = 0, twice = 0;
    double worst = 0;
    const glm::mat4 inv = glm::inverse(glm::make_mat4(proj) * glm::make_mat4(mv));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int h = cov.hits[size_t(y) * W + x];
            covered += h > 0;
            twice += h > 1;
            if (!h) continue;
            // Where the pixel centre's ray meets the z = 0 plane, analytically.
            const float nx = (x + 0.5f) / W * 2 - 1, ny = 1 - (y + 0.5f) / H * 2;
            glm::vec4 a = inv * glm::vec4(nx, ny, -1, 1), b = inv * glm::vec4(nx, ny, 1, 1);
            a /= a.w;
            b /= b.w;
            const float s = a.z / (a.z - b.z);
            const glm::vec4 hit = a + s * (b - a);
            worst = std::max<double>(worst, std::fabs(hit.x - cov.var[(size_t(y) * W + x) * 2]));
            worst = std::max<double>(worst, std::fabs(hit.y - cov.var[(size_t(y) * W + x) * 2 + 1]));
        }
    CHECK(covered > W * H / 3);
    CHECK(twice == 0);
    CHECK(worst < 2e-3);  // float maths; affine interpolation would be off by ~0.1
}

TEST_CASE("raster: near-plane clipping, degenerate input and argument checks") {
    const int W = 32, H = 32;
    std::vector<float> depth(size_t(W) * H);
    sepal_raster_target t = {W, H, depth.data()};
    sepal_raster_clear_depth(&t);
    Coverage cov{W, std::vector<int>(size_t(W) * H), std::vector<float>(size_t(W) * H * 2)};
    // One vertex behind the eye (w < 0): the triangle is clipped, not wrapped around.
    const float clip[] = {-0.5f, -0.5f, 0.5f, 1.0f, 0.5f, -0.5f, 0.5f, 1.0f, 0.0f, 0.5f, -3.0f, -2.0f,
                          // a zero-area triangle and a NaN vertex
                          0.1f, 0.1f, 0.0f, 1.0f, NAN, 0.0f, 0.0f, 1.0f};
    const uint16_t idx[] = {0, 1, 2, 0, 0, 3, 0, 1, 4};
    sepal_raster_desc rd = {};
    rd.clip = clip;
    rd.vertex_count = 5;
    rd.indices = idx;
    rd.index_count = 9;
    rd.fragment = count_hit;
    rd.user = &cov;
    sepal_error err = {};
    float zero_var[2] = {0, 0};
    rd.varyings = zero_var;
    REQUIRE(sepal_raster_triangles(&t, &rd, &err) == SEPAL_OK);
    int covered = 0;
    for (int h : cov.hits) covered += h;
    CHECK(covered > 0);
    CHECK(covered < W * H / 2);
    // Bad arguments are refused with a message.
    const uint16_t bad_idx[] = {0, 1, 7};
    rd.indices = bad_idx;
    rd.index_count = 3;
    CHECK(sepal_raster_triangles(&t, &rd, &err) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(std::string(err.message).find("vertex 7") != std::string::npos);
    rd.indices = idx;
    rd.varying_count = 40;
    CHECK(sepal_raster_triangles(&t, &rd, &err) == SEPAL_ERR_INVALID_ARGUMENT);
    rd.varying_count = 0;
    rd.fragment = nullptr;
    CHECK(sepal_raster_triangles(&t, &rd, &err) == SEPAL_ERR_INVALID_ARGUMENT);
}
