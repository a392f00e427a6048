#include "compiler/lower/DistanceRings.h"

#include "compiler/lower/DistanceDots.h"
#include "compiler/lower/LatticeCrowd.h"

#include <cmath>
#include <numbers>
#include <span>
#include <vector>

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

// The step along the level set to the second normal line (tangentStep): a 32nd of the point's
// distance from its member, so that near its cell's edge the second point seldom crosses it
// (with an eighth, 0.8% of the pixels of rings four a pixel read no round ring about their
// centres), and at least a 1024th of a pixel.
constexpr double kTangentShare = 1.0 / 32.0, kLeastStep = 1.0 / 1024.0;
// A point inside its ring: one of its two curvature readings within this share of R of the
// reach R - t an inside point has.
constexpr double kInsideWithin = 0.05;
// The ring's roundness: kRoundLooks points half its radius from its centre, a seventh of a
// turn apart, must read half its radius (within kRoundFrom of it to be trusted, not at all
// past kRoundFull), and the pixel's centre must stand its own distance from the ring read.
constexpr int kRoundLooks = 7;
constexpr double kRoundFrom = 0.02, kRoundFull = 0.04;
// A ring whose radius is under this share of the stroke's half-width is a dot (DistanceDots.h
// reads it); its radius read from a centre a rounding off is no ring's.
constexpr double kLeastRadius = 0.1;

// The unit normal of a reading, NaN where its gradient vanishes.
Normal rawNormal(ir::Builder& b, const Reading& r) {
    return {b.div(r.gu, r.length), b.div(r.gv, r.length)};
}

// The centre of curvature of the level set through p (read there as r), as how far along p's
// unit normal n it stands: where p's normal line meets the normal line of the point q a step
// `tau` along the level set (to n's left, or with a negative step its right). With t the level
// set's direction (n turned a right angle) and m q's normal, p + lambda n = q + mu m gives
// lambda = tau (t x m) / (n x m) = -tau (n . m) / (n x m); m's sign (which side of the ring q
// stands) drops out. Exact for a circle about any centre at any step, which is what a ring's
// level sets are, while q reads the same ring.
ValueId curvatureReach(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                       PixelPoint p, Normal n, ValueId tau) {
    const PixelPoint q{b.sub(p.u, b.mul(tau, n.v)), b.add(p.v, b.mul(tau, n.u))};
    const Normal m = rawNormal(b, readThere(b, at, pixel, q));
    const ValueId along = b.add(b.mul(n.u, m.u), b.mul(n.v, m.v));
    const ValueId across = b.sub(b.mul(n.u, m.v), b.mul(n.v, m.u));
    return b.div(b.neg(b.mul(tau, along)), across);
}

// The step to q: a share of p's distance from its member, and at least a share of the pixel,
// so that the normals turn by more than float's rounding of the world's coordinates where p
// stands on the ring itself.
ValueId tangentStep(ir::Builder& b, const PixelFootprint& pixel, ValueId t) {
    return b.max(b.mul(t, b.constF(kTangentShare)), b.mul(pixel.size, b.constF(kLeastStep)));
}

// The centre of the ring nearest p, the rings' radius known (`radius`, world units): a point
// outside its ring stands R + t from the centre, against its normal; one inside, R - t, along
// it. q a step to either side of p: near the edge of p's ring's cell one of them may read
// another ring, whose reach is no ring's about p, so the side and the reach that agree best
// with one of the two are taken.
PixelPoint ringCentreOf(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                        const Reading& r, PixelPoint p, ValueId radius) {
    const Normal n = rawNormal(b, r);
    const ValueId t = b.abs(b.div(r.d, r.length));
    const ValueId tau = tangentStep(b, pixel, t);
    const ValueId outside = b.neg(b.add(radius, t)), inside = b.sub(radius, t);
    ValueId offOutside = b.constF(1e30), offInside = offOutside;
    for (const ValueId step : {tau, b.neg(tau)}) {
        const ValueId reach = curvatureReach(b, at, pixel, p, n, step);
        offOutside = b.min(offOutside, b.denan(b.abs(b.sub(reach, outside)), b.constF(1e30)));
        offInside = b.min(offInside, b.denan(b.abs(b.sub(reach, inside)), b.constF(1e30)));
    }
    // A point further than R from its ring is outside it, and one that no q reads inside
    // within kInsideWithin of R is taken as outside: on the bisector of two rings (a half-step
    // of their lattice) both q may read the other ring, and where that bisector stands R
    // from both rings, inside would put the centre at the half-step itself.
    const ValueId isInside =
        b.emit(Op::And, {b.emit(Op::And, {b.lt(t, radius), b.lt(offInside, offOutside)}),
                         b.lt(offInside, b.mul(radius, b.constF(kInsideWithin)))});
    const ValueId lambda = b.select(isInside, inside, outside);
    return {b.add(p.u, b.mul(lambda, n.u)), b.add(p.v, b.mul(lambda, n.v))};
}

