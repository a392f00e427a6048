// A 5x7 bitmap font for the viewer's status line and error overlay, drawn straight into the
// RGBA8 frame before it is uploaded: no font files, no text rendering library, the same
// pixels on every machine. Printable ASCII (32 to 126); anything else draws as '?'.
#pragma once

#include <cstdint>
#include <string_view>

namespace moire::view {

struct Rgba8 {
    uint8_t r = 0, g = 0, b = 0, a = 255;
};

// An RGBA8 image in memory, rows top to bottom, drawn into in place.
struct Canvas {
    uint8_t* pixels = nullptr;
    int width = 0, height = 0;
};

// Blends `color` (its alpha is the opacity) over the rectangle, clipped to the canvas.
void fillRect(Canvas& canvas, int x, int y, int w, int h, Rgba8 color);

namespace font {

constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
constexpr int kAdvance = 6;    // a glyph and one column of space
constexpr int kLineHeight = 9; // a line and two rows of space

// Whether pixel (x, y) of character c's glyph is ink (x < 5, y < 7, y down).
bool ink(char c, int x, int y);
// The width in pixels of `text` drawn at `scale` (no trailing space).
int textWidth(std::string_view text, int scale = 1);
// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale block.
// Clipped to the canvas; no wrapping. Returns the x after the last glyph's advance.
int drawText(Canvas& canvas, int x, int y, std::string_view text, int scale, Rgba8 color);

} // namespace font
} // namespace moire::view
