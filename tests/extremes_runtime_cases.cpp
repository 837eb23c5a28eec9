#include "extremes_runtime_cases.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <glm/glm.hpp>

#include "bake/bake.h"
#include "bake/plan.h"
#include "common/render_gl.h"
#include "spec/spec.h"

namespace extremes {
namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double degrees) { return degrees * kPi / 180.0; }

glm::dvec3 v3(const float* p) { return glm::dvec3(p[0], p[1], p[2]); }
void put(float* dst, const glm::dvec3& v) {
    dst[0] = float(v.x), dst[1] = float(v.y), dst[2] = float(v.z);
}

// A texture of side n with the full MIP chain, q = fn(u, v, channel) at texel centres.
sepal::AssetTexture make_texture(int n, uint32_t role, uint32_t term, float scale, float bias, int bits,
                                 const std::function<double(double, double, int)>& fn) {
    sepal::AssetTexture t;
    t.desc.width = t.desc.height = uint32_t(n);
    t.desc.channels = 3;
    t.desc.bits = uint32_t(bits);
    t.desc.role = role;
    t.desc.term = term;
    for (int c = 0; c < 4; ++c) t.desc.scale[c] = scale, t.desc.bias[c] = bias;
    uint32_t levels = 0;
    for (int side = n; side >= 1; side /= 2) {
        ++levels;
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i)
                for (int c = 0; c < 3; ++c) {
                    const double q = std::min(1.0, std::max(0.0, fn((i + 0.5) / side, (j + 0.5) / side, c)));
                    if (bits == 8) {
                        t.data.push_back(uint8_t(std::lround(q * 255.0)));
                    } else {
                        const uint16_t v = uint16_t(std::lround(q * 65535.0));
                        t.data.push_back(uint8_t(v & 0xFF));
                        t.data.push_back(uint8_t(v >> 8));
                    }
                }
    }
    t.desc.levels = levels;
    return t;
}

bool planned(sepal::AssetData* a) {
    std::string err;
    return sepal::build_plan(a, &err);
}

// The runtime's tangent fallback, restated (runtime/src/common.cpp shading_frame): the x axis,
// or y when |n.x| >= 0.9, made perpendicular to n.
glm::dvec3 fallback_tangent(const glm::dvec3& n) {
    const glm::dvec3 axis = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(axis - glm::dot(axis, n) * n);
}

}  // namespace

std::vector<Backend> all_backends() {
    std::vector<Backend> b;
    auto gl = [&](const char* name, int gles, sepal_draw_mode mode, uint32_t mask) {
        Backend x;
        x.name = name;
        x.gles = gles;
        x.mode = mode;
        x.mask = mask;
        b.push_back(x);
    };
    gl("gles1", 1, SEPAL_MODE_MULTIPASS, 0);
    gl("gles1 -subtract", 1, SEPAL_MODE_MULTIPASS, SEPAL_MASK_BLEND_SUBTRACT);
    gl("gles1 -multitex", 1, SEPAL_MODE_MULTIPASS, SEPAL_MASK_MULTITEXTURE);
    gl("gles1 -sub -multitex", 1, SEPAL_MODE_MULTIPASS, SEPAL_MASK_BLEND_SUBTRACT | SEPAL_MASK_MULTITEXTURE);
    gl("gles1 -fbo -npot", 1, SEPAL_MODE_MULTIPASS, SEPAL_MASK_FBO | SEPAL_MASK_NPOT);
    gl("gles2", 2, SEPAL_MODE_MULTIPASS, 0);
    gl("gles2 -subtract", 2, SEPAL_MODE_MULTIPASS, SEPAL_MASK_BLEND_SUBTRACT);
    gl("gles2 float-target", 2, SEPAL_MODE_MULTIPASS, 0);
    b.back().float_target = true;
    gl("gles2-fused", 2, SEPAL_MODE_FUSED_VERTEX, 0);
    gl("gles2-fused-pixel", 2, SEPAL_MODE_FUSED_PIXEL, 0);
    Backend cpu;
    cpu.name = "cpu";
    cpu.cpu = true;
    b.push_back(cpu);
    return b;
}

bool all_finite(const sepal::Image& img) {
    for (float v : img.data)
        if (!std::isfinite(v)) return false;
    return true;
}

