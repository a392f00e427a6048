// What the viewer draws over the picture: a status line along the bottom (frame time,
// backend, clock) and, while the scene's text has errors, a box at the top with the
// diagnostics' first lines. Drawn into the RGBA8 frame with the bitmap font.
#pragma once

#include "runtime/view/BitmapFont.h"

#include <string>
#include <vector>

namespace moire::view {

struct OverlayText {
    std::string status;                  // empty: no status line
    std::vector<std::string> errorLines; // empty: no error box
};

// The headline of each diagnostic (`file:line:col: error: message`), without the quoted
// source and caret lines, at most `max` of them; the first lines as they are when none looks
// like a diagnostic.
std::vector<std::string> errorHeadlines(const std::string& diagnostics, size_t max = 6);

// The status line's height in pixels at `scale`.
int statusHeight(int scale);

void drawOverlay(Canvas& canvas, const OverlayText& text, int scale);

} // namespace moire::view
