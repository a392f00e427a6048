#include "compiler/lower/DistanceGrid.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/Prefilter.h"

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

// How nearly each family's parts run one way (the length of their doubled angles' mean) before the
// grid is trusted, by a smoothstep: as for parallel members (DistanceFamily.cpp, kRunsFrom), and
// dots, whose normals run every way, stand near 1/2.
constexpr double kTwoWaysFrom = 0.9, kTwoWaysFull = 0.95;
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
// Where the two families' lines cross at under about 12 degrees, the probes' path runs nearly
// along the own family's lines: not read.
constexpr double kLeastCrossing = 0.2;
// A probe reads its family's line where its normal is within about 18 degrees of the start's.
constexpr double kParallel = 0.95;

// A family of lines does not bend: probes beside the start read the same line with a normal
// turned by under about 2.5 degrees (straightAt).
constexpr double kStraight = 0.999;

// The values the grid's branch returns: trust, mean, members, half-width, and five a way.
constexpr size_t kGridRead = 14;

// The points crossingSeen reads, the first of an R2 sequence: a lattice of them (a rank-1
// lattice of 8, 1/8 of a pixel apart across) read the same few places of a grid's cells at 20
// lines a pixel, where it aliased as the parts do, and left 0.0043 RMSE there (0.0022 now);
// a sequence has no rows to alias with any grid.
constexpr int kCrossingLooks = 8;

// Carried: how many parts are the other family's and the sums of their doubled angles, and
// each family's part furthest from its line: its distance and place.
enum Slot : size_t {
    kOthers,
    kCos,
    kSin,
    kFirstAway,
    kFirstU,
    kFirstV,
    kOtherAway,
    kOtherU,
    kOtherV
};

// A family's spacing along the normal of the reading r at p, probed along the lines of the
// other family (its unit normal `other`): whether it was found, the spacing L, and the
// family's index at the pixel's centre (the centre's offset from the line through r's foot,
// along the normal, over L).
struct Spacing {
    ValueId found, spacing, index;
    Normal n;
};
Spacing spacingAlong(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     const Reading& r, PixelPoint p, Normal other) {
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
    auto probe = [&](ValueId k) {
        return b.mul(step, b.add(b.constF(1.75), b.mul(k, b.constF(1.5))));
    };
    // Carried: the probe, whether the next line was read, its distance from f along n.
    std::vector<ValueId> init{zero, zero, zero};
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{b.emit(
            Op::And, {b.emit(Op::And, {b.lt(v[0], b.constF(kProbes)), b.lt(v[1], b.constF(0.5))}),
                      b.le(probe(v[0]), reach)})};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const ValueId s = b.div(probe(v[0]), b.max(rate, b.constF(kLeastCrossing)));
        const PixelPoint q{b.add(p.u, b.mul(s, path.u)), b.add(p.v, b.mul(s, path.v))};
        const Reading there = readThere(b, at, pixel, q);
        const Normal m = unitNormal(b, there);
        const ValueId parallel =
            b.gt(b.abs(b.add(b.mul(n.u, m.u), b.mul(n.v, m.v))), b.constF(kParallel));
        const PixelPoint foot = footFrom(b, there, q, true);
        const ValueId along = offsetAlong(b, f, foot, n);
        // Its own line 0 stands at 0 along n, the next one at L >= 2 t: t clears it. NaN (a
        // probe on a kink) compares false.
        const ValueId hit = b.emit(
            Op::And, {b.emit(Op::And, {parallel, b.gt(there.length, zero)}), b.gt(along, step)});
        return std::vector<ValueId>{b.add(v[0], one), b.select(hit, one, zero),
                                    b.select(hit, along, v[2])};
    });
    const ValueId spacing = b.max(out[2], b.mul(pixel.size, b.constF(1e-4)));
    // The centre (0, 0) stands -f . n from the line through f.
    const ValueId offset = offsetAlong(b, f, {b.constF(0.0), b.constF(0.0)}, n);
    const ValueId found =
        b.emit(Op::And, {b.gt(out[1], b.constF(0.5)), b.gt(rate, b.constF(kLeastCrossing))});
    return {found, spacing, b.div(offset, spacing), n};
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
        const Reading there = readThere(b, at, pixel, q);
        const Normal m = unitNormal(b, there);
        const PixelPoint foot = footFrom(b, there, q, true);
        const ValueId off = b.abs(offsetAlong(b, f, foot, n));
        const ValueId facing = b.abs(b.add(b.mul(n.u, m.u), b.mul(n.v, m.v)));
        const ValueId same = b.lt(off, b.mul(t, b.constF(0.1)));
        straight =
            b.emit(Op::And, {straight, b.emit(Op::And, {same, b.gt(facing, b.constF(kStraight))})});
    }
    return straight;
}

} // namespace

