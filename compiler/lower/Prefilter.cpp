#include "compiler/lower/Prefilter.h"

namespace moire::lower {

using ir::ValueId;

ValueId meanInk(ir::Builder& b, const Footprint& footprint, ValueId pointInk, ValueId halfWidth,
                ValueId pixel) {
    ValueId nu = b.mul(footprint.grad, pixel);    // members per pixel
    ValueId w = b.mul(halfWidth, footprint.grad); // half-width in index units
    ir::BuiltValue mean =
        boxMeanInk(ir::BuiltValue(b, footprint.index), ir::BuiltValue(b, nu), ir::BuiltValue(b, w));
    ValueId weight = b.smoothstep(b.constF(kMeanFrom), b.constF(kMeanFull), nu);
    if (footprint.first) {
        ValueId lowest = b.sub(footprint.index, b.mul(nu, b.constF(0.5)));
        ValueId below = b.lt(lowest, b.constF(*footprint.first - 0.5));
        weight = b.select(below, b.constF(0.0), weight);
    }
    return b.mix(pointInk, mean.id, weight);
}

} // namespace moire::lower
