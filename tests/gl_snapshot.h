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

}  // namespace gl_snapshot