// The point lambda along the unit normal n from the pixel's centre.
PixelPoint along(ir::Builder& b, Normal n, ValueId lambda) {
    return {b.mul(lambda, n.u), b.mul(lambda, n.v)};
}

// How far the ring about c0, of radius `radius` in world units (its distance there `atCentre`),
// is round: the most share of half the radius by which a look half the radius out reads
// another distance than atCentre / 2.
ValueId roundness(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel, PixelPoint c0,
                  Normal n, ValueId radius, ValueId atCentre) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0), half = b.constF(0.5);
    const ValueId out = b.mul(radius, half), want = b.mul(atCentre, half);
    const Vals looked = b.loop(
        {zero, zero},
        [&](std::span<const ValueId> v) { return Vals{b.lt(v[0], b.constF(kRoundLooks))}; },
        [&](std::span<const ValueId> v) {
            const ValueId angle =
                b.mul(b.add(v[0], b.constF(0.25)), b.constF(2.0 * std::numbers::pi / kRoundLooks));
            const ValueId cu = b.cos(angle), cv = b.sin(angle);
            const PixelPoint look{b.add(c0.u, b.mul(out, b.sub(b.mul(n.u, cu), b.mul(n.v, cv)))),
                                  b.add(c0.v, b.mul(out, b.add(b.mul(n.u, cv), b.mul(n.v, cu))))};
            const ValueId d = readThere(b, at, pixel, look).d;
            const ValueId off = b.div(b.abs(b.sub(d, want)), want);
            return Vals{b.add(v[0], one), b.max(v[1], b.denan(off, one))};
        });
    return looked[1];
}

// The ring nearest the pixel's centre (its reading `centre`, its gradient not vanishing): its
// centre c0 (lambda along the centre's unit normal n), its radius in world units, and `off`,
// the share of half the radius by which the pixel's centre stands off its own distance from
// the ring read (|rho - R| = t).
struct CentreRing {
    ValueId lambda, radius, off;
};
CentreRing centreRing(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                      const Reading& centre, Normal n) {
    const ValueId zero = b.constF(0.0), far = b.constF(1e30), half = b.constF(0.5);
    const ValueId length = centre.length;
    const ValueId t = b.abs(b.div(centre.d, length));
    auto offOf = [&](ValueId lambda, ValueId radius) {
        return b.denan(
            b.div(b.abs(b.sub(b.abs(b.sub(b.abs(lambda), radius)), t)), b.mul(radius, half)), far);
    };
    // Its centre of curvature, with q to either side: the one whose centre stands the pixel
    // centre's own distance from the ring read there (where the other's q may read another
    // ring). It is read half-way from the pixel's centre to its ring, on the same normal line:
    // further from the edges of the ring's cell, where a q to either side of a pixel centre
    // by the corner four cells share may read other rings, and did in a float where a double
    // read its own (six pixels of 4800, rings four a pixel, left to the tubes on the JIT alone).
    const ValueId back = b.mul(t, b.constF(-0.5));
    const PixelPoint halfWay = along(b, n, back);
    const ValueId tau = tangentStep(b, pixel, b.mul(t, half));
    ValueId lambda = zero, atCentre = zero, chosenOff = far;
    for (const ValueId step : {tau, b.neg(tau)}) {
        const ValueId reach = b.add(back, curvatureReach(b, at, pixel, halfWay, n, step));
        const ValueId d = readThere(b, at, pixel, along(b, n, reach)).d;
        const ValueId off = offOf(reach, b.div(d, length));
        const ValueId better = b.lt(off, chosenOff);
        chosenOff = b.select(better, off, chosenOff);
        lambda = b.select(better, reach, lambda);
        atCentre = b.select(better, d, atCentre);
    }
    // The curvature's centre is as good as the normals' turn over the step, which a float's
    // rounding of the world's coordinates far out from the frame's centre spoils by a percent:
    // it is moved to where the distance peaks along the normal line. Half its reading s to
    // either side, the ring reads R - s - e and R - s + e where the centre read stands e past
    // the true one, whichever way, and the peak R is their mean plus s.
    const ValueId s = b.mul(atCentre, half);
    const ValueId ahead = readThere(b, at, pixel, along(b, n, b.add(lambda, s))).d;
    const ValueId behind = readThere(b, at, pixel, along(b, n, b.sub(lambda, s))).d;
    lambda = b.sub(lambda, b.div(b.sub(behind, ahead), b.mul(length, b.constF(2.0))));
    const ValueId radius = b.div(b.add(b.mul(b.add(ahead, behind), half), s), length);
    return {lambda, radius, offOf(lambda, radius)};
}

} // namespace

