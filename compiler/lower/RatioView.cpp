#include "compiler/lower/RatioView.h"

namespace moire::lower {

using ir::ValueId;

Ink ratioViewInk(ir::Builder& b, const Character& c) {
    ValueId one = b.constF(1.0);
    ValueId grey = b.clamp(b.div(c.mu, b.constF(kRatioScale)), b.constF(0.0), one);
    grey = b.denan(grey, one); // no character reads as no fringe
    // The order's colour, by thresholds on sum |k_i| (an integer held as a float).
    ValueId order = characterOrder(b, c);
    auto pick = [&](size_t channel) {
        ValueId v = b.constF(kOrderColours[3][channel]);
        v = b.select(b.lt(order, b.constF(7.5)), b.constF(kOrderColours[2][channel]), v);
        v = b.select(b.lt(order, b.constF(3.5)), b.constF(kOrderColours[1][channel]), v);
        v = b.select(b.lt(order, b.constF(2.5)), b.constF(kOrderColours[0][channel]), v);
        return b.mix(v, one, grey);
    };
    return {pick(0), pick(1), pick(2), one};
}

ValueId overlayCoverage(ir::Builder& b, const Character& c, std::span<const LayerFields> layers,
                        ValueId pixel) {
    if (c.count < 2) return b.constF(0.0);
    Combination comb = characterCombination(b, c, layers);
    // Distance to the nearest integer level of the combination, over its gradient's length
    // (Eq. 5 for the character's own field), in pixels.
    ValueId residual = b.abs(b.sub(comb.value, b.round(comb.value)));
    ValueId grad = b.max(b.hypot(comb.gradX, comb.gradY), b.constF(ir::kTiny));
    ValueId pixels = b.div(b.div(residual, grad), b.max(pixel, b.constF(ir::kTiny)));
    ValueId h = b.constF(kOverlayHalfWidthPixels), a = b.constF(kAntialiasPixels);
    ValueId line = b.sub(b.constF(1.0), b.smoothstep(b.sub(h, a), b.add(h, a), pixels));
    ValueId inRegime = b.le(c.mu, b.constF(kFringeMerit));
    ValueId cov = b.select(inRegime, line, b.constF(0.0));
    return b.denan(cov, b.constF(0.0));
}

Ink overlayFringes(ir::Builder& b, const Ink& acc, const Character& c,
                   std::span<const LayerFields> layers, ValueId pixel) {
    ValueId cov = overlayCoverage(b, c, layers, pixel);
    return inkOver(b, acc, b.constF(kOverlayCrimson[0]), b.constF(kOverlayCrimson[1]),
                   b.constF(kOverlayCrimson[2]), cov);
}

} // namespace moire::lower