sepal::Image display(const sepal::Image& linear) {
    sepal::Image out = linear;
    for (float& v : out.data) v = std::isnan(v) ? 0.0f : std::min(1.0f, std::max(0.0f, v));
    return out;
}

Frame render(const Backend& b, const std::vector<uint8_t>& bytes, const sepal_ports::SceneSetup& s) {
    Frame f;
    if (b.cpu) {
        sepal::Image img(s.width, s.height, 3);
        f.ok = sepal_ports::render_asset_cpu(bytes.data(), bytes.size(), s, nullptr, &img.data, nullptr, &f.err,
                                             &f.stats);
        f.image = img;
        f.finite = f.ok && all_finite(img);
        f.path = "cpu";
        return f;
    }
    sepal_ports::GlRenderOptions opt;
    opt.gles_version = b.gles;
    opt.mode = b.mode;
    opt.mask = b.mask;
    opt.float_target = b.float_target;
    sepal_ports::GlRenderInfo info;
    std::vector<uint8_t> rgba;
    f.ok = sepal_ports::render_asset_headless(bytes.data(), bytes.size(), s, opt, &rgba, &info, &f.err);
    if (!f.ok) return f;
    f.stats = info.stats;
    f.path = info.path + (b.float_target ? ", half-float target" : "");
    if (b.float_target) {
        f.image = sepal::Image(s.width, s.height, 3);
        f.image.data = info.float_rgb;
    } else {
        f.image = sepal::to_rgb(sepal::image_from_rgba8(rgba.data(), s.width, s.height));
    }
    f.finite = all_finite(f.image);
    return f;
}

void rebind(sepal_ports::SceneSetup* s) {
    s->mesh.vertices = s->vertices.data();
    s->mesh.indices = s->indices.data();
}

sepal_ports::SceneSetup quad_scene(const QuadConfig& q, int width, int height, int cells) {
    sepal_ports::SceneSetup s;
    s.width = width;
    s.height = height;
    sepal_camera& cam = s.scene.camera;
    const float eye[3] = {0, -4, 0}, up[3] = {0, 0, 1};
    std::copy(eye, eye + 3, cam.eye);
    std::fill(cam.target, cam.target + 3, 0.0f);
    std::copy(up, up + 3, cam.up);
    cam.fovy_degrees = 10;
    s.mesh_name = "quad";
    s.vertices.resize(size_t(cells + 1) * (cells + 1));
    s.indices.resize(size_t(cells) * cells * 6);
    s.mesh = {s.vertices.data(), s.indices.data(), int(s.vertices.size()), int(s.indices.size())};
    sepal_error e = {};
    sepal_mesh_grid(cells, &s.mesh, &e);
    const glm::dvec3 E(eye[0], eye[1], eye[2]), Up(0, 0, 1);
    const double ti = rad(q.theta_i), to = rad(q.theta_o);
    // The light.
    sepal_light& light = s.scene.lights[0];
    s.scene.light_count = 1;
    glm::dvec3 L(1, 0, 0);  // kDirectional: perpendicular to the view at the centre
    double intensity = 1.0;
    if (q.light == QuadLight::kAtEye) {
        light.type = SEPAL_LIGHT_POINT;
        put(light.position, E);
        intensity = q.irradiance * glm::dot(E, E) / std::max(std::cos(ti), 1e-6);
    } else {
        if (q.light == QuadLight::kMirror) {  // at 2 theta_i from the view, around z
            L = glm::dvec3(std::sin(2 * ti), -std::cos(2 * ti), 0.0);
            L = glm::normalize(L);
        }
        light.type = SEPAL_LIGHT_DIRECTIONAL;
        put(light.position, L);
        intensity = q.irradiance / std::max(std::cos(ti), 1e-6);
    }
    if (!(std::cos(ti) > 0)) intensity = q.irradiance;
    for (int c = 0; c < 3; ++c) light.intensity[c] = float(intensity);
    for (int i = 0; i < s.mesh.vertex_count; ++i) {
        sepal_vertex& v = s.vertices[size_t(i)];
        const double x = 0.3 * v.position[0], z = 0.3 * v.position[1];
        const glm::dvec3 P(x, 0.0, z);  // the grid rotated into the x-z plane, facing -y
        put(v.position, P);
        const glm::dvec3 e = glm::normalize(E - P);
        glm::dvec3 n, t;
        if (q.light == QuadLight::kAtEye) {
            const glm::dvec3 p = glm::normalize(Up - glm::dot(Up, e) * e);
            n = std::cos(to) * e + std::sin(to) * p;
            t = e - glm::dot(e, n) * n;  // the eye's azimuth is the tangent's
            t = glm::length(t) > 1e-9 ? glm::normalize(t) : p;
        } else if (q.light == QuadLight::kMirror) {
            n = glm::normalize(e + L);
            t = glm::normalize(Up - glm::dot(Up, n) * n);
        } else {
            // n = a e + b L + c w with n.e = cos(theta_o), n.L = cos(theta_i), |n| = 1.
            const double g = glm::dot(e, L), co = std::cos(to), ci = std::cos(ti);
            const double a = (co - g * ci) / (1 - g * g), b = (ci - g * co) / (1 - g * g);
            const glm::dvec3 m = a * e + b * L;
            const glm::dvec3 w = glm::normalize(glm::cross(e, L));
            n = m + std::sqrt(std::max(0.0, 1 - glm::dot(m, m))) * w;
            t = e - glm::dot(e, n) * n;
            t = glm::length(t) > 1e-9 ? glm::normalize(t) : fallback_tangent(n);
        }
        put(v.normal, n);
        put(v.tangent, t);
        v.tangent[3] = 1.0f;
    }
    return s;
}

