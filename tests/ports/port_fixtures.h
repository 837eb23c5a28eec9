// Shared by the ports' end-to-end tests (windowed viewer under Xvfb, web page in headless
// Chromium): a baked 2-term asset and a copy of it with one pass masked, the command
// lines the ports print parsed back into scenes, and the headless render they are held to.
#pragma once
#include <string>
#include <vector>

#include "common/scene_flags.h"
#include "util/image.h"

namespace port_test {

// In dir: intact.sepal, a 2-term NMF Ward (gs-half, 32x32, peaks capped at 2, as
// `make run`: one product pass per term), and masked.sepal, the same with the second
// term's H texture zeroed (every level): what a runtime that skipped that term's pass
// would draw, on the plan paths and the fused ones alike. The tests must tell them apart.
struct Assets {
    std::string intact, masked;
};
Assets bake_assets(const std::string& dir);

// The golden tests' tolerances. Same driver (golden_materials_test.cpp's regression
// check): at most 0.5% of pixels more than 2 levels apart, PSNR at least 45 dB. Another
// rasterizer (headless_test.cpp's lit quad, "other Mesa versions"): 1% over 3 levels,
// PSNR at least 40 dB.
sepal::Tolerance golden_tolerance();
sepal::Tolerance cross_rasterizer_tolerance();

// Against the CPU backend (float, f = sum G H evaluated directly: no GL code shared with
// the ports' frames, so a runtime that draws wrong on GL is caught): golden_materials_test's
// bar for every GL backend, PSNR above 33 dB and under 3% of pixels more than 8 levels apart.
sepal::Tolerance cpu_tolerance();
sepal::Image render_cpu(const std::string& asset, const sepal_ports::SceneSetup& setup);

// Parses a "sepal-view --headless ASSET --backend B [scene flags] -o OUT" line.
struct Command {
    std::string asset, backend;
    sepal_ports::SceneSetup setup;
};
bool parse_command(const std::string& line, Command* c, std::string* err);

// The asset drawn headless (ports/common/render_gl) on a GL backend, as an 8-bit image.
sepal::Image render_headless(const std::string& asset, const sepal_ports::SceneSetup& setup, const std::string& backend);

// Whether a program is on PATH (tests fail, rather than skip, when `make deps` was not run).
bool have_program(const std::string& name);

}  // namespace port_test
