// Drawing a .sepaltree (runtime/include/sepal/sepal_tree.h) headless on GL ES or on the CPU,
// for `sepal ist render`, the tests and the benchmark.
//
// Usage:
//   std::vector<uint8_t> rgba; sepal_ports::GlRenderInfo info; std::string err;
//   sepal_ports::render_tree_headless(bytes.data(), bytes.size(), setup, opt, &rgba, &info, &err);
//   std::vector<float> rgb; sepal_ports::render_tree_cpu(bytes.data(), bytes.size(), setup, &rgb, &ms, &err);
//
// GlRenderOptions: gles_version 1 or 2, mode MULTIPASS (the bases composed) or, on GL ES 2,
// FUSED_PIXEL (the one-pass tree shader); mask as for materials; frames > 1 times the
// draw (two warm-up frames, median of the rest). diffuse and float_target do not apply.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/render_gl.h"

namespace sepal_ports {

bool render_tree_headless(const void* bytes, size_t size, const SceneSetup& setup, const GlRenderOptions& options,
                          std::vector<uint8_t>* rgba, GlRenderInfo* info, std::string* err);
bool render_tree_cpu(const void* bytes, size_t size, const SceneSetup& setup, std::vector<float>* rgb, double* ms,
                     std::string* err, sepal_draw_stats* stats = nullptr);

}  // namespace sepal_ports
