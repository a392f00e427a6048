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

// The diagnostics as the terminal shows them, each whole: its headline
// (`file:line:col: error: message`), the quoted source line and the caret under the value
// (the font is fixed-width, so the caret stands under its column). As many whole diagnostics
// as fit in `max` lines (the first always), then "(and N more)"; text that does not look like
// diagnostics (a backend's failure) is shown as it is, up to `max` lines.
std::vector<std::string> errorLines(const std::string& diagnostics, size_t max = 12);

// The status line's height in pixels at `scale`.
int statusHeight(int scale);

void drawOverlay(Canvas& canvas, const OverlayText& text, int scale);

} // namespace moire::view
