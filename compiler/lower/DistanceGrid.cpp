#include "compiler/lower/DistanceGrid.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/Prefilter.h"

#include <array>
#include <functional>

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

MeetingSum meetingSum(ir::Builder& b, const std::array<ValueId, 3>& index,
                      const std::array<ValueId, 3>& u, const std::array<ValueId, 3>& v) {
    MeetingSum out{b.constF(1.0), b.constF(1.0), b.constF(0.0), b.constF(0.0), b.constF(0.0)};
    out.along = out.across = out.c;
    ValueId best = b.constF(1e30);
    for (double s2 : {1.0, -1.0})
        for (double s3 : {1.0, -1.0}) {
            auto sum = [&](const std::array<ValueId, 3>& x) {
                return b.add(x[0], b.add(b.mul(b.constF(s2), x[1]), b.mul(b.constF(s3), x[2])));
            };
            const ValueId su = sum(u), sv = sum(v);
            const ValueId size = b.add(b.mul(su, su), b.mul(sv, sv));
            const ValueId better = b.lt(size, best);
            const ValueId c = sum(index);
            best = b.select(better, size, best);
            out.c = b.select(better, c, out.c);
            out.along = b.select(better, su, out.along);
            out.across = b.select(better, sv, out.across);
            out.s2 = b.select(better, b.constF(s2), out.s2);
            out.s3 = b.select(better, b.constF(s3), out.s3);
        }
    return out;
}