sepal_ports::SceneSetup sphere_scene(int lights, int width, int height) {
    sepal_ports::SceneSetup s;
    s.width = width;
    s.height = height;
    s.mesh_name = "sphere";
    test_fx::test_lights(&s.scene, lights);
    std::string err;
    sepal_ports::load_scene_mesh(&s, &err);
    return s;
}

BrokenMesh broken_sphere(int lights) {
    BrokenMesh b;
    b.broken = sphere_scene(lights);
    sepal_ports::SceneSetup& s = b.broken;
    const int slices = 64, row = slices + 1;
    auto at = [&](int ring, int k) -> sepal_vertex& { return s.vertices[size_t(ring * row + k)]; };
    const float nan = NAN, inf = INFINITY;
    std::vector<int> repaired;  // vertices whose tangent the runtime must replace
    // Degenerate tangents, on the lit side (rings 8..14, around the light's longitude).
    for (int k = 0; k < 4; ++k) {  // zero
        sepal_vertex& v = at(10, 40 + 2 * k);
        v.tangent[0] = v.tangent[1] = v.tangent[2] = 0;
        repaired.push_back(10 * row + 40 + 2 * k);
    }
    for (int k = 0; k < 4; ++k) {  // parallel to the normal (and its opposite)
        sepal_vertex& v = at(12, 40 + 2 * k);
        for (int c = 0; c < 3; ++c) v.tangent[c] = (k % 2 ? -2.0f : 1.0f) * v.normal[c];
        repaired.push_back(12 * row + 40 + 2 * k);
    }
    for (int k = 0; k < 3; ++k) {  // NaN
        sepal_vertex& v = at(14, 40 + 2 * k);
        v.tangent[k] = nan;
        repaired.push_back(14 * row + 40 + 2 * k);
    }
    at(8, 44).tangent[3] = nan;  // handedness NaN: the tangent itself is kept
    at(8, 46).tangent[3] = -inf;
    repaired.push_back(8 * row + 44);
    repaired.push_back(8 * row + 46);
    b.fallback_tangents = int(repaired.size());
    // Bad vertices: the triangles around them are skipped.
    std::vector<int> bad = {9 * row + 36, 11 * row + 36, 13 * row + 36, 15 * row + 36};
    s.vertices[size_t(bad[0])].normal[1] = nan;
    for (int c = 0; c < 3; ++c) s.vertices[size_t(bad[1])].normal[c] = 0;
    s.vertices[size_t(bad[2])].position[2] = nan;
    s.vertices[size_t(bad[3])].position[0] = inf;
    b.bad_vertices = int(bad.size());
    // Zero-area triangles appended: repeated corners, and three collinear points on the
    // equator's chord (a, midpoint vertex of a, b by position, b) made exact by copying.
    const int used = s.mesh.index_count;
    std::vector<uint16_t> extra;
    for (int k = 0; k < 6; ++k) {
        const uint16_t a = uint16_t(16 * row + 10 + k), c = uint16_t(17 * row + 10 + k);
        const uint16_t tri[3] = {a, a, c};
        extra.insert(extra.end(), tri, tri + 3);
    }
    {
        // Three new vertices on one axis-aligned line (exactly collinear in float), placed
        // inside the sphere: a zero-area triangle that also is not repeated corners.
        const sepal_vertex model = s.vertices[size_t(20 * row + 5)];
        const uint16_t first = uint16_t(s.mesh.vertex_count);
        for (int k = 0; k < 3; ++k) {
            sepal_vertex v = model;
            v.position[0] = 0.25f * float(k + 1), v.position[1] = -0.5f, v.position[2] = -0.5f;
            s.vertices.push_back(v);
        }
        s.mesh.vertex_count += 3;
        const uint16_t tri[3] = {first, uint16_t(first + 1), uint16_t(first + 2)};
        extra.insert(extra.end(), tri, tri + 3);
    }
    b.zero_area_triangles = int(extra.size() / 3);
    s.indices.resize(size_t(used) + extra.size());
    std::copy(extra.begin(), extra.end(), s.indices.begin() + used);
    s.mesh.index_count = int(s.indices.size());
    rebind(&s);
    for (int t = 0; t < used; t += 3) {
        bool touches = false;
        for (int k = 0; k < 3; ++k) touches = touches || std::count(bad.begin(), bad.end(), int(s.indices[size_t(t + k)]));
        b.skipped_triangles += touches;
    }
    // The clean twin: bad triangles and zero-area ones dropped, tangents as documented.
    b.clean = b.broken;
    sepal_ports::SceneSetup& c = b.clean;
    c.indices.clear();
    for (int t = 0; t < used; t += 3) {
        bool touches = false;
        for (int k = 0; k < 3; ++k) touches = touches || std::count(bad.begin(), bad.end(), int(s.indices[size_t(t + k)]));
        if (!touches) c.indices.insert(c.indices.end(), s.indices.begin() + t, s.indices.begin() + t + 3);
    }
    c.mesh.index_count = int(c.indices.size());
    for (int i : repaired) {
        sepal_vertex& v = c.vertices[size_t(i)];
        const glm::dvec3 n = glm::normalize(v3(v.normal));
        const glm::dvec3 t = v3(v.tangent);
        const bool xyz_ok = std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) &&
                            glm::length(t - glm::dot(t, n) * n) > 1e-6;
        put(v.tangent, xyz_ok ? glm::normalize(t - glm::dot(t, n) * n) : fallback_tangent(n));
        v.tangent[3] = v.tangent[3] < 0.0f ? -1.0f : 1.0f;  // NaN -> +1, -inf -> -1
    }
    // Bad vertices stay in the array, unreferenced: harmless, and counted on both.
    rebind(&c);
    return b;
}

