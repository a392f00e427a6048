// What a family given by its distance says at a point of the pixel: the distance and its
// gradient along the pixel's sides (the compiler's AD of the family's expression), shared by
// the reading in parts (DistanceFamily.cpp) and the reading of crowded members by their tubes
// (DistanceTubes.cpp).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/Prefilter.h"

#include <functional>

namespace moire::lower {

// The family's distance at the pixel's centre moved by (ox, oy) world units.
using DistanceAt = std::function<ir::ValueId(ir::Builder&, ir::ValueId ox, ir::ValueId oy)>;

// A point of the pixel, (a, c) pixel units along its sides from its centre, as a world offset.
struct Offset {
    ir::ValueId ox, oy;
};
inline Offset offsetOf(ir::Builder& b, ir::ValueId a, ir::ValueId c, const PixelFootprint& pixel) {
    if (pixel.cosTurn == ir::kNoValue) return {b.mul(pixel.size, a), b.mul(pixel.size, c)};
    // The pixel's sides run along the world's axes turned by the camera (onPixelSides).
    return {b.mul(pixel.size, b.sub(b.mul(a, pixel.cosTurn), b.mul(c, pixel.sinTurn))),
            b.mul(pixel.size, b.add(b.mul(a, pixel.sinTurn), b.mul(c, pixel.cosTurn)))};
}

// The distance at a point and its gradient along the pixel's sides, per world unit.
struct Reading {
    ir::ValueId d, gu, gv, length;
};
inline Reading readAt(ir::Builder& b, ir::ValueId d, const PixelFootprint& pixel) {
    PixelSides g = onPixelSides(b, b.emit(ir::Op::DerivX, {d}), b.emit(ir::Op::DerivY, {d}), pixel);
    return {d, g.u, g.v, b.hypot(g.u, g.v)};
}

// The k-th of n squares' centres along a pixel's side, in pixel units from its centre.
inline ir::ValueId place(ir::Builder& b, ir::ValueId k, int n) {
    return b.sub(b.div(b.add(k, b.constF(0.5)), b.constF(n)), b.constF(0.5));
}

} // namespace moire::lower
