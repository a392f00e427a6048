// What the window shows, as the RGBA8 pixels uploaded to its one texture: the frame on screen
// fitted to the framebuffer, and the overlay (status line, error box) drawn over it. No GL
// here, so that the window's pixels can be checked without a display.
#pragma once

#include "runtime/view/FrameRenderer.h"
#include "runtime/view/Overlay.h"

#include <cstdint>
#include <vector>

namespace moire::view {

// The shown frame into `canvas` (w x h RGBA8, resized to fit): 1:1 when it is the window's
// size, each pixel a divisor x divisor block for a preview of a frame of the window's size,
// stretched (nearest pixel) while a resize waits for its frame. The picture is opaque
// (straight alpha over nothing: the window has no backdrop).
void blitFrame(const RenderedFrame& frame, int w, int h, std::vector<uint8_t>& canvas);

// The whole window: the frame (a dark grey before the first one), then the overlay.
void composeWindow(const RenderedFrame* shown, int w, int h, const OverlayText& text, int scale,
                   std::vector<uint8_t>& canvas);

} // namespace moire::view
