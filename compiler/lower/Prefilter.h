// The `mean` filter (docs/filtering.md): where a phase family's members are finer than the
// pixels, a pixel shows the ink averaged over its footprint instead of the ink at its centre.
// Along the index gradient the footprint of a pixel spans nu = |grad index| x pixel units of
// index (the members it holds); over so short a run the index is taken as linear, so the mean
// of the periodic stroke over a box of width nu centred on the pixel's index is a difference
// of the stroke's cumulative ink, which is floor-based and exact (boxMeanInk), and over the
// square pixel, whose sides the gradient crosses at an angle, a second difference of that
// cumulative's integral (squareMeanInk). A family that gives no index to average along is
// averaged from its distance instead: the overlap of the nearest member's stroke with the
// pixel's footprint along the stroke's normal (distanceMeanInk). Written once as templates:
// instantiated over IR values for every backend, over double by the tests and experiments that
// check them.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LayerPipeline.h"

#include <algorithm>
#include <cmath>

namespace moire::lower {

// The narrowest footprint the box mean divides by, in index units: below it the quotient
// would be lost to float rounding (the quotient is then close to the step at the index).
constexpr double kLeastFootprint = 1e-3;
// Where a layer's members count as unresolved, by members per pixel: from kCrowdFrom (a member
// every 1.33 pixels) to kCrowdFull (one a pixel). Short of it a pixel meets one member of the
// layer, its nearest, and strokes of two layers that meet in it are correlated by their
// straight strokes (StrokePairs.h); past it the union of fine layers (FineUnion.h) correlates
// the layers by their beat. Measured by experiments/fine_pairs, which is worst at the hand-over:
// from 1/4 to 2/5 it left 0.05 error at 0.4-0.6 members a pixel, from 2/3 to 1 0.015 at 0.75,
// from 3/4 to 1 0.016 at 1.
constexpr double kCrowdFrom = 3.0 / 4.0;
constexpr double kCrowdFull = 1.0;

// Half the square pixel's diagonal, in pixels (a hair over sqrt(2) / 2): a stroke whose centre
// line stands further than that plus its half-width from the pixel's centre does not reach it.
constexpr double kHalfDiagonal = 0.7072;

// The mean, over the box [index - nu/2, index + nu/2], of the periodic stroke that inks the
// index within w of a whole number (members at the integers, half-width w in index units).
// Its cumulative ink from y = x + 1/2 is C(y) = 2w floor(y) + clamp(fract(y) - (1/2 - w), 0,
// 2w): one stroke's 2w per whole period passed, plus the part of the current one. The mean
// is (C(hi) - C(lo)) / nu: the exact step of the stroke as nu -> 0, 2w as nu grows, and 1
// where w >= 1/2 (the strokes touch). The box is taken about the index's residual in
// [-1/2, 1/2), so the floors stay small numbers whatever the index.
template <class T>
T boxMeanInk(T index, T nu, T w) {
    using ir::literal;
    using std::floor;
    using std::max;
    using std::min;
    const T zero = literal(index, 0.0);
    const T half = min(max(w, zero), literal(index, 0.5)); // w clamped to [0, 1/2]
    const T twoW = half * 2.0;
    const T gap = 0.5 - half; // where the stroke starts in its period
    const T residual = index - floor(index + 0.5);
    const T foot = max(nu, literal(index, kLeastFootprint));
    auto cumulative = [&](T y) {
        T k = floor(y);
        return twoW * k + min(max(y - k - gap, zero), twoW);
    };
    T centre = residual + 0.5;
    T reach = foot * 0.5;
    return (cumulative(centre + reach) - cumulative(centre - reach)) / foot;
}

// The narrower side of the footprint is held at least this share of the wider one (and at
// least kLeastFootprint): where the gradient runs along a pixel's side the square's footprint
// is the box above, which the trapezoid's second difference reaches only as 0 / 0. A side
// 1/32 of the other blurs the box's edges by that share of a pixel, which the eye cannot see.
constexpr double kLeastSideShare = 1.0 / 32.0;

// The square pixel's footprint along a direction: the sides' extents `along` and `across`
// (the narrower held at least kLeastSideShare of the wider, and at least kLeastFootprint),
// spread evenly and added, a trapezoid with half-spans s1 = (a + b) / 2 and s2 = (a - b) / 2.
template <class T>
struct Trapezoid {
    T a, b, s1, s2;
};
template <class T>
Trapezoid<T> trapezoid(T along, T across) {
    using std::max;
    const T least = max(max(along, across) * kLeastSideShare, ir::literal(along, kLeastFootprint));
    const T a = max(along, least), b = max(across, least);
    return {a, b, (a + b) * 0.5, (a - b) * 0.5};
}
// The mean over the trapezoid centred on c of a function whose integral is `integral`: the
// second difference (F(c + s1) - F(c + s2) - F(c - s2) + F(c - s1)) / (a b).
template <class T, class F>
T trapezoidMean(const Trapezoid<T>& t, T c, F integral) {
    return (integral(c + t.s1) - integral(c + t.s2) - integral(c - t.s2) + integral(c - t.s1)) /
           (t.a * t.b);
}

// The mean over a square pixel whose sides span `along` and `across` units of index (the
// index's steps across the pixel's two sides, |grad index . side|): the stroke's ink averaged
// over the index's offsets along u + v, u and v spread evenly over boxes that wide, a
// trapezoid. It is a second difference of the running total's own integral,
//   D(y) = w k^2 + 2 w k t + G(t),  k = floor(y), t = fract(y),
//   G(t) = clamp(t - (1/2 - w), 0, 2w)^2 / 2 + 2w max(t - (1/2 + w), 0),
// (D gathers w per whole period of C, C's 2w k across the current one, and the stroke's own
// part): mean = (D(c + s1) - D(c + s2) - D(c - s2) + D(c - s1)) / (along x across), with
// c = residual + 1/2, s1 = (along + across) / 2 and s2 = (along - across) / 2. Where the
// gradient runs along a side (across = 0) it is boxMeanInk; wherever it points it tends to
// 2w as the pixel grows.
template <class T>
T squareMeanInk(T index, T along, T across, T w) {
    using ir::literal;
    using std::abs;
    using std::floor;
    using std::max;
    using std::min;
    const T zero = literal(index, 0.0);
    const T half = min(max(w, zero), literal(index, 0.5));
    const T twoW = half * 2.0;
    const T gap = 0.5 - half;
    const T residual = index - floor(index + 0.5);
    const Trapezoid<T> foot = trapezoid(along, across);
    auto twice = [&](T y) { // D(y)
        T k = floor(y);
        T t = y - k;
        T inStroke = min(max(t - gap, zero), twoW);
        T past = max(t - gap - twoW, zero);
        return half * k * k + twoW * k * t + inStroke * inStroke * 0.5 + twoW * past;
    };
    T mean = trapezoidMean(foot, residual + 0.5, twice);
    // Exactly 0 where the footprint lies wholly between member 0's stroke and the next, exactly
    // 1 where it lies wholly within the stroke: there D is linear or quadratic over the
    // footprint, and its second difference would round to a few float steps off.
    const T one = literal(index, 1.0);
    const T off = abs(residual);
    const T clear = ir::select(ir::lessThan(off, half + foot.s1), zero,
                               ir::select(ir::lessThan(one - half, off + foot.s1), zero, one));
    const T inside = ir::select(ir::lessThan(half, off + foot.s1), zero, one);
    mean = min(max(mean, zero), one);
    return ir::select(ir::lessThan(zero, inside), one,
                      ir::select(ir::lessThan(zero, clear), zero, mean));
}

// The mean over a square pixel of one stroke seen from its distance: the pixel's centre stands
// `d` from the member's centre line, the stroke inks [-h, h] across it, and the pixel's sides
// span `along` and `across` world units along the stroke's normal (a trapezoid again, or a box
// of the pixel's side where the normal is not known: across = 0). The running total of the
// stroke across the normal is C(y) = clamp(y + h, 0, 2h), its integral
//   E(y) = clamp(y + h, 0, 2h)^2 / 2 + 2h max(y - h, 0),
// and the mean is (E(d + s1) - E(d + s2) - E(d - s2) + E(d - s1)) / (along x across), s1 and s2
// as in squareMeanInk. It counts the nearest member alone: exact for members apart by more than
// the footprint, whatever the stroke, with no floor (a box-filtered hairline is a faint line,
// not speckle). d is read as |d| and held within reach of the footprint (a family with no
// member in sight reports a distance of 1e30, whose E would round away the difference).
template <class T>
T distanceMeanInk(T d, T h, T along, T across) {
    using ir::literal;
    using std::abs;
    using std::max;
    using std::min;
    const T zero = literal(d, 0.0);
    const T half = max(h, zero);
    const Trapezoid<T> foot = trapezoid(along, across);
    const T centre = min(abs(d), half + foot.s1 + 1.0); // past half + s1 the mean is 0
    auto integral = [&](T y) {                          // E(y)
        T in = min(max(y + half, zero), half * 2.0);
        return in * in * 0.5 + half * 2.0 * max(y - half, zero);
    };
    const T one = literal(d, 1.0);
    const T mean = min(max(trapezoidMean(foot, centre, integral), zero), one);
    // Exactly 0 where the footprint lies wholly past the stroke, exactly 1 where it lies wholly
    // within: there E is linear or constant over the footprint, and its second difference
    // would round to a few float steps off (a paper-white pixel drawn 1e-7 grey).
    return ir::select(ir::lessThan(centre - foot.s1, half),
                      ir::select(ir::lessThan(half, centre + foot.s1), mean, one), zero);
}

// The pixel as the mean filter reads it: its world size, and where the camera turns the
// picture the cosine and sine of the turn, along which the pixel's sides run in the world
// (kNoValue: along the world's axes).
struct PixelFootprint {
    ir::ValueId size = ir::kNoValue, cosTurn = ir::kNoValue, sinTurn = ir::kNoValue;
};

// The ink (before opacity) a phase family draws under the mean filter: the mean of its stroke
// as written (half-width `halfWidth` in world units, no floor) over the square pixel
// (squareMeanInk), at every number of members a pixel. A box filter composes exactly (the mean
// of a block of box-filtered small pixels is the box filter of the big one), so a frame drawn
// small has the tone of the same frame drawn large and downsampled; and a box-filtered hairline
// does not speckle (speckle is point sampling's aliasing, which the floor was there to hide).
// A family that starts at member `first` takes its nearest member's distance mean
// (distanceMeanInk) wherever the footprint reaches below that member, where the members the
// periodic stroke would count do not exist.
ir::ValueId meanInk(ir::Builder& b, const Footprint& footprint, ir::ValueId distance,
                    ir::ValueId halfWidth, const PixelFootprint& pixel);

// A vector's components along the pixel's two sides, which run along the world's axes turned
// by the camera (the world's own components where the camera does not turn).
struct PixelSides {
    ir::ValueId u, v;
};
PixelSides onPixelSides(ir::Builder& b, ir::ValueId x, ir::ValueId y, const PixelFootprint& pixel);

// The normal of a layer's nearest member, along the pixel's sides and not normalised: the
// distance's own gradient (`ofDistance`: it points away from the member, so the pixel's centre
// stands `distance` along it), or where AD cannot take it (the distance is computed from a
// derivative, or in a loop: see the .cpp) the family's index gradient (gradX, gradY), whose
// sense relative to the member is not known. u kNoValue: neither is known.
struct MemberNormal {
    ir::ValueId u = ir::kNoValue, v = ir::kNoValue;
    bool ofDistance = false;
};
MemberNormal memberNormal(ir::Builder& b, ir::ValueId distance, ir::ValueId gradX,
                          ir::ValueId gradY, const PixelFootprint& pixel);

// The square pixel of side `side` seen across a normal given along the pixel's sides (u, v),
// not normalised: the spans of its two sides along the normal (distanceMeanInk's `along` and
// `across`), |u| side / |(u, v)| and |v| side / |(u, v)|; a box of the pixel's side (side, 0)
// where the normal vanishes or is NaN.
struct NormalExtents {
    ir::ValueId along, across;
};
NormalExtents extentsAcross(ir::Builder& b, ir::ValueId u, ir::ValueId v, ir::ValueId side);

// The ink (before opacity) a family without a footprint (walking families, lattices, morphs,
// the pencil, distance families) draws under the mean filter: distanceMeanInk of its nearest
// member at `distance` (world units), across that member's normal: the distance's own gradient
// (its derivatives in the kernel), or where the distance is itself computed from a derivative
// (which the first-order AD cannot differentiate again), the direction of (gradX, gradY), the
// family's index gradient (kNoValue: none, and the footprint is a box of the pixel's side).
ir::ValueId distanceInk(ir::Builder& b, ir::ValueId distance, ir::ValueId halfWidth,
                        ir::ValueId gradX, ir::ValueId gradY, const PixelFootprint& pixel);

// A phase family's index at the pixel's centre moved by (ox, oy) world units.
using IndexAt = std::function<ir::ValueId(ir::Builder&, ir::ValueId ox, ir::ValueId oy)>;

// The closed form takes the index as linear across the pixel, which it is not where a phase
// folds (a polygon's support function along its corners, where a stroke turns a corner inside
// the pixel) or bends within it (the circles about their centre). The index read at the
// pixel's corners says how far it departs from its linear model there, in pixels across the
// members; past kBentFrom the pixel is read in n x n parts (n = 2, 4 or 8 by the departure),
// each by the closed form over its own index and gradient, fully past kBentFull. `weight` is that
// hand-over, `mean` the parts' mean (0 where the weight is).
struct BentIndex {
    ir::ValueId weight, mean;
};
BentIndex bentIndexMean(ir::Builder& b, const IndexAt& at, const Footprint& footprint,
                        ir::ValueId halfWidth, const PixelFootprint& pixel);
// The hand-over alone: `weight` as above, and `parts`, the parts a side the departure asks for
// (2, 4 or 8).
struct Bend {
    ir::ValueId weight, parts;
};
Bend bendOf(ir::Builder& b, const IndexAt& at, const Footprint& footprint,
            const PixelFootprint& pixel);

// Whether the footprint of a family with a first member reaches below it (half the square's
// diagonal extent along the index short of first - 1/2, the first member's own cell), where
// meanInk reads the nearest member's distance, or Footprint::belowMean, and the stroke pairs
// the first member's stroke alone.
ir::ValueId reachesBelowFirst(ir::Builder& b, const Footprint& footprint,
                              const PixelFootprint& pixel);

// Below a first member the closed form does not hold (it would count the excluded members) and
// the nearest member's distance sees one stroke, where a fold of the phase (the hyperbola's
// asymptotes, its member 0) brings the first member's two sides and the members after it
// together within the pixel, and beside the fold the index runs as the square root of the
// distance to it, so that no part is small enough to take it as linear. There, and where the
// index bends within the pixel (bendOf), the pixel is read in n x n parts (foldParts), each
// in P = (phi / s)^2 (FoldMean.h), where the phase of a family with a first member is taken
// to fold as a square root (as the point rule takes it below the first member): `p` and
// `pNear` (P read off a fold through the part, for its gradient), `level`, the members' level
// in spacings, and `lead`, the first member's phi in spacings, at the part's centre moved by
// (ox, oy). Where a field moves the level across the part, P is read as (index + the centre's
// level)^2, in which the members stand still: its gradient is grad P less 2 phi grad level.
struct FoldAt {
    ir::ValueId p, pNear, level, lead;
};
using FoldsAt = std::function<FoldAt(ir::Builder&, ir::ValueId ox, ir::ValueId oy)>;
ir::ValueId belowFirstMean(ir::Builder& b, const FoldsAt& at, ir::ValueId halfWidth,
                           const PixelFootprint& pixel, ir::ValueId n);
// The parts a side belowFirstMean needs (1, 2, 4 or 8, at least `least`): by how far P departs
// at the pixel's corners and its sides' middles from its linear model folded at 0, as bendOf
// reads the index's departure. P is as smooth as the function whose square root the phase is,
// so where the index runs as the square root of the distance to a fold a few parts do, and
// about the hyperbola's centre, where P bends, as many as it asks for.
ir::ValueId foldParts(ir::Builder& b, const FoldsAt& at, const IndexAt& indexAt,
                      const PixelFootprint& pixel, ir::ValueId least);

// The drawn ink `ink` handed over to a crowd's mean (CrowdEstimate), weighted by `engaged`
// (a crowd is estimated where the family's own strokes miss members, so there is no resolved
// picture to keep: see the .cpp). Called under the mean filter only.
ir::ValueId crowdInk(ir::Builder& b, const CrowdEstimate& crowd, ir::ValueId ink);

// A layer's ink (before opacity) under the mean filter, as the compose step lays it: a
// family with a footprint by its index (meanInk), one that measures its nearest member itself
// by that (CrowdEstimate::nearest), any other from its distance (distanceInk); then handed
// over to its crowd where it estimates one (crowdInk).
ir::ValueId layerMeanInk(ir::Builder& b, const LayerFields& fields, ir::ValueId halfWidth,
                         const PixelFootprint& pixel);

} // namespace moire::lower
