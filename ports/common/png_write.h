// PNG output for the ports' tools (sepal-view): written next to the target and renamed,
// so a failed run never leaves a half-written file.
#pragma once
#include <stdint.h>

#include <string>

namespace sepal_ports {

// rgba: width x height RGBA8, top row first, written as an opaque RGB PNG (alpha dropped).
// False when encoding, writing or renaming fails.
bool write_png_atomic(const std::string& path, int width, int height, const uint8_t* rgba);

}  // namespace sepal_ports