sepal::AssetData lobe_asset(sepal_param param, int side, int bits) {
    sepal::AssetData a = test_fx::base_asset(param, 1);
    a.textures.push_back(make_texture(side, SEPAL_ROLE_G, 0, 1.2f, 0.0f, bits, [](double u, double v, int c) {
        const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5);
        return 0.08 + 0.92 * std::exp(-r2 * 30.0) * (0.85 + 0.05 * c);
    }));
    // H: gs-half and the others get an H that depends on the azimuth (so the t' frame and
    // the tangents matter); rusinkiewicz an H symmetric about the pole, as an isotropic
    // BRDF's is (at h = n the azimuth of d is arbitrary, and f does not depend on it).
    const bool symmetric = param == SEPAL_PARAM_RUSINKIEWICZ;
    a.textures.push_back(make_texture(side, SEPAL_ROLE_H, 0, 0.5f, 0.0f, bits, [symmetric](double u, double v, int) {
        const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5);
        return symmetric ? 0.4 + 2.0 * r2 : 0.4 + 0.3 * u + 0.3 * v * v;
    }));
    planned(&a);
    return a;
}

sepal::AssetData constant_asset(sepal_param param, int side, double value) {
    sepal::AssetData a = test_fx::base_asset(param, 1);
    // G = H = sqrt(value): stored as q = 1 with that scale, exact at 8 bits.
    const float root = float(std::sqrt(value));
    for (uint32_t role : {uint32_t(SEPAL_ROLE_G), uint32_t(SEPAL_ROLE_H)})
        a.textures.push_back(make_texture(side, role, 0, root, 0.0f, 8, [](double, double, int) { return 1.0; }));
    planned(&a);
    return a;
}

