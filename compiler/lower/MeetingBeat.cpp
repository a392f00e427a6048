#include "compiler/lower/MeetingBeat.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/DistanceGrid.h"

namespace moire::lower {

using ir::ValueId;

namespace {

// A side's meeting sum, its senses taken as the layer's own mean takes them
// (DistanceGrid.cpp, excessOfThree): sigma_1 = +1 and the two that make the gradients cancel.
struct Meeting {
    std::array<ValueId, 3> sigma;
    ValueId c, along, across;
};

Meeting meetingOf(ir::Builder& b, const MeetingSide& side) {
    std::array<ValueId, 3> index, u, v;
    for (size_t k = 0; k < 3; ++k)
        index[k] = side.lines[k].index, u[k] = side.lines[k].u, v[k] = side.lines[k].v;
    const MeetingSum sum = meetingSum(b, index, u, v);
    return {{b.constF(1.0), sum.s2, sum.s3}, sum.c, sum.along, sum.across};
}

} // namespace

ValueId meetingCovariance(ir::Builder& b, const MeetingSide& first, const MeetingSide& second,
                          ValueId blank1, ValueId blank2) {
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const Meeting one = meetingOf(b, first), two = meetingOf(b, second);
    const ValueId zero = b.constF(0.0);
    // The partner's stroke as a function of i_x sits about i_x - s i_y.
    std::array<ValueId, 3> offsets;
    for (size_t k = 0; k < 3; ++k) {
        const MeetingSide::Line& x = first.lines[k];
        offsets[k] = b.sub(x.index, b.mul(x.sense, x.partnerIndex));
    }
    // One harmonic a turn of the loop: the pairs' product and each layer's own lines.
    const std::vector<ValueId> sums = b.loop(
        {b.constF(1.0), zero, zero, zero},
        [&](std::span<const ValueId> v) {
            return std::vector<ValueId>{b.le(v[0], b.constF(kMeetingHarmonics))};
        },
        [&](std::span<const ValueId> v) {
            std::array<MeetingLine<ir::BuiltValue>, 3> paired, own;
            for (size_t k = 0; k < 3; ++k) {
                const MeetingSide::Line& x = first.lines[k];
                paired[k] = {value(x.half), value(x.partnerHalf), value(offsets[k]),
                             value(one.sigma[k])};
                own[k] = {value(second.lines[k].half), value(zero), value(zero),
                          value(two.sigma[k])};
            }
            const MeetingHarmonic<ir::BuiltValue> h1 = meetingHarmonic(
                value(v[0]), value(one.c), value(one.along), value(one.across), paired);
            const MeetingHarmonic<ir::BuiltValue> h2 = meetingHarmonic(
                value(v[0]), value(two.c), value(two.along), value(two.across), own);
            return std::vector<ValueId>{b.add(v[0], b.constF(1.0)), b.add(v[1], h1.paired.id),
                                        b.add(v[2], h1.alone.id), b.add(v[3], h2.alone.id)};
        });
    const ValueId paired = sums[1], alone1 = sums[2], alone2 = sums[3];
    return b.sub(paired,
                 b.add(b.add(b.mul(alone1, blank2), b.mul(alone2, blank1)), b.mul(alone1, alone2)));
}

} // namespace moire::lower
