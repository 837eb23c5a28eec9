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
// `make run`), and masked.sepal, the same with its second pass's colour zeroed: what a
// runtime that skipped that pass would draw. The tests must tell the two apart.
struct Assets {
    std::string intact, masked;
};
Assets bake_assets(const std::string& dir);

// The tolerance of the golden tests (golden_materials_test.cpp's regression check): at
// most 0.5% of pixels more than 2 levels apart, PSNR at least 45 dB.
sepal::Tolerance golden_tolerance();

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