namespace {

// How nearly each family's parts run one way (the length of their doubled angles' mean) before the
// grid is trusted, by a smoothstep: as for parallel members (DistanceFamily.cpp, kRunsFrom), and
// dots, whose normals run every way, stand near 1/2.
constexpr double kTwoWaysFrom = 0.9, kTwoWaysFull = 0.95;
// Three ways rather than two where the left's and the right's mean directions stand more than
// 45 degrees apart (their doubled angles' cosine under 0), by a smoothstep over the cosine:
// a grid whose lines cross square has its second family's parts at the first's opposite,
// split between left and right as they fall, and both halves run the same way.
constexpr double kApartFrom = 0.2, kApartFull = -0.2;
// The least share of the parts each family must hold, by a smoothstep: one part of the 16
// (the parts alias with a grid at zooms where they stand nearly a whole number of lines
// apart, and may read its second family once). A part off the rest by a kink or a bend is
// no family of lines: the probes find no spacing for it.
constexpr double kShareFrom = 0.03, kShareFull = 0.06;
// The probes for a family's next line run along the other family's lines, where the other's
// distance stays what it is at the start, at least t (the start's own distance: the start
// reads its own family as nearest). They stand 1.75 t, then every 1.5 t, further along the
// own family's normal: a probe within t of the next line reads it, and steps under 2 t cannot
// step over that window. kProbes of them, no further than kProbeReach pixels along the
// normal: a spacing past half a pixel is under the closed form's hand-over (two lines a
// pixel).
constexpr int kProbes = 8;
constexpr double kProbeReach = 0.75;
// Where the lines run three ways the third family's lines cross the probes' path, and near the
// next line the own family is nearest over a window only half the other's distance to either
// side (at least t / 2): the probes stand 0.75 t, then every 0.75 t, up to kProbesThree.
constexpr int kProbesThree = 24;
// Where the two families' lines cross at under about 12 degrees, the probes' path runs nearly
// along the own family's lines: not read.
constexpr double kLeastCrossing = 0.2;
// A probe reads its family's line where its normal is within about 18 degrees of the start's.
constexpr double kParallel = 0.95;
// A probe reads a third family's line where its normal is more than about 30 degrees from both
// the start's and the other family's.
constexpr double kThirdWay = 0.866;

// A family of lines does not bend: probes beside the start read the same line with a normal
// turned by under about 2.5 degrees (straightAt).
constexpr double kStraight = 0.999;

// How nearly two unit normals face each other, |n . m| (1 parallel, 0 square).
ValueId facing(ir::Builder& b, Normal n, Normal m) {
    return b.abs(b.add(b.mul(n.u, m.u), b.mul(n.v, m.v)));
}
// Whether a normal m crosses n by more than about 30 degrees (kThirdWay).
ValueId crosses(ir::Builder& b, Normal n, Normal m) {
    return b.lt(facing(b, n, m), b.constF(kThirdWay));
}

// Two families read crossing at 45 to 75 degrees (the cosine of the angle between their
// normals) may be two of three: their pixel looks for a third.
constexpr double kAslantFrom = 0.25, kAslantTo = 0.71;
// The values the grid's branch returns: trust, mean, members, half-width, three ways, and five
// a way.
constexpr size_t kGridRead = 20;

// The points crossingSeen reads, the first of an R2 sequence: a lattice of them (a rank-1
// lattice of 8, 1/8 of a pixel apart across) read the same few places of a grid's cells at 20
// lines a pixel, where it aliased as the parts do, and left 0.0043 RMSE there (0.0022 now);
// a sequence has no rows to alias with any grid.
constexpr int kCrossingLooks = 8;

// Carried: how many parts are another family's than the first and the sums of their doubled
// angles, the same for those turned to the first's left, and the first's, the left's and the
// right's parts furthest from their lines: each one's distance and place.
enum Slot : size_t {
    kOthers,
    kCos,
    kSin,
    kLeft,
    kLeftCos,
    kLeftSin,
    kFirstAway,
    kFirstU,
    kFirstV,
    kLeftAway,
    kLeftU,
    kLeftV,
    kRightAway,
    kRightU,
    kRightV
};
static_assert(kRightV + 1 == PartDirections::kCarried);

// What the reading at q says of a line of the family whose unit normal is n and whose line
// 0 has its foot at f: its normal m, how nearly m faces n (|n . m|), its foot's offset from f
// along n, and whether it has a gradient (false on NaN too).
struct LineSeen {
    Normal m;
    ValueId facing, along, some;
};
LineSeen lineSeen(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel, PixelPoint q,
                  PixelPoint f, Normal n) {
    const Reading there = readThere(b, at, pixel, q);
    const Normal m = unitNormal(b, there);
    return {m, facing(b, n, m), offsetAlong(b, f, footFrom(b, there, q, true), n),
            b.gt(there.length, b.constF(0.0))};
}

// A family's spacing along the normal of the reading r at p, probed along the lines of the
// other family (its unit normal `other`): whether it was found, the spacing L, and the
// family's index at the pixel's centre (the centre's offset from the line through r's foot,
// along the normal, over L).
// Where a probe read a line crossing both the family's and the other's by more than about 30
// degrees (kThirdWay): a third family's, which the parts missed, and the first such probe's
// place.
struct Spacing {
    ValueId found, spacing, index;
    Normal n;
    ValueId thirdSeen;
    PixelPoint thirdAt;
};
// The probes' layout: the first `first` strides along the normal, then every `gap` strides,
// `count` of them; two ways' or three ways' (`three`). A stride is t, or where the lines run
// three ways, the start's distance from the other family's line where that is further (the
// window about the next line is at least that wide: a start by its own line, t small, would
// otherwise take more probes than it has).
struct Probes {
    ValueId first, gap, count, three;
};
Probes probesFor(ir::Builder& b, ValueId three) {
    auto pick = [&](double threeWays, double twoWays) {
        return b.select(three, b.constF(threeWays), b.constF(twoWays));
    };
    return {pick(0.75, 1.75), pick(0.75, 1.5), pick(kProbesThree, kProbes), three};
}
// `otherDistance`: the start's distance from the other family's nearest line (0 where not
// known).
Spacing spacingAlong(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     const Reading& r, PixelPoint p, Normal other, ValueId otherDistance,
                     const Probes& probes) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    const Normal n = unitNormal(b, r);
    const ValueId t = b.div(r.d, heldLength(b, r));
    const PixelPoint f = footFrom(b, r, p, true);
    // The other family's lines run along (-other.v, other.u); taken the way n points, each
    // unit along it is `rate` along n.
    const ValueId rate0 = b.sub(b.mul(n.v, other.u), b.mul(n.u, other.v));
    const ValueId rate = b.abs(rate0);
    const ValueId sense = b.select(b.lt(rate0, zero), b.constF(-1.0), one);
    const Normal path{b.mul(sense, b.neg(other.v)), b.mul(sense, other.u)};
    // A start on its line (t about 0) still steps a thousandth of a pixel.
    const ValueId step = b.max(t, b.mul(pixel.size, b.constF(1e-3)));
    const ValueId reach = b.mul(pixel.size, b.constF(kProbeReach));
    // Probe k stands this far along n from f.
    const ValueId stride = b.select(probes.three, b.max(step, otherDistance), step);
    auto probe = [&](ValueId k) {
        return b.mul(stride, b.add(probes.first, b.mul(k, probes.gap)));
    };
    // Carried: the probe, whether the next line was read, its distance from f along n, and
    // whether a third family's line was read, with the first such probe's place.
    std::vector<ValueId> init{zero, zero, zero, zero, zero, zero};
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{
            b.emit(Op::And, {b.emit(Op::And, {b.lt(v[0], probes.count), b.lt(v[1], b.constF(0.5))}),
                             b.le(probe(v[0]), reach)})};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const ValueId s = b.div(probe(v[0]), b.max(rate, b.constF(kLeastCrossing)));
        const PixelPoint q{b.add(p.u, b.mul(s, path.u)), b.add(p.v, b.mul(s, path.v))};
        const LineSeen seen = lineSeen(b, at, pixel, q, f, n);
        const ValueId parallel = b.gt(seen.facing, b.constF(kParallel));
        // Its own line 0 stands at 0 along n, the next one at L >= 2 t: t clears it. NaN (a
        // probe on a kink) compares false.
        const ValueId hit =
            b.emit(Op::And, {b.emit(Op::And, {parallel, seen.some}), b.gt(seen.along, step)});
        const ValueId third =
            b.emit(Op::And, {b.emit(Op::And, {crosses(b, n, seen.m), crosses(b, other, seen.m)}),
                             b.emit(Op::And, {seen.some, b.lt(v[3], b.constF(0.5))})});
        return std::vector<ValueId>{
            b.add(v[0], one),           b.select(hit, one, zero),   b.select(hit, seen.along, v[2]),
            b.select(third, one, v[3]), b.select(third, q.u, v[4]), b.select(third, q.v, v[5])};
    });
    // Where a third family's line passes close by the next line's crossing with the path, the
    // window in which the own family is nearest narrows (at angles other than 60 degrees it
    // may close), and the probes may step over it to the line after. A line half-way halves
    // the spacing: read a twentieth of a stride past the half (off its kink), half a stride
    // to either side of the path along the line (off the third family's line, which crosses
    // it by the path), where it stands nearer than anything else.
    // Read only where there is a third family (the lines read three ways, or this family's
    // probes crossed one): a grid's two ways leave the window its whole width.
    const ValueId halfway = b.mul(out[2], b.constF(0.5));
    const ValueId mayStep = b.emit(Op::Or, {probes.three, b.gt(out[3], b.constF(0.5))});
    const Vals checked = b.ifThenElse(
        b.emit(Op::And, {mayStep, b.gt(out[1], b.constF(0.5))}),
        [&] {
            const ValueId past = b.sub(b.add(halfway, b.mul(stride, b.constF(0.05))), t);
            const ValueId sHalf = b.div(past, b.max(rate, b.constF(kLeastCrossing)));
            ValueId line = b.constB(false);
            for (double side : {-0.5, 0.5}) {
                const ValueId aside = b.mul(stride, b.constF(side));
                const PixelPoint q{b.sub(b.add(p.u, b.mul(sHalf, path.u)), b.mul(aside, n.v)),
                                   b.add(b.add(p.v, b.mul(sHalf, path.v)), b.mul(aside, n.u))};
                const LineSeen seen = lineSeen(b, at, pixel, q, f, n);
                const ValueId there = b.emit(
                    Op::And,
                    {b.emit(Op::And, {b.gt(seen.facing, b.constF(kParallel)), seen.some}),
                     b.lt(b.abs(b.sub(seen.along, halfway)), b.mul(halfway, b.constF(0.1)))});
                line = b.emit(Op::Or, {line, there});
            }
            return Vals{b.select(line, one, zero)};
        },
        [&] { return Vals{zero}; });
    const ValueId halved = b.gt(checked[0], b.constF(0.5));
    const ValueId spacing =
        b.max(b.select(halved, halfway, out[2]), b.mul(pixel.size, b.constF(1e-4)));
    // The centre (0, 0) stands -f . n from the line through f.
    const ValueId offset = offsetAlong(b, f, {b.constF(0.0), b.constF(0.0)}, n);
    const ValueId found =
        b.emit(Op::And, {b.gt(out[1], b.constF(0.5)), b.gt(rate, b.constF(kLeastCrossing))});
    return {found,           spacing, b.div(offset, spacing), n, b.gt(out[3], b.constF(0.5)),
            {out[4], out[5]}};
}

