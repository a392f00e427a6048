// The `mean` filter (docs/filtering.md): where a phase family's members are finer than the
// pixels, a pixel shows the ink averaged over its footprint instead of the ink at its centre.
// Along the index gradient the footprint of a pixel spans nu = |grad index| x pixel units of
// index (the members it holds); over so short a run the index is taken as linear, so the
// footprint is a box of width nu centred on the pixel's index, and the mean of the periodic
// stroke over it is a difference of the stroke's cumulative ink, which is floor-based and
// exact (boxMeanInk). Written once as a template: instantiated over IR values for every
// backend, over double by the tests and experiments that check it.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LayerPipeline.h"

#include <algorithm>
#include <cmath>

namespace moire::lower {

// The hand-over by members per pixel nu: point-sampled (today's floored stroke, Eq. 35)
// up to kMeanFrom, the box mean from kMeanFull on, smoothstep between. A floored stroke (2.3
// px of ink and a 0.7 px band each side) stands clear of the next member down to about 4
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

// The ink (before opacity) a phase family draws under the mean filter: the point rule's
// `pointInk` (Eq. 4 with the floored band) handed over by nu to the box mean of the stroke
// as written (half-width `halfWidth` in world units, no floor: the floor exists to keep
// resolved hairlines from speckling, and where members are unresolved it is what turns a
// grey into black). `pixel` is the world size of a pixel. A family that starts at member
// `first` stays point-sampled wherever the footprint reaches below that member, where the
// members the periodic stroke would count do not exist.
ir::ValueId meanInk(ir::Builder& b, const Footprint& footprint, ir::ValueId pointInk,
                    ir::ValueId halfWidth, ir::ValueId pixel);

} // namespace moire::lower
