// sepal-view's interactive mode: a window (ports/windowed/sepal_window.h) showing baked
// materials through the runtime, with the camera and the light under the mouse.
//
//   sepal-view ASSET.sepal|FOLDER|SPEC [--backend B] [--mask LIST] [viewer flags] [scene flags]
//
// ASSET.sepal shows that asset and lets n/N step through every *.sepal of its folder;
// FOLDER starts with the folder's first asset; anything else is a BRDF spec (a model spec
// or a measured file), baked on start through the `sepal` tool (below) with
// `sepal bake SPEC --param gs-half`.
//
// Controls (also printed by `h`):
//   left drag            orbit the camera around the target (0.5 degrees per pixel)
//   right or shift drag  move the first light around the target (0.5 degrees per pixel)
//   wheel, + / -         move the camera closer / further (x0.9 / x1.11 per step)
//   arrow keys           orbit by 5 degrees
//   b / B                next / previous backend: gles1, gles2, gles2-fused,
//                        gles2-fused-pixel, cpu, exact
//   1..9, 0              show the first k terms of the asset (a prefix), 0: all
//   m / M                next / previous mesh: sphere, torus, wave (and --mesh PATH.obj)
//   n / N                next / previous material in the folder
//   p                    PSNR of this view against the exact render (computed on request)
//   s                    screenshot: shot-NNN.png (the 3D view, comparable with
//                        --headless), shot-NNN-window.png (with the status line) and
//                        shot-NNN.txt (the command that renders the same view headless)
//   r                    reset the view;  h: help;  q, Esc: quit
//
// The status line (top of the window) shows the material, backend, terms, mesh, the last
// frame's draw time (sepal_draw + glFinish; the CPU draw for cpu) and whole frame time,
// draw calls and full-screen passes, the texture bytes on the GPU, and the PSNR once asked.
//
// The exact backend and PSNR need the exact renderer, which lives in offline/ (not linked
// into sepal-view). The viewer asks the `sepal` tool for it, as a process:
//   sepal render SPEC --backend exact <this view's scene flags> -o TMP.png
// SPEC is the asset's META "spec" (--spec overrides it). The tool is --sepal PATH, else
// $SEPAL_CLI, else the `sepal` beside the sepal-view binary, else `sepal` on PATH. Without
// it, exact and PSNR report "needs the sepal tool" and everything else works.
//
// Viewer flags: --shot-dir DIR (screenshots, default .), --sepal PATH, --spec SPEC,
// --terms K (start with a prefix), --frames N (draw N frames, print the median frame time,
// exit: the benchmark mode).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "common/scene_flags.h"

namespace sepal_ports {

struct ViewerOptions {
    std::string input;             // ASSET.sepal, FOLDER or SPEC
    std::string backend = "gles1"; // gles1, gles2, gles2-fused, gles2-fused-pixel, cpu, exact
    uint32_t mask = 0;             // SEPAL_MASK_* for the GL backends
    std::string shot_dir = ".";
    std::string sepal_tool;        // --sepal
    std::string spec;              // --spec
    int terms = 0;                 // --terms
    int frames = 0;                // --frames
};

// Returns how many arguments it consumed at argv[i] (0: not a viewer flag), or -1 with
// the reason in *err.
int parse_viewer_flag(int argc, char** argv, int i, ViewerOptions* o, std::string* err);
const char* viewer_flags_help();
// Runs the window until quit; returns the process exit code (0, 1 runtime or GL
// failure, 2 bad input). setup holds the scene flags and the mesh name (not yet loaded).
int run_viewer(const ViewerOptions& options, SceneSetup* setup);

// The folder of the running binary ("" when unknown).
std::string self_dir();
// Runs argv (argv[0] looked up on PATH when it has no slash) with its output in log;
// returns the exit status, or -1 when it could not run.
int run_process(const std::vector<std::string>& args, const std::string& log);
// The sepal tool: `given` (--sepal), else $SEPAL_CLI, else the one beside this binary, else
// `sepal` on PATH.
std::string sepal_tool(const std::string& given);

}  // namespace sepal_ports