ScreenRead ringsRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     ValueId halfWidth, const Reading& centre, ValueId wanted) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    const Vals read = b.ifThenElse(
        wanted,
        [&] {
            // The pixel centre's ring, its radius in world units by the distance's unit, the
            // pixel centre's gradient (1 for a Euclidean distance). A pixel centre on its ring's
            // centre, to the last bit, has no gradient: it is c0, the distance there the
            // radius, the gradient's length read beside it, and its rays run along the pixel's
            // first side.
            const ValueId some = b.gt(centre.length, zero); // false on NaN too
            const Vals ring = b.ifThenElse(
                some,
                [&] {
                    const Normal n = rawNormal(b, centre);
                    const CentreRing r = centreRing(b, at, pixel, centre, n);
                    return Vals{b.mul(r.lambda, n.u),
                                b.mul(r.lambda, n.v),
                                n.u,
                                n.v,
                                r.radius,
                                centre.length,
                                r.off};
                },
                [&] {
                    const ValueId length =
                        b.max(besideCentre(b, at, pixel).length, b.constF(1e-30));
                    return Vals{zero, zero, one, zero, b.div(centre.d, length), length, zero};
                });
            const PixelPoint c0{ring[0], ring[1]};
            const Normal n{ring[2], ring[3]};
            const ValueId radius = ring[4], length = ring[5];
            const ValueId h = b.div(halfWidth, length);
            const ValueId off =
                b.max(ring[6], roundness(b, at, pixel, c0, n, radius, b.mul(radius, length)));
            const ValueId round =
                b.sub(one, b.smoothstep(b.constF(kRoundFrom), b.constF(kRoundFull), off));
            const ValueId outer = b.add(radius, h);
            const ValueId shaped =
                b.emit(Op::And, {b.emit(Op::And, {b.gt(round, zero),
                                                  b.gt(radius, b.mul(h, b.constF(kLeastRadius)))}),
                                 b.lt(outer, b.mul(pixel.size, b.constF(kScreenMostEdge)))});
            return b.ifThenElse(
                shaped,
                [&] {
                    const CentreOf centreOf = [&](ir::Builder& bb, const Reading& r, PixelPoint p) {
                        return ringCentreOf(bb, at, pixel, r, p, radius);
                    };
                    const ValueId start = b.max(outer, b.div(pixel.size, b.constF(16.0)));
                    const DotLattice lattice =
                        dotLattice(b, at, pixel, centreOf, c0, n, start, outer);
                    const ScreenOf screen = screenOf(b, pixel, c0, lattice);
                    // The closed form takes every ring for c0's: the rings about its four
                    // nearest neighbours must read its radius (a distance that peaks at R
                    // there), as its own looks must read half of it.
                    ValueId otherRadius = zero;
                    for (const double k : {1.0, -1.0})
                        for (const PixelPoint step : {lattice.p, lattice.q}) {
                            const ValueId su = b.mul(step.u, b.constF(k));
                            const ValueId sv = b.mul(step.v, b.constF(k));
                            const ValueId d =
                                readThere(b, at, pixel, {b.add(c0.u, su), b.add(c0.v, sv)}).d;
                            const ValueId off =
                                b.div(b.abs(b.sub(b.div(d, length), radius)), radius);
                            otherRadius = b.max(otherRadius, b.denan(off, one));
                        }
                    const ValueId same = b.sub(
                        one, b.smoothstep(b.constF(kRoundFrom), b.constF(kRoundFull), otherRadius));
                    // The ring's stroke is the disc within its outer edge less the disc
                    // within its inner one, where the stroke leaves one (R > h).
                    const ValueId inner = b.max(b.sub(radius, h), zero);
                    const ValueId innerMean =
                        b.select(b.gt(inner, zero), dotScreenMean(b, screen.in, inner), zero);
                    const ValueId trust = b.select(lattice.ok, b.mul(round, same), zero);
                    const ValueId mean = b.sub(dotScreenMean(b, screen.in, outer), innerMean);
                    return screenReadValues(b, trust, mean, screen, outer, inner);
                },
                [&] { return Vals(kScreenReadValues, zero); });
        },
        [&] { return Vals(kScreenReadValues, zero); });
    return screenReadOf(read);
}

} // namespace moire::lower