// The three families' excess over independent inks over the pixel (tripleExcess): their
// indices' senses taken so that the gradients (n / L, in pixels) nearly cancel, the least of
// the four sums with the first's taken as is; `halves` each family's stroke half-width in
// index units.
ValueId excessOfThree(ir::Builder& b, const PixelFootprint& pixel,
                      const std::array<const Spacing*, 3>& ways,
                      const std::array<ValueId, 3>& halves) {
    std::array<ValueId, 3> index, gu, gv;
    for (int k = 0; k < 3; ++k) {
        const ValueId per = b.div(pixel.size, ways[k]->spacing);
        index[k] = ways[k]->index;
        gu[k] = b.mul(ways[k]->n.u, per);
        gv[k] = b.mul(ways[k]->n.v, per);
    }
    const MeetingSum sum = meetingSum(b, index, gu, gv);
    const ValueId c = sum.c, along = sum.along, across = sum.across;
    auto value = [&](ValueId x) { return ir::BuiltValue(b, x); };
    auto width = [&](ValueId half) { return value(b.mul(half, b.constF(2.0))); };
    return tripleExcess(value(c), width(halves[0]), width(halves[1]), width(halves[2]),
                        value(along), value(across))
        .id;
}

// Whether the member the reading r at p reads is straight: two probes half way from p to its
// foot, a tenth of its distance t to either side along it, read the same member (a foot on
// its line) facing as r does (kStraight). There the own line is nearer than at p and the
// other family's lines as far, less a tenth of t: the probes read the own line (a dot's
// normals turn by 11 degrees between them and p).
ValueId straightAt(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                   const Reading& r, PixelPoint p) {
    const Normal n = unitNormal(b, r);
    const ValueId t = b.div(r.d, heldLength(b, r));
    const PixelPoint f = footFrom(b, r, p, true);
    const ValueId in = b.mul(t, b.constF(0.5)), side = b.mul(t, b.constF(0.1));
    ValueId straight = b.constB(true);
    for (double sense : {-1.0, 1.0}) {
        const ValueId s = b.mul(side, b.constF(sense));
        const PixelPoint q{b.sub(b.sub(p.u, b.mul(in, n.u)), b.mul(s, n.v)),
                           b.add(b.sub(p.v, b.mul(in, n.v)), b.mul(s, n.u))};
        const LineSeen seen = lineSeen(b, at, pixel, q, f, n);
        const ValueId same = b.lt(b.abs(seen.along), b.mul(t, b.constF(0.1)));
        straight = b.emit(
            Op::And, {straight, b.emit(Op::And, {same, b.gt(seen.facing, b.constF(kStraight))})});
    }
    return straight;
}

} // namespace