TwoDirections::TwoDirections(ir::Builder& b, const Reading& centre) : b_(b) {
    const DoubledAngle a = doubledAngle(b, centre);
    cos2_ = a.cos2;
    sin2_ = a.sin2;
}

std::vector<ValueId> TwoDirections::start() const {
    std::vector<ValueId> v(kCarried, b_.constF(0.0));
    // No part yet: the furthest stand at -1.
    v[kFirstAway] = v[kOtherAway] = b_.constF(-1.0);
    return v;
}

std::vector<ValueId> TwoDirections::add(std::span<const ValueId> v, ValueId away, ValueId cos2,
                                        ValueId sin2, ValueId some, PixelPoint p) const {
    ir::Builder& b = b_;
    const ValueId zero = b.constF(0.0);
    // The part is the first family's where its doubled angle is within a right angle of the
    // centre's (its normal within 45 degrees of the centre's), else the other's.
    const ValueId cosine = b.add(b.mul(cos2, cos2_), b.mul(sin2, sin2_));
    const ValueId first = b.emit(Op::Ge, {cosine, zero});
    const ValueId weight =
        b.select(b.emit(Op::And, {some, b.emit(Op::Not, {first})}), b.constF(1.0), zero);
    std::vector<ValueId> out(v.begin(), v.end());
    out[kOthers] = b.add(v[kOthers], weight);
    out[kCos] = b.add(v[kCos], b.mul(weight, cos2));
    out[kSin] = b.add(v[kSin], b.mul(weight, sin2));
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
    furthest(kOtherAway, b.emit(Op::Not, {first}));
    return out;
}

CrossingStart crossingSeen(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                           ValueId cos2, ValueId sin2) {
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
        const DoubledAngle a = doubledAngle(b, r);
        // Its doubled angle more than a right angle from the axis's: a direction more than
        // 45 degrees off.
        const ValueId crossed =
            b.emit(Op::And, {b.gt(r.length, zero),
                             b.lt(b.add(b.mul(a.cos2, cos2), b.mul(a.sin2, sin2)), zero)});
        return std::vector<ValueId>{b.add(k, one), b.select(crossed, one, zero),
                                    b.select(crossed, p.u, v[2]), b.select(crossed, p.v, v[3])};
    });
    return {b.gt(out[1], half), {out[2], out[3]}};
}

