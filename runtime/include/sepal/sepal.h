// sepal.h - the sepal runtime in one include: capabilities, meshes, materials, scenes,
// the software rasterizer and the asset format. C99 or C++.
//
// Usage (installed with `make install PREFIX=DIR`; DIR/lib/pkgconfig on PKG_CONFIG_PATH):
//   #include <sepal/sepal.h>
//   #include <sepal/sepal_headless.h>   // only if you let the headless EGL port make the context
//   $ cc -std=c99 app.c $(pkg-config --cflags --libs sepal)
// examples/minimal.c is a complete program (headless context, asset, one frame).
//
// What each header covers, and its usage block (C99, compiled by `make check-c99`: the
// names a block uses without declaring them are the program's, tests/check_c99.sh lists them):
//   sepal_rt.h        errors, GL capability checks, meshes (sphere, torus, OBJ...), preview
//   sepal_scene.h     camera and lights: what every backend draws
//   sepal_material.h  baked assets on the GPU (GL ES 1.1 and GL ES 2) and the CPU backend
//   sepal_frame.h     a frame of many objects in the engine's framebuffer, its GL state kept
//   sepal_raster.h    the software rasterizer the CPU backend uses
//   sepal_format.h    the .sepal file format (data only)
//   sepal_asset.h     its reader, the parameterizations' texture coordinates, the checksum
//   sepal_tree.h      multiresolution (tree) assets on GL ES 1.1 and GL ES 2
//   sepal_sampler.h   factored importance sampling of a baked material (Lawrence 2004)
//   sepal_version.h   SEPAL_VERSION_*, compile time (sepal_version() answers at run time)
//
// sepal does NOT: create windows or GL contexts (a port hands the current context in),
// read files (the caller passes bytes), allocate after loading (callers hand in memory),
// raise C++ exceptions, or keep global state. Link: -lsepal and the platform's GL ES libraries
// (libGLESv1_CM, libGLESv2); the headless port adds -lsepal_headless and EGL.
//
// Thread safety (each header states its own): functions that touch no GL (parsing, texture
// coordinates, scene matrices, meshes, the rasterizer, the CPU backend, the
// sampler) keep no global state, so any threads may call them at once on distinct outputs;
// functions that call GL run on the thread whose context is current, one at a time per
// context. Parsed assets, samplers and trees are read-only after parsing and may be shared.
#pragma once

#include "sepal/sepal_version.h"  /* SEPAL_VERSION_*: defined there only */

#include "sepal/sepal_rt.h"
#include "sepal/sepal_scene.h"
#include "sepal/sepal_format.h"
#include "sepal/sepal_asset.h"
#include "sepal/sepal_material.h"
#include "sepal/sepal_frame.h"
#include "sepal/sepal_raster.h"
#include "sepal/sepal_sampler.h"
#include "sepal/sepal_tree.h"
