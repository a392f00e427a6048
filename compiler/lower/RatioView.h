// The ratio view and the fringe overlay (spec §4.2, Fig. 5d and 5e), built from a stack's
// winning character (Characters.h) at the pixel.
//
// Ratio view: the least merit min mu_k as a grey map, value = clamp(min mu_k / kRatioScale,
// 0, 1), so black is an infinitely broad fringe, the fringe criterion (1/4) sits at 25% and
// mu >= 1 (a beat as fast as its carriers) is white. Its dark end is hued by the winning
// character's order |k1| + |k2| (+ |k3|): the grey is mixed from the order's colour toward
// white, so where no fringe stands every order looks the same.
//   order 2      (1, +-1): the first-order difference and sum beats    black
//   order 3      (2, +-1), (1, +-2)                                   blue
//   order 4 - 7  (3, +-1), (3, +-2), (1, 1, -2), ...                  orange
//   order 8 +    deeper beats                                         purple
//
// Overlay: the unit level sets {sum k_i idx_i in Z} of the winning character, the fringe
// curves computed from the index fields alone, drawn in crimson, kOverlayHalfWidthPixels
// either side with the renderer's antialias band, and only where min mu_k <= 1/4: where the
// criterion says no fringe exists, there is no curve to draw (Fig. 5d stops short of the
// lobes).
#pragma once

#include "compiler/lower/Characters.h"
#include "compiler/lower/LayerPipeline.h"

#include <array>

namespace moire::lower {

constexpr double kRatioScale = 1.0;
constexpr double kOverlayHalfWidthPixels = 0.75; // a 1.5 px line
// The palette's colours at full darkness, straight RGB, by order (see above).
inline constexpr std::array<std::array<double, 3>, 4> kOrderColours = {{
    {0.0, 0.0, 0.0},    // 2
    {0.10, 0.30, 0.85}, // 3
    {0.90, 0.50, 0.05}, // 4 - 7
    {0.55, 0.15, 0.65}, // 8 and beyond
}};
inline constexpr std::array<double, 3> kOverlayCrimson = {220.0 / 255, 20.0 / 255, 60.0 / 255};

// The ratio view's opaque colour (premultiplied, alpha 1) for the winner `c`.
Ink ratioViewInk(ir::Builder& b, const Character& c);

// The overlay laid over `acc` (whatever the view drew); `pixel` is the world size of a pixel.
// `layers` are the ones `c` was found for.
Ink overlayFringes(ir::Builder& b, const Ink& acc, const Character& c,
                   std::span<const LayerFields> layers, ir::ValueId pixel);

// The overlay's coverage alone (0 to 1), for tests and for a view that inks it otherwise.
ir::ValueId overlayCoverage(ir::Builder& b, const Character& c, std::span<const LayerFields> layers,
                            ir::ValueId pixel);

} // namespace moire::lower
