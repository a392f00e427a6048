#include "compiler/lower/Prefilter.h"

namespace moire::lower {

using ir::ValueId;

ValueId meanInk(ir::Builder& b, const Footprint& footprint, ValueId pointInk, ValueId halfWidth,
                const PixelFootprint& pixel) {
    ValueId nu = b.mul(footprint.grad, pixel.size); // members per pixel
    ValueId weight = b.smoothstep(b.constF(kMeanFrom), b.constF(kMeanFull), nu);
    if (footprint.first) {
        ValueId lowest = b.sub(footprint.index, b.mul(nu, b.constF(0.5)));
        ValueId below = b.lt(lowest, b.constF(*footprint.first - 0.5));
        weight = b.select(below, b.constF(0.0), weight);
    }
    // Where members are resolved (weight 0) the point rule alone is drawn, and the mean is not
    // computed: most pixels of most scenes.
    auto mean = [&] {
        ValueId w = b.mul(halfWidth, footprint.grad); // half-width in index units
        // The index's steps across the pixel's two sides: the gradient's components along them.
        ValueId gu = footprint.gradX, gv = footprint.gradY;
        if (pixel.cosTurn != ir::kNoValue) {
            gu =
                b.add(b.mul(footprint.gradX, pixel.cosTurn), b.mul(footprint.gradY, pixel.sinTurn));
            gv =
                b.sub(b.mul(footprint.gradY, pixel.cosTurn), b.mul(footprint.gradX, pixel.sinTurn));
        }
        ValueId along = b.mul(b.abs(gu), pixel.size), across = b.mul(b.abs(gv), pixel.size);
        ir::BuiltValue m =
            squareMeanInk(ir::BuiltValue(b, footprint.index), ir::BuiltValue(b, along),
                          ir::BuiltValue(b, across), ir::BuiltValue(b, w));
        return std::vector<ValueId>{b.mix(pointInk, m.id, weight)};
    };
    return b.ifThenElse(b.gt(weight, b.constF(0.0)), mean,
                        [&] { return std::vector<ValueId>{pointInk}; })[0];
}

ValueId crowdInk(ir::Builder& b, const CrowdEstimate& crowd, ValueId ink, ValueId halfWidth,
                 const PixelFootprint& /*pixel: the mean filter is on*/) {
    // Weighted by `engaged` alone, not handed over by members per pixel as a phase family's
    // mean is: the hand-over keeps resolved members drawn as strokes, but where a family
    // cannot resolve its members itself (a strided scan) the strokes it draws are a subset of
    // them, whatever their size on screen, and their ink is short by the members skipped.
    ValueId mean =
        crowd.mean != ir::kNoValue
            ? crowd.mean
            : b.min(b.mul(b.mul(halfWidth, b.constF(2.0)), crowd.density), b.constF(1.0));
    return b.mix(ink, mean, crowd.engaged);
}

} // namespace moire::lower
