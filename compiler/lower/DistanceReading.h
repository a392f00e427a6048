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
// Components (a, c) along the pixel's sides as world components: onPixelSides' inverse (the
// pixel's sides run along the world's axes turned by the camera).
inline Offset worldOf(ir::Builder& b, ir::ValueId a, ir::ValueId c, const PixelFootprint& pixel) {
    if (pixel.cosTurn == ir::kNoValue) return {a, c};
    return {b.sub(b.mul(a, pixel.cosTurn), b.mul(c, pixel.sinTurn)),
            b.add(b.mul(a, pixel.sinTurn), b.mul(c, pixel.cosTurn))};
}
inline Offset offsetOf(ir::Builder& b, ir::ValueId a, ir::ValueId c, const PixelFootprint& pixel) {
    const Offset o = worldOf(b, a, c, pixel);
    return {b.mul(pixel.size, o.ox), b.mul(pixel.size, o.oy)};
}

// The distance at a point and its gradient along the pixel's sides, per world unit.
struct Reading {
    ir::ValueId d, gu, gv, length;
};
inline Reading readAt(ir::Builder& b, ir::ValueId d, const PixelFootprint& pixel) {
    PixelSides g = onPixelSides(b, b.emit(ir::Op::DerivX, {d}), b.emit(ir::Op::DerivY, {d}), pixel);
    return {d, g.u, g.v, b.hypot(g.u, g.v)};
}

// A reading's gradient length, held above 1e-30 so that dividing by it stays finite.
inline ir::ValueId heldLength(ir::Builder& b, const Reading& r) {
    return b.max(r.length, b.constF(1e-30));
}

// A reading's unit normal along the pixel's sides.
struct Normal {
    ir::ValueId u, v;
};
inline Normal unitNormal(ir::Builder& b, const Reading& r) {
    const ir::ValueId length = heldLength(b, r);
    return {b.div(r.gu, length), b.div(r.gv, length)};
}

// A point in the pixel's own frame: world units along its sides from its centre.
struct PixelPoint {
    ir::ValueId u, v;
};

inline ir::ValueId fract(ir::Builder& b, ir::ValueId v) {
    return b.sub(v, b.floor(v));
}

// The R2 sequence's steps: the plastic number's inverse and its square. Its points have no
// rows for a family's rows to alias with.
constexpr double kR2a = 0.7548776662466927, kR2b = 0.5698402909980532;

// A shift in [0, 1)^2 that runs over the frame's pixels as an R2 sequence does, the same on
// every backend: points of the pixel moved by it from pixel to pixel do not line up with a
// family's rows as the same points in every pixel would.
inline PixelPoint pixelShift(ir::Builder& b) {
    const ir::ValueId px = b.leaf(ir::Op::PixelX), py = b.leaf(ir::Op::PixelY);
    return {fract(b, b.add(b.mul(px, b.constF(kR2a)), b.mul(py, b.constF(kR2b)))),
            fract(b, b.add(b.mul(px, b.constF(kR2b)), b.mul(py, b.constF(kR2a))))};
}

// The reading at p, a point of the pixel. Where p stands depends on other readings'
// gradients (a probe along a normal), so it is detached: the gradient read there is the
// distance's at p, not a derivative of a derivative.
inline Reading readThere(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                         PixelPoint p) {
    const ir::ValueId u = b.emit(ir::Op::Detach, {p.u}), v = b.emit(ir::Op::Detach, {p.v});
    const Offset o = offsetOf(b, b.div(u, pixel.size), b.div(v, pixel.size), pixel);
    return readAt(b, at(b, o.ox, o.oy), pixel);
}

// The foot of a reading's member from its point p, the nearest point of its centre line to
// first order: p - d grad d / |grad d|^2. Where the gradient vanishes the foot is NaN, or, with
// `held` (the denominator held above 1e-30), p itself.
inline PixelPoint footFrom(ir::Builder& b, const Reading& r, PixelPoint p, bool held) {
    ir::ValueId squared = b.mul(r.length, r.length);
    if (held) squared = b.max(squared, b.constF(1e-30));
    const ir::ValueId k = b.div(r.d, squared);
    return {b.sub(p.u, b.mul(k, r.gu)), b.sub(p.v, b.mul(k, r.gv))};
}

// How far `to` stands from `from` along the unit normal n.
inline ir::ValueId offsetAlong(ir::Builder& b, PixelPoint from, PixelPoint to, Normal n) {
    return b.add(b.mul(b.sub(to.u, from.u), n.u), b.mul(b.sub(to.v, from.v), n.v));
}

// A reading's normal as a doubled angle, (cos 2 theta, sin 2 theta): a normal and its opposite
// are one direction. (0, 0) where the gradient vanishes.
struct DoubledAngle {
    ir::ValueId cos2, sin2;
};
inline DoubledAngle doubledAngle(ir::Builder& b, const Reading& r) {
    const ir::ValueId squared = b.max(b.mul(r.length, r.length), b.constF(1e-30));
    return {b.div(b.sub(b.mul(r.gu, r.gu), b.mul(r.gv, r.gv)), squared),
            b.div(b.mul(b.constF(2.0), b.mul(r.gu, r.gv)), squared)};
}

// How far the unit normal m has turned from the unit normal n: their cosine, and the angle's
// tangent (n x m) / (n . m), its denominator held above 1e-6 (a normal turned a right angle or
// more is another side's, which a caller tells by the cosine).
struct Turn {
    ir::ValueId cosine, tangent;
};
inline Turn turnOf(ir::Builder& b, Normal n, Normal m) {
    const ir::ValueId cosine = b.add(b.mul(n.u, m.u), b.mul(n.v, m.v));
    return {cosine, b.div(b.sub(b.mul(n.u, m.v), b.mul(n.v, m.u)), b.max(cosine, b.constF(1e-6)))};
}

// The k-th of n squares' centres along a pixel's side, in pixel units from its centre.
inline ir::ValueId place(ir::Builder& b, ir::ValueId k, ir::ValueId n) {
    return b.sub(b.div(b.add(k, b.constF(0.5)), n), b.constF(0.5));
}
inline ir::ValueId place(ir::Builder& b, ir::ValueId k, int n) {
    return place(b, k, b.constF(n));
}

} // namespace moire::lower
