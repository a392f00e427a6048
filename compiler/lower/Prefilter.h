// The `mean` filter (docs/filtering.md): where a phase family's members are finer than the
// pixels, a pixel shows the ink averaged over its footprint instead of the ink at its centre.
// Along the index gradient the footprint of a pixel spans nu = |grad index| x pixel units of
// index (the members it holds); over so short a run the index is taken as linear, so the mean
// of the periodic stroke over a box of width nu centred on the pixel's index is a difference
// of the stroke's cumulative ink, which is floor-based and exact (boxMeanInk), and over the
// square pixel, whose sides the gradient crosses at an angle, a second difference of that
// cumulative's integral (squareMeanInk). Written once as a template: instantiated over IR values
// for every backend, over double by the tests and experiments that check it.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LayerPipeline.h"

#include <algorithm>
#include <cmath>

namespace moire::lower {

// The hand-over by members per pixel nu: point-sampled (today's floored stroke, Eq. 35)
// up to kMeanFrom, the square pixel's mean from kMeanFull on, smoothstep between. A floored stroke
// (2.3 px of ink and a 0.7 px band each side) stands clear of the next member down to about 4
// pixels a member and has merged into solid ink by 2.5, which is where the mean takes over;
// a scene designed with its members a few pixels apart keeps its picture.
constexpr double kMeanFrom = 1.0 / 4.0;
constexpr double kMeanFull = 2.0 / 5.0;
// The narrowest footprint the box mean divides by, in index units: below it the quotient
// would be lost to float rounding, and such a layer is point-sampled anyway (kMeanFrom).
constexpr double kLeastFootprint = 1e-3;

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
    using std::floor;
    using std::max;
    using std::min;
    const T zero = literal(index, 0.0);
    const T half = min(max(w, zero), literal(index, 0.5));
    const T twoW = half * 2.0;
    const T gap = 0.5 - half;
    const T residual = index - floor(index + 0.5);
    const T least = max(max(along, across) * kLeastSideShare, literal(index, kLeastFootprint));
    const T a = max(along, least), b = max(across, least);
    auto twice = [&](T y) { // D(y)
        T k = floor(y);
        T t = y - k;
        T inStroke = min(max(t - gap, zero), twoW);
        T past = max(t - gap - twoW, zero);
        return half * k * k + twoW * k * t + inStroke * inStroke * 0.5 + twoW * past;
    };
    T c = residual + 0.5;
    T s1 = (a + b) * 0.5, s2 = (a - b) * 0.5;
    return (twice(c + s1) - twice(c + s2) - twice(c - s2) + twice(c - s1)) / (a * b);
}

// The pixel as the mean filter reads it: its world size, and where the camera turns the
// picture the cosine and sine of the turn, along which the pixel's sides run in the world
// (kNoValue: along the world's axes).
struct PixelFootprint {
    ir::ValueId size = ir::kNoValue, cosTurn = ir::kNoValue, sinTurn = ir::kNoValue;
};

// The ink (before opacity) a phase family draws under the mean filter: the point rule's
// `pointInk` (Eq. 4 with the floored band) handed over by nu to the box mean of the stroke
// as written over the square pixel (squareMeanInk; half-width `halfWidth` in world units, no
// floor: the floor exists to keep resolved hairlines from speckling, and where members are
// unresolved it is what turns a grey into black). A family that starts at member
// `first` stays point-sampled wherever the footprint reaches below that member, where the
// members the periodic stroke would count do not exist.
ir::ValueId meanInk(ir::Builder& b, const Footprint& footprint, ir::ValueId pointInk,
                    ir::ValueId halfWidth, const PixelFootprint& pixel);

// The drawn ink `ink` handed over to a crowd's mean (CrowdEstimate): min(1, 2 h density), h
// the stroke's own half-width `halfWidth` (or the crowd's own `mean` where it gives one),
// weighted by `engaged` (a crowd is estimated where the family's own strokes miss members,
// so there is no resolved picture to keep: see the .cpp). Called under the mean filter only.
ir::ValueId crowdInk(ir::Builder& b, const CrowdEstimate& crowd, ir::ValueId ink,
                     ir::ValueId halfWidth, const PixelFootprint& pixel);

} // namespace moire::lower
