// What the viewer draws itself, around the runtime's frame: RGBA8 images copied into a
// rectangle of the window (the status line; the cpu and exact backends' frames), on
// GL ES 1.1 (fixed function) or GL ES 2 (a tiny shader), and the status text rasterized on
// the CPU (stb_easy_font's quads are axis-aligned rectangles: filled, not drawn).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

namespace sepal_ports {

// GL objects of one context (a GL ES 1.1 and a GL ES 2 context share nothing).
struct Blitter {
    int gles = 0;  // the version the objects were made under; 0 before the first blit
    uint32_t texture = 0, program = 0;
    int texture_width = 0, texture_height = 0;  // powers of two (GL ES 1.1 needs them)
};

// Copies rgba (width x height, top row first) 1:1 into the window at (x, y) from the
// top-left; the window is window_width x window_height. The blitter's objects are made
// on first use under the current context, whose version is gles.
bool blit_rgba(Blitter* b, int gles, const uint8_t* rgba, int width, int height, int x, int y, int window_width,
               int window_height, std::string* err);
// Deletes the blitter's objects; its context must be current.
void blit_release(Blitter* b);

// Lines of text (7 pixels high, 12 apart) on a dark strip of width x height, RGBA8.
void text_strip(const std::vector<std::string>& lines, int width, int height, std::vector<uint8_t>* rgba);

// Per-version executors (overlay_gles1.cpp, overlay_gles2.cpp); x, y in GL window
// coordinates (bottom-left origin). u, v: the image's extent in the texture.
// The quad both draw as a triangle strip: positions covering the viewport, and texture
// coordinates with t = 0 at the top (image rows are stored top first).
struct BlitQuad {
    float position[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    float uv[8];
    BlitQuad(float u, float v) : uv{0, v, u, v, 0, 0, u, 0} {}
};
bool blit_gles1(Blitter* b, int x, int y, int width, int height, float u, float v, std::string* err);
bool blit_gles2(Blitter* b, int x, int y, int width, int height, float u, float v, std::string* err);

}  // namespace sepal_ports
