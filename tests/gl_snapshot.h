// A named list of GL state values for before/after comparisons (the frame state tests).
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace gl_snapshot {

struct Snapshot {
    std::vector<std::pair<std::string, double>> values;
    void add(const std::string& name, double v) { values.emplace_back(name, v); }
    void add(const std::string& name, const float* v, int n) {
        for (int i = 0; i < n; ++i) add(name + "[" + std::to_string(i) + "]", v[i]);
    }
    void add(const std::string& name, const int* v, int n) {
        for (int i = 0; i < n; ++i) add(name + "[" + std::to_string(i) + "]", v[i]);
    }
};

// The names whose values differ (the lists hold the same names in the same order).
inline std::string differences(const Snapshot& a, const Snapshot& b) {
    std::string out;
    if (a.values.size() != b.values.size()) return "snapshots of different sizes";
    for (size_t i = 0; i < a.values.size(); ++i)
        if (a.values[i].second != b.values[i].second)
            out += a.values[i].first + " " + std::to_string(a.values[i].second) + " -> " +
                   std::to_string(b.values[i].second) + "; ";
    return out;
}

#ifdef GL_VIEWPORT  // after <GLES/gl.h> or <GLES2/gl2.h>: the state both versions have
inline void add_core(Snapshot& s) {
    GLint i4[4], v = 0;
    GLfloat f4[4];
    GLboolean b4[4];
    glGetIntegerv(GL_VIEWPORT, i4), s.add("viewport", i4, 4);
    glGetIntegerv(GL_SCISSOR_BOX, i4), s.add("scissor box", i4, 4);
    const std::pair<const char*, GLenum> enables[] = {
        {"scissor", GL_SCISSOR_TEST}, {"stencil", GL_STENCIL_TEST}, {"polygon offset", GL_POLYGON_OFFSET_FILL},
        {"cull", GL_CULL_FACE},       {"depth test", GL_DEPTH_TEST}, {"blend", GL_BLEND},
        {"dither", GL_DITHER},        {"alpha to coverage", GL_SAMPLE_ALPHA_TO_COVERAGE}};
    for (const auto& e : enables) s.add(e.first, glIsEnabled(e.second));
    const std::pair<const char*, GLenum> ints[] = {
        {"front face", GL_FRONT_FACE},       {"cull face", GL_CULL_FACE_MODE},
        {"depth func", GL_DEPTH_FUNC},       {"active texture", GL_ACTIVE_TEXTURE},
        {"array buffer", GL_ARRAY_BUFFER_BINDING}, {"element buffer", GL_ELEMENT_ARRAY_BUFFER_BINDING},
        {"stencil func", GL_STENCIL_FUNC}};
    for (const auto& e : ints) glGetIntegerv(e.second, &v), s.add(e.first, v);
    glGetBooleanv(GL_COLOR_WRITEMASK, b4);
    for (int k = 0; k < 4; ++k) s.add("color mask", b4[k]);
    glGetBooleanv(GL_DEPTH_WRITEMASK, b4), s.add("depth mask", b4[0]);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, f4), s.add("clear color", f4, 4);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, f4), s.add("clear depth", f4[0]);
}
#endif

}  // namespace gl_snapshot
