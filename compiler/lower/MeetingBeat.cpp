#include "compiler/lower/MeetingBeat.h"

#include "compiler/ir/BuiltValue.h"

namespace moire::lower {

using ir::ValueId;

namespace {

// The senses sigma_2, sigma_3 (sigma_1 = +1) that make the three lines' gradients nearly
// cancel, the least of the four sums, as the layer's own mean takes them (DistanceGrid.cpp,
// excessOfThree): the meeting sum c and its change over the pixel's sides.
struct Meeting {
    std::array<ValueId, 3> sigma;
    ValueId c, along, across;
};

Meeting meetingOf(ir::Builder& b, const MeetingSide& side) {
    const auto& l = side.lines;
    Meeting out{
        {b.constF(1.0), b.constF(1.0), b.constF(1.0)}, b.constF(0.0), b.constF(0.0), b.constF(0.0)};
    ValueId best = b.constF(1e30);
    for (double s2 : {1.0, -1.0})
        for (double s3 : {1.0, -1.0}) {
            auto sum = [&](ValueId x0, ValueId x1, ValueId x2) {
                return b.add(x0, b.add(b.mul(b.constF(s2), x1), b.mul(b.constF(s3), x2)));
            };
            const ValueId u = sum(l[0].u, l[1].u, l[2].u), v = sum(l[0].v, l[1].v, l[2].v);
            const ValueId size = b.add(b.mul(u, u), b.mul(v, v));
            const ValueId better = b.lt(size, best);
            best = b.select(better, size, best);
            out.sigma[1] = b.select(better, b.constF(s2), out.sigma[1]);
            out.sigma[2] = b.select(better, b.constF(s3), out.sigma[2]);
            out.c = b.select(better, sum(l[0].index, l[1].index, l[2].index), out.c);
            out.along = b.select(better, b.abs(u), out.along);
            out.across = b.select(better, b.abs(v), out.across);
        }
    return out;
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