sepal::AssetData huge_peak_asset() {
    sepal::AssetData a = test_fx::base_asset(SEPAL_PARAM_GS_HALF, 2);
    // Term 0: 0.3 everywhere. Term 1: a spike in G(h) at h = n reaching 1e4 - 0.3.
    a.textures.push_back(make_texture(32, SEPAL_ROLE_G, 0, 0.3f, 0.0f, 16, [](double, double, int) { return 1.0; }));
    a.textures.push_back(make_texture(32, SEPAL_ROLE_H, 0, 1.0f, 0.0f, 16, [](double, double, int) { return 1.0; }));
    a.textures.push_back(make_texture(32, SEPAL_ROLE_G, 1, 9999.7f, 0.0f, 16, [](double u, double v, int) {
        const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5);
        return std::exp(-r2 * 2000.0);  // about 1.5 texels wide at 32x32
    }));
    a.textures.push_back(make_texture(32, SEPAL_ROLE_H, 1, 1.0f, 0.0f, 16, [](double, double, int) { return 1.0; }));
    planned(&a);
    return a;
}

sepal::AssetData tiny_asset() {
    sepal::AssetData a = lobe_asset(SEPAL_PARAM_GS_HALF, 32);
    for (sepal::AssetTexture& t : a.textures)
        for (int c = 0; c < 4; ++c) t.desc.scale[c] *= 1e-4f;  // f ~ 1e-8 (products of two)
    planned(&a);
    return a;
}

sepal::AssetData zero_asset() {
    sepal::AssetData a = test_fx::base_asset(SEPAL_PARAM_GS_HALF, 1);
    for (uint32_t role : {uint32_t(SEPAL_ROLE_G), uint32_t(SEPAL_ROLE_H)})
        a.textures.push_back(make_texture(16, role, 0, 1.0f, 0.0f, 8, [](double, double, int) { return 0.0; }));
    // The plan of f = 1 * q_G * q_H (q = 0 everywhere): one product pass.
    planned(&a);
    return a;
}

sepal::AssetData signed_asset(sepal_param param) {
    sepal::AssetData a = test_fx::base_asset(param, 2);
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 0, 1.0f, 0.0f, 8, [](double u, double v, int c) {
        const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5);
        return std::exp(-r2 * 12.0) * (0.8 + 0.1 * c);
    }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 0, 0.3f, 0.0f, 8, [](double u, double v, int) { return 0.5 + 0.5 * u * v; }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_G, 1, 0.6f, -0.3f, 8, [](double u, double, int) { return u; }));
    a.textures.push_back(make_texture(16, SEPAL_ROLE_H, 1, 0.1f, -0.02f, 8, [](double, double v, int) { return v; }));
    planned(&a);
    return a;
}

bool bake_asset(const std::string& spec, sepal_param param, int res, sepal::AssetData* out, std::string* err) {
    std::unique_ptr<sepal::Brdf> f = sepal::make_brdf(spec, err);
    if (!f) return false;
    sepal::BakeOptions o;
    o.params = {param == SEPAL_PARAM_RUSINKIEWICZ ? sepal::Param::Rusinkiewicz
                : param == SEPAL_PARAM_IV         ? sepal::Param::IncidentView
                : param == SEPAL_PARAM_VH         ? sepal::Param::ViewHalf
                : param == SEPAL_PARAM_AXIS       ? sepal::Param::Axis
                : param == SEPAL_PARAM_GS_MIRROR  ? sepal::Param::GsMirror
                                                : sepal::Param::GsHalf};
    o.resolutions = {res};
    o.methods = {sepal::Method::NMF};
    o.terms = {1};
    sepal::BakeResult r;
    if (!sepal::bake(*f, o, &r, err)) return false;
    *out = r.asset;
    return true;
}

bool encode(const sepal::AssetData& a, std::vector<uint8_t>* bytes, std::string* err) {
    return sepal::encode_asset(a, bytes, err);
}

}  // namespace extremes