PartDirections::PartDirections(ir::Builder& b, const Reading& centre) : b_(b) {
    const DoubledAngle a = doubledAngle(b, centre);
    cos2_ = a.cos2;
    sin2_ = a.sin2;
}

std::vector<ValueId> PartDirections::start() const {
    std::vector<ValueId> v(kCarried, b_.constF(0.0));
    // No part yet: the furthest stand at -1.
    v[kFirstAway] = v[kLeftAway] = v[kRightAway] = b_.constF(-1.0);
    return v;
}

std::vector<ValueId> PartDirections::add(std::span<const ValueId> v, ValueId away, ValueId cos2,
                                         ValueId sin2, ValueId some, PixelPoint p) const {
    ir::Builder& b = b_;
    const ValueId zero = b.constF(0.0);
    // The part is the first family's where its doubled angle is within a right angle of the
    // centre's (its normal within 45 degrees of the centre's), else another's: the left's
    // where its doubled angle is ahead of the centre's.
    const ValueId cosine = b.add(b.mul(cos2, cos2_), b.mul(sin2, sin2_));
    const ValueId ahead = b.sub(b.mul(sin2, cos2_), b.mul(cos2, sin2_));
    const ValueId first = b.emit(Op::Ge, {cosine, zero});
    const ValueId other = b.emit(Op::Not, {first});
    const ValueId left = b.emit(Op::And, {other, b.emit(Op::Ge, {ahead, zero})});
    const ValueId right = b.emit(Op::And, {other, b.emit(Op::Not, {left})});
    const ValueId weight = b.select(b.emit(Op::And, {some, other}), b.constF(1.0), zero);
    const ValueId leftWeight = b.select(b.emit(Op::And, {some, left}), b.constF(1.0), zero);
    std::vector<ValueId> out(v.begin(), v.end());
    out[kOthers] = b.add(v[kOthers], weight);
    out[kCos] = b.add(v[kCos], b.mul(weight, cos2));
    out[kSin] = b.add(v[kSin], b.mul(weight, sin2));
    out[kLeft] = b.add(v[kLeft], leftWeight);
    out[kLeftCos] = b.add(v[kLeftCos], b.mul(leftWeight, cos2));
    out[kLeftSin] = b.add(v[kLeftSin], b.mul(leftWeight, sin2));
    // Each family's part furthest from its line.
    const ValueId read = b.emit(Op::And, {some, b.emit(Op::Eq, {away, away})});
    auto furthest = [&](size_t slot, ValueId mine) {
        const ValueId better =
            b.emit(Op::And, {b.emit(Op::And, {read, mine}), b.gt(away, v[slot])});
        out[slot] = b.select(better, away, v[slot]);
        out[slot + 1] = b.select(better, p.u, v[slot + 1]);
        out[slot + 2] = b.select(better, p.v, v[slot + 2]);
    };
    furthest(kFirstAway, first);
    furthest(kLeftAway, left);
    furthest(kRightAway, right);
    return out;
}

