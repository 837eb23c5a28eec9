// The runtime's frame descriptions for a SceneSetup (the ports' shared scene), with the
// buffers sized here, so each port sets only what it does differently.
//
// Usage:
//   std::vector<float> scratch;
//   sepal_draw_desc d = scene_draw_desc(&material, setup, SEPAL_MODE_MULTIPASS, &scratch);
//   sepal_draw(&d, &stats, &err);
//   CpuFrame cpu;  sepal_cpu_desc c = scene_cpu_desc(&asset, setup, &cpu, &stats);
//   sepal_draw_cpu(&c, &err);   // cpu.rgb: linear RGB, top row first
//   EmulatedFrame em;  sepal_emulate_desc m = scene_emulate_desc(&asset, setup, 1, 0, &em, &stats);
//   sepal_emulate_draw(&m, &err);  // em.rgba: what GL ES 1.1 shows
#pragma once
#include <vector>

#include "common/scene_flags.h"
#include "sepal/sepal_material.h"
#include "sepal/internal/sepal_emulate.h"

namespace sepal_ports {

sepal_draw_desc scene_draw_desc(const sepal_material* material, const SceneSetup& setup, sepal_draw_mode mode,
                                std::vector<float>* scratch);

struct CpuFrame {
    std::vector<float> rgb, depth, scratch;
};
// rgb is cleared to 0; stats may be NULL.
sepal_cpu_desc scene_cpu_desc(const sepal_asset* asset, const SceneSetup& setup, CpuFrame* frame,
                              sepal_draw_stats* stats);

struct EmulatedFrame {
    std::vector<uint8_t> rgba;
    std::vector<float> scratch;
};
// The GL ES emulator's frame (gles_version 1 or 2, capabilities masked by mask); rgba is
// cleared to 0; stats may be NULL.
sepal_emulate_desc scene_emulate_desc(const sepal_asset* asset, const SceneSetup& setup, int gles_version,
                                      uint32_t mask, EmulatedFrame* frame, sepal_draw_stats* stats);

}  // namespace sepal_ports