GridRead gridRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                  ValueId halfWidth, std::span<const ValueId> v, ValueId cos2, ValueId sin2,
                  ValueId directed, ValueId wanted, const CrossingStart& crossing) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0), tiny = b.constF(1e-30);
    // Each family's mean direction, and how nearly its parts run that way: the other
    // family's sums are carried, the first's are the rest.
    const ValueId count = b.max(directed, one);
    const ValueId otherWeight = v[kOthers], firstWeight = b.sub(directed, v[kOthers]);
    const ValueId otherRuns = b.div(b.hypot(v[kCos], v[kSin]), b.max(otherWeight, tiny));
    const ValueId firstRuns =
        b.div(b.hypot(b.sub(cos2, v[kCos]), b.sub(sin2, v[kSin])), b.max(firstWeight, tiny));
    auto share = [&](ValueId weight) {
        return b.smoothstep(b.constF(kShareFrom), b.constF(kShareFull), b.div(weight, count));
    };
    // Where no part reads the second family, the crossing the centre's ray met stands for it.
    const ValueId partsOther = b.emit(Op::Ge, {v[kOtherAway], zero});
    const ValueId fromRay = b.emit(Op::And, {b.emit(Op::Not, {partsOther}), crossing.found});
    const ValueId runs = b.select(partsOther, b.min(firstRuns, otherRuns), firstRuns);
    const ValueId trust =
        b.mul(b.smoothstep(b.constF(kTwoWaysFrom), b.constF(kTwoWaysFull), runs),
              b.select(partsOther, b.mul(share(otherWeight), share(firstWeight)), one));
    const ValueId both =
        b.emit(Op::And, {b.emit(Op::And, {wanted, b.gt(trust, zero)}),
                         b.emit(Op::And, {b.emit(Op::Ge, {v[kFirstAway], zero}),
                                          b.emit(Op::Or, {partsOther, fromRay})})});
    const Vals read = b.ifThenElse(
        both,
        [&] {
            const PixelPoint firstAt{v[kFirstAway + 1], v[kFirstAway + 2]};
            const PixelPoint otherAt{b.select(fromRay, crossing.at.u, v[kOtherAway + 1]),
                                     b.select(fromRay, crossing.at.v, v[kOtherAway + 2])};
            const Reading firstRead = readThere(b, at, pixel, firstAt);
            const Reading otherRead = readThere(b, at, pixel, otherAt);
            auto family = [&](const Reading& r, PixelPoint p, const Reading& across) {
                Spacing s = spacingAlong(b, at, pixel, r, p, unitNormal(b, across));
                s.found = b.emit(Op::And, {s.found, straightAt(b, at, pixel, r, p)});
                // The family's mean as a phase family's: members at the integers of the
                // index, which runs n / L a world unit, the stroke h / (|grad d| L) to either
                // side of each.
                auto value = [&](ValueId x) { return ir::BuiltValue(b, x); };
                const ValueId per = b.div(pixel.size, s.spacing);
                const ValueId mean =
                    squareMeanInk(value(s.index), value(b.mul(b.abs(s.n.u), per)),
                                  value(b.mul(b.abs(s.n.v), per)),
                                  value(b.div(halfWidth, b.mul(heldLength(b, r), s.spacing))))
                        .id;
                return std::pair{s, mean};
            };
            const auto [first, firstMean] = family(firstRead, firstAt, otherRead);
            const auto [other, otherMean] = family(otherRead, otherAt, firstRead);
            // Two families of lines crossing: over a pixel that holds two of each or more,
            // the union of independent inks.
            const ValueId mean = b.sub(b.add(firstMean, otherMean), b.mul(firstMean, otherMean));
            const ValueId found = b.emit(Op::And, {first.found, other.found});
            Vals out{b.select(found, one, zero), b.denan(mean, zero),
                     b.div(pixel.size, b.max(first.spacing, other.spacing)),
                     b.denan(b.div(halfWidth, heldLength(b, firstRead)), zero)};
            for (const auto& [s, m] : {std::pair{first, firstMean}, std::pair{other, otherMean}}) {
                // The index runs n / L a world unit: n along the pixel's sides turned back to
                // the world's axes.
                const Offset g = worldOf(b, s.n.u, s.n.v, pixel);
                for (ValueId x : {s.index, b.div(one, s.spacing), b.div(g.ox, s.spacing),
                                  b.div(g.oy, s.spacing), m})
                    out.push_back(b.denan(x, zero));
            }
            return out;
        },
        [&] { return Vals(kGridRead, zero); });
    GridRead out{b.mul(trust, read[0]), read[1], read[2], {}, read[3]};
    for (int w = 0; w < 2; ++w) {
        const size_t k = 4 + 5 * w;
        out.ways[w] = {read[k], read[k + 1], read[k + 2], read[k + 3], read[k + 4]};
    }
    return out;
}

} // namespace moire::lower