namespace {

// The first of kCrossingLooks points of the pixel off the parts' lattice (an R2 sequence, moved
// from pixel to pixel by pixelShift) whose reading is `wanted`.
CrossingStart firstLook(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                        const std::function<ValueId(const Reading&)>& wanted) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0), half = b.constF(0.5);
    const PixelPoint shift = pixelShift(b);
    // Carried: the point, whether one crossed, its place.
    std::vector<ValueId> init{zero, zero, zero, zero};
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{
            b.emit(Op::And, {b.lt(v[0], b.constF(kCrossingLooks)), b.lt(v[1], half)})};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        // Point k of an R2 sequence (the plastic number's steps), moved by the pixel's shift.
        const ValueId k = v[0];
        const ValueId across = b.add(b.mul(k, b.constF(kR2a)), shift.u);
        const ValueId up = b.add(b.mul(k, b.constF(kR2b)), b.add(shift.v, half));
        const PixelPoint p{b.mul(b.sub(fract(b, across), half), pixel.size),
                           b.mul(b.sub(fract(b, up), half), pixel.size)};
        const Reading r = readThere(b, at, pixel, p);
        const ValueId crossed = b.emit(Op::And, {b.gt(r.length, zero), wanted(r)});
        return std::vector<ValueId>{b.add(k, one), b.select(crossed, one, zero),
                                    b.select(crossed, p.u, v[2]), b.select(crossed, p.v, v[3])};
    });
    return {b.gt(out[1], half), {out[2], out[3]}};
}

} // namespace

CrossingStart crossingSeen(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                           ValueId cos2, ValueId sin2) {
    return firstLook(b, at, pixel, [&](const Reading& r) {
        // Its doubled angle more than a right angle from the axis's: a direction more than
        // 45 degrees off.
        const DoubledAngle a = doubledAngle(b, r);
        return b.lt(b.add(b.mul(a.cos2, cos2), b.mul(a.sin2, sin2)), b.constF(0.0));
    });
}

