// Helpers for the doctest suites: golden images, temporary folders, running binaries.
//
// Golden images live in fixtures/golden/<name>.png. Each test states its own tolerance
// (sepal::Tolerance: max channel difference, share of pixels over it, PSNR floor).
// SEPAL_UPDATE_GOLDENS=1 (`make update-goldens`) rewrites the goldens instead of
// comparing. A failed comparison leaves <name>.actual.png, <name>.expected.png and
// <name>.heatmap.png in build/test-output/ and names them in the message.
#pragma once
#include <string>

#include "cli/cli.h"
#include "util/image.h"

namespace sepal_test {

std::string source_path(const std::string& relative);  // inside the repository
std::string output_dir();                              // build/test-output (created)
std::string temp_dir();                                // a fresh folder per call
std::string bin(const std::string& name);              // build/bin/<name> of this build
// The build folder this test binary runs from (build, build/asan, ...: the parent of its bin/).
std::string build_dir();

// Empty when the image matches; otherwise the reason and the files written.
// owner=false: never rewrite the golden (a second test comparing against it).
std::string check_golden(const std::string& name, const sepal::Image& actual,
                         const sepal::Tolerance& tol, bool owner = true);
// A GL render against its golden. GL goldens are made on Mesa's llvmpipe (make
// update-goldens; CI's renderer): another driver rasterizes, interpolates and rounds
// differently (NVIDIA's GL ES 1.1 also lacks GL_OES_blend_subtract, so signed plans take
// another path). There the comparison is printed, not enforced, and the caller's tolerance
// against the exact render is what binds.
std::string check_gl_golden(const std::string& name, const sepal::Image& actual,
                            const sepal::Tolerance& tol, bool owner = true);
// The GL_RENDERER of a headless GL ES 1.1 context ("" when none can be made). The first
// call makes and destroys a probe context, which releases the thread's current one: call it
// between renders, not inside one.
const std::string& gl_renderer();
// Mesa's llvmpipe, the renderer the goldens and the tight rounding bounds were measured on
// (CI's). Other conformant drivers round and interpolate differently: tests give them the
// slack measured on NVIDIA's, never llvmpipe.
bool reference_renderer();
// The same against an explicit golden folder (for testing the harness itself).
std::string check_golden_in(const std::string& golden_dir, const std::string& name,
                            const sepal::Image& actual, const sepal::Tolerance& tol,
                            bool owner, bool update);
bool update_goldens();

// Runs a shell command; returns its exit status (or -1), output captured into *out.
int run(const std::string& command, std::string* out = nullptr);
// Runs a sepal subcommand in-process; returns its exit code, stdout + stderr in *out.
int run_cmd(const char* command, const std::vector<std::string>& args, std::string* out = nullptr);

}  // namespace sepal_test