GridRead gridRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                  ValueId halfWidth, std::span<const ValueId> v, ValueId cos2, ValueId sin2,
                  ValueId directed, ValueId wanted, const CrossingStart& crossing) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0), tiny = b.constF(1e-30);
    // Each family's mean direction, and how nearly its parts run that way: the others' and
    // the left's sums are carried, the first's and the right's are what they leave.
    const ValueId count = b.max(directed, one);
    const ValueId otherWeight = v[kOthers], firstWeight = b.sub(directed, v[kOthers]);
    const ValueId leftWeight = v[kLeft], rightWeight = b.sub(v[kOthers], v[kLeft]);
    auto runsOf = [&](ValueId c, ValueId s2, ValueId weight) {
        return b.div(b.hypot(c, s2), b.max(weight, tiny));
    };
    const ValueId otherRuns = runsOf(v[kCos], v[kSin], otherWeight);
    const ValueId firstRuns = runsOf(b.sub(cos2, v[kCos]), b.sub(sin2, v[kSin]), firstWeight);
    const ValueId rightCos = b.sub(v[kCos], v[kLeftCos]), rightSin = b.sub(v[kSin], v[kLeftSin]);
    const ValueId leftRuns = runsOf(v[kLeftCos], v[kLeftSin], leftWeight);
    const ValueId rightRuns = runsOf(rightCos, rightSin, rightWeight);
    auto share = [&](ValueId weight) {
        return b.smoothstep(b.constF(kShareFrom), b.constF(kShareFull), b.div(weight, count));
    };
    auto runsTrust = [&](ValueId runs) {
        return b.smoothstep(b.constF(kTwoWaysFrom), b.constF(kTwoWaysFull), runs);
    };
    // Two ways: the other family's part furthest from its line, the left's or the right's.
    // Where no part reads the other family, the crossing the centre's ray met stands for it.
    const ValueId leftFurther = b.emit(Op::Ge, {v[kLeftAway], v[kRightAway]});
    auto slotOf = [&](size_t left, size_t right) {
        return b.select(leftFurther, v[left], v[right]);
    };
    const ValueId partsOther = b.emit(Op::Ge, {slotOf(kLeftAway, kRightAway), zero});
    const ValueId fromRay = b.emit(Op::And, {b.emit(Op::Not, {partsOther}), crossing.found});
    const ValueId runs = b.select(partsOther, b.min(firstRuns, otherRuns), firstRuns);
    const ValueId twoTrust = b.mul(
        runsTrust(runs), b.select(partsOther, b.mul(share(otherWeight), share(firstWeight)), one));
    // Three ways: the left's and the right's each run one way, apart from each other.
    const ValueId apartCosine =
        b.div(b.add(b.mul(v[kLeftCos], rightCos), b.mul(v[kLeftSin], rightSin)),
              b.max(b.mul(b.hypot(v[kLeftCos], v[kLeftSin]), b.hypot(rightCos, rightSin)), tiny));
    const ValueId threeTrust = b.mul(
        b.mul(runsTrust(b.min(firstRuns, b.min(leftRuns, rightRuns))),
              b.sub(one, b.smoothstep(b.constF(kApartFull), b.constF(kApartFrom), apartCosine))),
        b.mul(share(firstWeight), b.mul(share(leftWeight), share(rightWeight))));
    const ValueId threeRead = b.emit(
        Op::And, {b.emit(Op::Ge, {v[kLeftAway], zero}), b.emit(Op::Ge, {v[kRightAway], zero})});
    const ValueId three = b.emit(Op::And, {threeRead, b.gt(threeTrust, twoTrust)});
    const ValueId trust = b.select(three, threeTrust, twoTrust);
    const ValueId both =
        b.emit(Op::And,
               {b.emit(Op::And, {wanted, b.gt(trust, zero)}),
                b.emit(Op::And, {b.emit(Op::Ge, {v[kFirstAway], zero}),
                                 b.emit(Op::Or, {three, b.emit(Op::Or, {partsOther, fromRay})})})});
    const Vals read = b.ifThenElse(
        both,
        [&] {
            // The second family is the left where the lines run three ways (the right the
            // third), else the further of the two, or the ray's crossing.
            const PixelPoint firstAt{v[kFirstAway + 1], v[kFirstAway + 2]};
            const PixelPoint otherAt{
                b.select(three, v[kLeftU],
                         b.select(fromRay, crossing.at.u, slotOf(kLeftU, kRightU))),
                b.select(three, v[kLeftV],
                         b.select(fromRay, crossing.at.v, slotOf(kLeftV, kRightV)))};
            const Reading firstRead = readThere(b, at, pixel, firstAt);
            const Reading otherRead = readThere(b, at, pixel, otherAt);
            auto family = [&](const Reading& r, PixelPoint p, const Reading& across,
                              ValueId acrossDistance, const Probes& probes) {
                Spacing s =
                    spacingAlong(b, at, pixel, r, p, unitNormal(b, across), acrossDistance, probes);
                s.found = b.emit(Op::And, {s.found, straightAt(b, at, pixel, r, p)});
                // The family's mean as a phase family's: members at the integers of the
                // index, which runs n / L a world unit, the stroke h / (|grad d| L) to either
                // side of each.
                auto value = [&](ValueId x) { return ir::BuiltValue(b, x); };
                const ValueId per = b.div(pixel.size, s.spacing);
                const ValueId half = b.div(halfWidth, b.mul(heldLength(b, r), s.spacing));
                const ValueId mean = squareMeanInk(value(s.index), value(b.mul(b.abs(s.n.u), per)),
                                                   value(b.mul(b.abs(s.n.v), per)), value(half))
                                         .id;
                return std::tuple{s, mean, half};
            };
            const Probes probes = probesFor(b, three), threeProbes = probesFor(b, b.constB(true));
            auto [first, firstMean, firstHalf] =
                family(firstRead, firstAt, otherRead, zero, probes);
            // A point's distance from a family's nearest line, by its index there (the
            // centre's, and n / L a world unit).
            auto distanceFrom = [&](const Spacing& s, PixelPoint q) {
                const ValueId index =
                    b.add(s.index, b.div(b.add(b.mul(q.u, s.n.u), b.mul(q.v, s.n.v)), s.spacing));
                return b.mul(s.spacing, b.abs(b.sub(index, b.floor(b.add(index, b.constF(0.5))))));
            };
            const auto [other, otherMean, otherHalf] =
                family(otherRead, otherAt, firstRead, distanceFrom(first, otherAt), probes);
            // Where the lines run three ways and the first family's probes found no line (its
            // start by its own line, and the stride t too short for its probes to reach the
            // next), they try again with the stride the second family's distance gives.
            {
                const Vals again = b.ifThenElse(
                    b.emit(Op::And, {three, b.emit(Op::Not, {first.found})}),
                    [&] {
                        const auto [s, m, half] = family(firstRead, firstAt, otherRead,
                                                         distanceFrom(other, firstAt), threeProbes);
                        return Vals{b.select(s.found, one, zero), s.spacing, s.index, m, half};
                    },
                    [&] {
                        return Vals{b.select(first.found, one, zero), first.spacing, first.index,
                                    firstMean, firstHalf};
                    });
                first.found = b.gt(again[0], b.constF(0.5));
                first.spacing = again[1];
                first.index = again[2];
                firstMean = again[3];
                firstHalf = again[4];
            }
            // The index runs n / L a world unit: n along the pixel's sides turned back to the
            // world's axes.
            auto wayOf = [&](const Spacing& s, ValueId m) {
                const Offset g = worldOf(b, s.n.u, s.n.v, pixel);
                return Vals{s.index, b.div(one, s.spacing), b.div(g.ox, s.spacing),
                            b.div(g.oy, s.spacing), m};
            };
            // The third family where the lines run three ways: its way, whether its spacing
            // was found, and the three's excess over independent inks (tripleExcess). Where
            // the parts read two ways, a probe that read a third stands for the parts that
            // missed it (they alias with the lines at zooms where they stand nearly a whole
            // number of cells apart).
            const ValueId seen = b.emit(Op::Or, {first.thirdSeen, other.thirdSeen});
            // Where neither the parts nor the probes read a third family, and the two read
            // cross at 45 to 75 degrees (as two of a triangle lattice's three do; a square
            // grid's do not, and pays nothing more), a few points of the pixel off the parts'
            // lattice look for it.
            const ValueId crossCosine = facing(b, first.n, other.n);
            const ValueId aslant = b.emit(Op::And, {b.gt(crossCosine, b.constF(kAslantFrom)),
                                                    b.lt(crossCosine, b.constF(kAslantTo))});
            const Vals looked = b.ifThenElse(
                b.emit(Op::And, {aslant, b.emit(Op::Not, {b.emit(Op::Or, {three, seen})})}),
                [&] {
                    const CrossingStart c = firstLook(b, at, pixel, [&](const Reading& r) {
                        const Normal m = unitNormal(b, r);
                        return b.emit(Op::And, {crosses(b, first.n, m), crosses(b, other.n, m)});
                    });
                    return Vals{b.select(c.found, one, zero), c.at.u, c.at.v};
                },
                [&] { return Vals(3, zero); });
            const ValueId lookedThird = b.gt(looked[0], b.constF(0.5));
            const ValueId threeWays = b.emit(Op::Or, {three, b.emit(Op::Or, {seen, lookedThird})});
            const Vals third = b.ifThenElse(
                threeWays,
                [&] {
                    auto seenAt = [&](ValueId right, ValueId a, ValueId c, ValueId look) {
                        return b.select(
                            three, right,
                            b.select(first.thirdSeen, a, b.select(other.thirdSeen, c, look)));
                    };
                    const PixelPoint thirdAt{
                        seenAt(v[kRightU], first.thirdAt.u, other.thirdAt.u, looked[1]),
                        seenAt(v[kRightV], first.thirdAt.v, other.thirdAt.v, looked[2])};
                    const Reading thirdRead = readThere(b, at, pixel, thirdAt);
                    auto [s, m, half] = family(thirdRead, thirdAt, firstRead,
                                               distanceFrom(first, thirdAt), threeProbes);
                    // Its lines cross the other two's.
                    s.found = b.emit(Op::And, {s.found, crosses(b, s.n, first.n)});
                    s.found = b.emit(Op::And, {s.found, crosses(b, s.n, other.n)});
                    const ValueId excess =
                        excessOfThree(b, pixel, {&first, &other, &s}, {firstHalf, otherHalf, half});
                    Vals out = wayOf(s, m);
                    out.push_back(b.select(s.found, one, zero));
                    out.push_back(excess);
                    return out;
                },
                [&] {
                    Vals out(5, zero);
                    out.push_back(one);
                    out.push_back(zero);
                    return out;
                });
            const ValueId thirdMean = third[4];
            // Two families of lines crossing: over a pixel that holds two of each or more,
            // the union of independent inks; three, that and their excess.
            const ValueId paper =
                b.mul(b.mul(b.sub(one, firstMean), b.sub(one, otherMean)), b.sub(one, thirdMean));
            const ValueId mean = b.clamp(b.add(b.sub(one, paper), third[6]), zero, one);
            const ValueId found = b.emit(Op::And, {b.emit(Op::And, {first.found, other.found}),
                                                   b.gt(third[5], b.constF(0.5))});
            // The sparsest family's spacing: the third's is 1 / its gradient (0 where there is
            // none).
            const ValueId widest =
                b.max(b.max(first.spacing, other.spacing), b.div(one, b.max(third[1], tiny)));
            const ValueId thirdWidest =
                b.select(threeWays, widest, b.max(first.spacing, other.spacing));
            Vals out{b.select(found, one, zero), b.denan(mean, zero),
                     b.div(pixel.size, thirdWidest),
                     b.denan(b.div(halfWidth, heldLength(b, firstRead)), zero),
                     b.select(threeWays, one, zero)};
            for (const Vals& w : {wayOf(first, firstMean), wayOf(other, otherMean),
                                  Vals(third.begin(), third.begin() + 5)})
                for (ValueId x : w) out.push_back(b.denan(x, zero));
            return out;
        },
        [&] { return Vals(kGridRead, zero); });
    GridRead out{b.mul(trust, read[0]), read[1], read[2], {}, read[3], read[4]};
    for (int w = 0; w < 3; ++w) {
        const size_t k = 5 + 5 * w;
        out.ways[w] = {read[k], read[k + 1], read[k + 2], read[k + 3], read[k + 4]};
    }
    return out;
}

} // namespace moire::lower
