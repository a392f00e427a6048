#include "compiler/lower/DistanceFamily.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/DistanceDots.h"
#include "compiler/lower/DistanceGrid.h"
#include "compiler/lower/DistanceRings.h"
#include "compiler/lower/DistanceTubes.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/StrokePairs.h"

#include <span>
#include <vector>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

namespace {

// How much faster than at the centre a distance may change across the pixel: a distance
// given as |f| for a smooth f whose gradient grows, not a Euclidean one.
constexpr double kGrowth = 1.25;
// The share of the 4 x 4 parts' neighbouring pairs that must hold another's stroke (each way
// round counted once) before the tubes are read: crowded dots cross nearly every pair, a
// resolved grid's crossing a few (at three quarters, dots five a pixel read 0.052 off). Crowded
// parallel curves cross only the pairs along their normal (half, where it runs along a side:
// rings fifty a pixel read 0.236 against 0.250 with some of their pixels left out), so they
// are read as well where the parts' members stand within kParallelGate fine parts' sides on
// average, which a resolved member's pixel does not (its parts' mean distance is a fifth of
// the pixel at least: 1.6 fine parts' sides).
constexpr double kCrossedGate = 0.5, kParallelGate = 0.5;
// A neighbour's member is the square's own where their feet stand within kSameFoot of a side
// (a point), or its foot stands that near the own centre line and their normals' cosine is past
// kSameFacing (a curve).
constexpr double kSameFoot = 0.25;
constexpr double kSameFacing = 0.9;
// The coarse parts' coherence (Parts) over which a crowd's members are taken as running
// parallel, by a smoothstep from kRunsFrom to kRunsFull: the parts' normals within about 13
// and 9 degrees of one direction, which rings meet from about 1.3 and 1.8 pixels off their
// centre (coherence about 1 - 0.16 / R^2, R in pixels). A grid's two directions, or dots'
// normals running out from several dots, stand near 0: such a crowd is laid as independent.
constexpr double kRunsFrom = 0.9, kRunsFull = 0.95;
// A crowd read by the index it runs by is read in closed form (Prefilter.h, squareMeanInk)
// rather than in parts or by its tubes from kClosedFrom to kClosedFull members a pixel:
// exact for straight members at any density, and within 0.0009 RMSE of the parts for the
// rings and waves of tests/filter_test.cpp at 2 to 5 a pixel (rings 0.2 apart about their
// centre 0.0007, 0.0005 in parts; from 1/12 apart, where the tubes read them, 0.0001, 0.0004
// by the tubes), at a ray's cost where the parts read 80 points and the tubes 34 rays.
constexpr double kClosedFrom = 2.0, kClosedFull = 3.0;
// A dot screen's closed form (DistanceDots.h) takes over sooner, from kDotsClosedFrom to
// kDotsClosedFull cells a pixel along a side: dots two a pixel square to the pixels put every
// part's centre on a square dot's corner, where no reading tells the corner (such squares were
// drawn with twice their ink), and over square dots 2.2 to 2.5 a pixel, turned, the parts read
// 0.0042 to 0.0076 RMSE where the closed form reads 0.0008 to 0.0020 (round dots alike within
// 0.001 either way; tests/distance_dots_test.cpp). Rings about a lattice's points, two dot
// screens' difference (DistanceRings.h), hand over alike: 0.0017 RMSE at 2.5 a pixel.
constexpr double kDotsClosedFrom = 1.8, kDotsClosedFull = 2.0;
// How far along its normal the centre looks for the ridge, in pixels: members whose ray runs
// further stand more than two pixels apart, resolved (under kCrowdFrom members a pixel), and
// their spacing reads as twice the reach, which is resolved too.
constexpr double kRunsReach = 1.0;

// A reading whose gradient vanishes (or is NaN), at a kink of the distance such as |f| where f
// is 0 to the last bit (often so in float), with `stand`'s gradient: the pixel's centre's
// (which is read in parts where its own vanishes).
Reading steady(ir::Builder& b, const Reading& r, const Reading& stand) {
    ValueId some = b.gt(r.length, b.constF(0.0)); // false on NaN too
    return {r.d, b.select(some, r.gu, stand.gu), b.select(some, r.gv, stand.gv),
            b.select(some, r.length, stand.length)};
}

// The mean over a square of side `side` about the reading's point of the stroke d < h, the
// distance read to first order: a centre line d / |grad d| away across the gradient, the stroke
// h / |grad d| to either side of it (distanceMeanInk); a vanishing gradient `stand`'s
// (steady).
//
// `nearIn` (world units, or none) moves the stroke's edge on the reading's side of the centre
// line in by that much, the far edge staying: across the centre line, in world units, the band
// (-h', h' - nearIn) with h' = h / |grad d|, which is the band of half-width h' - nearIn / 2
// about -nearIn / 2.
ValueId firstOrderMean(ir::Builder& b, const Reading& reading, ValueId h, ValueId side,
                       const Reading& stand, ValueId nearIn = ir::kNoValue) {
    const Reading r = steady(b, reading, stand);
    const ValueId length = heldLength(b, r);
    NormalExtents e = extentsAcross(b, r.gu, r.gv, side);
    ValueId d = b.div(r.d, length), half = b.div(h, length);
    if (nearIn != ir::kNoValue) {
        ValueId moved = b.mul(nearIn, b.constF(0.5));
        d = b.add(d, moved);
        half = b.sub(half, moved);
    }
    ValueId mean = distanceMeanInk(ir::BuiltValue(b, d), ir::BuiltValue(b, half),
                                   ir::BuiltValue(b, e.along), ir::BuiltValue(b, e.across))
                       .id;
    return b.denan(mean, b.constF(0.0));
}

// The first-order reading from `r` at o, (da, dc) sides of `span` pixels from its point:
// |d + grad d . o|.
ValueId firstOrderAt(ir::Builder& b, const Reading& r, double da, double dc, ValueId span) {
    ValueId along = b.mul(span, b.add(b.mul(r.gu, b.constF(da)), b.mul(r.gv, b.constF(dc))));
    return b.abs(b.add(r.d, along));
}

// Whether the distance read `there` stands off the first-order reading from `r` there
// (`predicted`, firstOrderAt) by more than kStraightSlack of the change across `span` pixels.
ValueId bends(ir::Builder& b, const Reading& r, ValueId there, ValueId predicted, ValueId span) {
    ValueId slack = b.mul(b.constF(kStraightSlack), b.mul(r.length, span));
    return b.gt(b.abs(b.sub(there, predicted)), slack);
}

ValueId anyOf(ir::Builder& b, const std::vector<ValueId>& flags) {
    ValueId out = b.constB(false);
    for (ValueId f : flags) out = b.emit(Op::Or, {out, f});
    return out;
}

// Whether the stroke of `m`'s member, read straight from `m`'s point, reaches into the square
// of side `side` whose centre stands (da, dc) sides from it: the least of d + grad d . o over
// the square, d + side (grad d . (da, dc) - (|g_u| + |g_v|) / 2), short of h (with
// kStraightSlack to spare).
ValueId reachesInto(ir::Builder& b, const Reading& m, double da, double dc, ValueId side,
                    ValueId h) {
    ValueId toward = b.add(b.mul(m.gu, b.constF(da)), b.mul(m.gv, b.constF(dc)));
    ValueId spread = b.mul(b.add(b.abs(m.gu), b.abs(m.gv)), b.constF(0.5));
    ValueId least = b.add(m.d, b.mul(side, b.sub(toward, spread)));
    ValueId slack = b.mul(b.constF(kStraightSlack), b.mul(m.length, side));
    return b.lt(least, b.add(h, slack));
}

// Whether `model`, a neighbour's first-order distance at a point whose own reading is `own`,
// stands below it by more than `slack` (a negative slack: not above it by more than -slack):
// the distance there is the greater of the two. A model below 0 has crossed its own centre
// line (|f|'s kink), which says nothing of a greater distance.
ValueId greaterThere(ir::Builder& b, ValueId model, ValueId own, ValueId slack) {
    return b.emit(Op::And, {b.lt(model, b.sub(own, slack)), b.gt(model, b.constF(0.0))});
}

// The same, or `model` level with `own` (within `slack`) where the neighbour's own reading
// (`there`) stands further than the point's first-order reading puts it there (`predicted`,
// firstOrderAt): the greater of two met on its diagonal, where the two read alike (a
// lattice square to the parts puts its squares' corners on the parts' centres). The lesser of
// two (a grid's crossing) met on its diagonal reads nearer there instead.
ValueId greaterOrLevel(ir::Builder& b, ValueId model, ValueId own, ValueId slack, ValueId there,
                       ValueId predicted) {
    const ValueId level = b.emit(
        Op::And, {greaterThere(b, model, own, b.neg(slack)), b.gt(there, b.add(predicted, slack))});
    return b.emit(Op::Or, {greaterThere(b, model, own, slack), level});
}

// Whether the distance about r's square is the greater of r's first-order reading and that of
// `s` (da, dc) sides away, near the stroke's edge: s's reading at r's point stands below r's by
// more than kStraightSlack of a side's change, or level with it (greaterOrLevel), facing
// another way (a box's or a Chebyshev dot's distance past the diagonal where its normal
// turns), and r's distance within a side's change of h. Its stroke is then the two
// first-order strokes' intersection (unionMean).
ValueId boundedBy(ir::Builder& b, const Reading& r, const Reading& s, double da, double dc,
                  ValueId side, ValueId h) {
    const ValueId back = b.mul(side, b.add(b.mul(s.gu, b.constF(da)), b.mul(s.gv, b.constF(dc))));
    const ValueId change = b.mul(r.length, side);
    const ValueId slack = b.mul(b.constF(kStraightSlack), change);
    const ValueId below =
        greaterOrLevel(b, b.sub(s.d, back), r.d, slack, s.d, firstOrderAt(b, r, da, dc, side));
    const ValueId cosine = b.div(b.add(b.mul(r.gu, s.gu), b.mul(r.gv, s.gv)),
                                 b.max(b.mul(r.length, s.length), b.constF(1e-30)));
    const ValueId turned = b.lt(b.abs(cosine), b.constF(kSameFacing));
    const ValueId edge = b.lt(b.abs(b.sub(r.d, h)), change);
    return b.emit(Op::And, {b.emit(Op::And, {below, turned}), edge});
}

// Whether the square of reading `r` holds the stroke of a member other than its own, as read
// from `s`, (da, dc) sides away: `s` stands off r's first-order reading (bends) and its member's
// stroke, read straight from `s`, reaches into r's square.
ValueId otherReaches(ir::Builder& b, const Reading& r, const Reading& s, double da, double dc,
                     ValueId side, ValueId h) {
    return b.emit(Op::And, {bends(b, r, s.d, firstOrderAt(b, r, da, dc, side), side),
                            reachesInto(b, s, -da, -dc, side, h)});
}

// The readings of a row of n squares whose centres stand `c` pixel units up from the pixel's.
std::vector<Reading> readRow(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                             ValueId c, int n) {
    std::vector<Reading> row;
    for (int i = 0; i < n; ++i) {
        Offset o = offsetOf(b, place(b, b.constF(i), n), c, pixel);
        row.push_back(readAt(b, at(b, o.ox, o.oy), pixel));
    }
    return row;
}

// A row of n readings carried by a loop, four values a reading from `first`, and back.
std::vector<Reading> carriedRow(std::span<const ValueId> v, size_t first, int n) {
    std::vector<Reading> row;
    for (int i = 0; i < n; ++i) {
        const size_t k = first + 4 * i;
        row.push_back({v[k], v[k + 1], v[k + 2], v[k + 3]});
    }
    return row;
}
void carry(std::vector<ValueId>& next, const std::vector<Reading>& row) {
    for (const Reading& r : row) next.insert(next.end(), {r.d, r.gu, r.gv, r.length});
}

// The curvature of the level set through a square's point, from its neighbours' normals where
// they read its own member: a distance's normals run straight from the centre of curvature,
// so how far a neighbour's has turned from the square's own says how far off that centre is
// (add), and kappa is the least-squares fit over the neighbours. It is > 0 where the level
// set bends back from the normal (about a dot), < 0 where it bends towards it (inside a ring).
// The stroke's near edge, (h - d) / |grad d| further along the normal, bends by
// kappa / (1 + kappa (h - d) / |grad d|) (the level sets of a distance are parallel curves);
// a straight edge across a square of side s inks the parabola's lens beyond it, about
// kappa_edge s^2 / 24 of the square's area once a side of edge (the square's second moment
// s^2 / 12 about any line through its centre), which moving the edge in by kappa_edge s^2 /
// 24 takes back (edgeIn). Without it a dot's edge read straight made dots 0.7 apart 5% heavy.
class Curvature {
  public:
    Curvature(ir::Builder& b, const Reading& own, ValueId side)
        : own_(own), n_(unitNormal(b, own)), side_(side), num_(b.constF(0.0)), den_(b.constF(0.0)) {
    }
    // A neighbour (da, dc) sides away, counted where `counts`.
    void add(ir::Builder& b, ValueId counts, const Reading& n, double da, double dc) {
        // The normals of parallel curves meet at the centre of curvature, 1 / kappa along the
        // normal from the square's point. A neighbour a step (tau along the tangent t = (-n_v,
        // n_u), nu along the normal) away has turned by tan theta = kappa tau / (1 + kappa nu),
        // that is tan theta = kappa (tau - nu tan theta): exact for a circle, whatever the step.
        const Turn turn = turnOf(b, n_, unitNormal(b, n));
        const ValueId tau = b.add(b.mul(b.neg(n_.v), b.constF(da)), b.mul(n_.u, b.constF(dc)));
        const ValueId across = b.add(b.mul(n_.u, b.constF(da)), b.mul(n_.v, b.constF(dc)));
        const ValueId step = b.sub(tau, b.mul(across, turn.tangent)); // in sides
        // A normal turned past a right angle is the member's far side (a neighbour across
        // its centre line), not the level set bending.
        const ValueId zero = b.constF(0.0);
        counts = b.emit(Op::And, {counts, b.gt(turn.cosine, zero)});
        num_ = b.add(num_, b.select(counts, b.mul(turn.tangent, step), zero));
        den_ = b.add(den_, b.select(counts, b.mul(step, step), zero));
    }
    // How far (world units) to move the near edge in: none where no neighbour stands along
    // the level set (a quarter of a side's step squared at least), and held to a twelfth of a
    // side (the edge's curvature to 2 a side) where the estimate is far off the parabola's
    // reach.
    ValueId edgeIn(ir::Builder& b, ValueId h) const {
        const ValueId some = b.gt(den_, b.constF(kLeastStep));
        const ValueId kappa = b.div(b.select(some, num_, b.constF(0.0)),
                                    b.mul(b.max(den_, b.constF(kLeastStep)), side_));
        const ValueId toEdge = b.div(b.sub(h, own_.d), heldLength(b, own_));
        const ValueId spread = b.max(b.add(b.constF(1.0), b.mul(kappa, toEdge)), b.constF(0.1));
        const ValueId most = b.div(b.constF(kMostBend), side_);
        const ValueId atEdge = b.clamp(b.div(kappa, spread), b.neg(most), most);
        return b.denan(b.mul(atEdge, b.mul(b.mul(side_, side_), b.constF(1.0 / 24.0))),
                       b.constF(0.0));
    }

  private:
    static constexpr double kLeastStep = 0.25, kMostBend = 2.0;
    Reading own_;
    Normal n_;
    ValueId side_, num_, den_;
};

// A square's ink where a second member's stroke may cross it: its own member's stroke and the
// nearest of its four neighbours' members whose stroke reaches in (`reachesInto`, read
// straight from the neighbour), their union by inclusion and exclusion, a1 + a2 - E[A1 A2],
// E[A1 A2] = a1 a2 + the two straight strokes' covariance over the square (StrokePairs.h:
// strokeCovariance, in the square's units). `others` are the neighbours' readings with their
// offsets (in sides) from the square and whether each is there.
struct Neighbour {
    Reading r;
    double da, dc;
    ValueId there;
};
ValueId unionMean(ir::Builder& b, const Reading& read, const std::vector<Neighbour>& others,
                  ValueId h, ValueId side, const Reading& centre) {
    const Reading own = steady(b, read, centre);
    // The nearest other stroke to the square's centre: its first-order distance there.
    ValueId found = b.constB(false), best = b.constF(kNoMember);
    Reading other{b.constF(kNoMember), centre.gu, centre.gv, centre.length};
    // The foot of a reading's member from the square's centre, in world units along the
    // pixel's sides (its point is (da, dc) sides away).
    auto foot = [&](const Reading& r, double da, double dc) {
        return footFrom(b, r, {b.mul(side, b.constF(da)), b.mul(side, b.constF(dc))}, true);
    };
    const PixelPoint ownFoot = foot(own, 0, 0);
    const ValueId ownLength = heldLength(b, own);
    Curvature bend(b, own, side);
    // A neighbour whose first-order distance at the square's centre stands below the square's
    // own reading, facing another way: the distance there is the greater of the two (a box's
    // or a Chebyshev dot's, max(|dx|, |dy|), past the diagonal where its normal turns), whose
    // stroke is the two first-order strokes' intersection, not their union (d is the lesser of
    // two members' distances where members meet). The greatest such bound. Also level with it
    // (greaterOrLevel): taken below only, squares 1.3 a pixel square to the pixels were drawn
    // 22% heavy, their corners' parts half inked.
    ValueId clipFound = b.constB(false), clipBest = b.constF(-kNoMember);
    Reading clip{b.constF(kNoMember), centre.gu, centre.gv, centre.length};
    const ValueId clipSlack = b.mul(b.constF(kStraightSlack), b.mul(own.length, side));
    for (const Neighbour& neighbour : others) {
        Neighbour n = neighbour;
        n.r = steady(b, n.r, centre);
        ValueId crosses =
            b.emit(Op::And, {n.there, otherReaches(b, own, n.r, n.da, n.dc, side, h)});
        // The same member seen bending, not another: its foot where the square's own is (a
        // point, a dot's centre), or on the square's own centre line facing the same way (a
        // curve). kSameFoot of a side either way.
        const PixelPoint itsFoot = foot(n.r, n.da, n.dc);
        ValueId apart = b.hypot(b.sub(itsFoot.u, ownFoot.u), b.sub(itsFoot.v, ownFoot.v));
        ValueId onLine = b.abs(b.div(
            b.add(own.d, b.add(b.mul(own.gu, itsFoot.u), b.mul(own.gv, itsFoot.v))), ownLength));
        ValueId facing = b.gt(b.abs(b.div(b.add(b.mul(own.gu, n.r.gu), b.mul(own.gv, n.r.gv)),
                                          b.max(b.mul(ownLength, n.r.length), b.constF(1e-30)))),
                              b.constF(kSameFacing));
        ValueId reach = b.mul(side, b.constF(kSameFoot));
        ValueId same =
            b.emit(Op::Or, {b.lt(apart, reach), b.emit(Op::And, {facing, b.lt(onLine, reach)})});
        crosses = b.emit(Op::And, {crosses, b.emit(Op::Not, {same})});
        // The same member's normal, turned from the square's own: the level set's curvature
        // (Curvature), from a neighbour whose own gradient is there (not `steady`'s
        // stand-in).
        ValueId counts = b.emit(Op::And, {b.emit(Op::And, {neighbour.there, same}),
                                          b.gt(neighbour.r.length, b.constF(0.0))});
        bend.add(b, counts, n.r, n.da, n.dc);
        // Its distance at the square's centre, (da, dc) sides back from its own point.
        ValueId back =
            b.mul(side, b.add(b.mul(n.r.gu, b.constF(n.da)), b.mul(n.r.gv, b.constF(n.dc))));
        ValueId f = b.sub(n.r.d, back);
        const ValueId greater =
            greaterOrLevel(b, f, own.d, clipSlack, n.r.d, firstOrderAt(b, own, n.da, n.dc, side));
        const ValueId below =
            b.emit(Op::And, {b.emit(Op::And, {neighbour.there, b.emit(Op::Not, {same})}),
                             b.emit(Op::And, {greater, b.emit(Op::Not, {facing})})});
        const ValueId binds = b.emit(Op::And, {below, b.gt(f, clipBest)});
        clipBest = b.select(binds, f, clipBest);
        clip = {b.select(binds, f, clip.d), b.select(binds, n.r.gu, clip.gu),
                b.select(binds, n.r.gv, clip.gv), b.select(binds, n.r.length, clip.length)};
        clipFound = b.emit(Op::Or, {clipFound, binds});
        crosses = b.emit(Op::And, {crosses, b.emit(Op::Not, {below})});
        ValueId nearer = b.emit(Op::And, {crosses, b.lt(b.abs(f), best)});
        best = b.select(nearer, b.abs(f), best);
        other = {b.select(nearer, f, other.d), b.select(nearer, n.r.gu, other.gu),
                 b.select(nearer, n.r.gv, other.gv), b.select(nearer, n.r.length, other.length)};
        found = b.emit(Op::Or, {found, nearer});
    }
    // The own stroke's near edge, moved in where it bends away from the square (a dot's).
    const ValueId a1 = firstOrderMean(b, own, h, side, centre, bend.edgeIn(b, h));
    // Behind a branch: most squares hold one member's stroke or none. One partner a square,
    // its covariance written out once: the bound where there is one (the strokes'
    // intersection), else the other member's stroke (their union).
    const Reading partner{
        b.select(clipFound, clip.d, other.d), b.select(clipFound, clip.gu, other.gu),
        b.select(clipFound, clip.gv, other.gv), b.select(clipFound, clip.length, other.length)};
    return b.ifThenElse(
        b.emit(Op::Or, {found, clipFound}),
        [&] {
            const ValueId a2 = firstOrderMean(b, partner, h, side, centre);
            auto across = [&](const Reading& r) { // the stroke in the square's units
                const ValueId length = heldLength(b, r);
                ValueId scale = b.mul(length, side);
                return StrokeAcross{b.div(r.gu, length), b.div(r.gv, length), b.div(r.d, scale),
                                    b.div(h, scale),     b.constF(1.0),       b.constB(true)};
            };
            const ValueId cov = strokeCovariance(b, across(own), across(partner));
            const ValueId overlap = b.add(b.mul(a1, a2), cov);
            const ValueId both = b.sub(b.add(a1, a2), overlap);
            const ValueId joined =
                b.min(b.max(both, b.max(a1, a2)), b.min(b.add(a1, a2), b.constF(1.0)));
            const ValueId cut = b.clamp(overlap, b.constF(0.0), b.min(a1, a2));
            return Vals{b.denan(b.select(clipFound, cut, joined), a1)};
        },
        [&] { return Vals{a1}; })[0];
}

// The pixel cut into n x n squares, each read to first order about its centre, with a second
// member's stroke where one crosses it (unionMean): their mean ink. A loop over the rows of
// squares, the family's expression written out once a square of a row (a loop over every
// square, written out once, took 1.6 times as long on the JIT; the whole pixel written out, a
// kernel that lavapipe took 30 s to compile). A row's squares are read once the row above is
// (their upper neighbours): the loop reads rows 0 to n, the last above the pixel, and carries
// the two rows before.
ValueId finePartsMean(ir::Builder& b, const DistanceAt& at, ValueId h, const PixelFootprint& pixel,
                      const Reading& centre, int n) {
    const ValueId side = b.div(pixel.size, b.constF(n));
    // Carried: the row read, the sum, the rows two and one before it (four values a square).
    std::vector<ValueId> init(2 + 8 * n, b.constF(0.0));
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{b.le(v[0], b.constF(n))};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const std::vector<Reading> row = readRow(b, at, pixel, place(b, v[0], n), n);
        const std::vector<Reading> below = carriedRow(v, 2, n), mid = carriedRow(v, 2 + 4 * n, n);
        // The squares of the row before this one (none before the first).
        const ValueId yes = b.constB(true);
        const ValueId hasBelow = b.gt(v[0], b.constF(1.5));
        ValueId sum = b.constF(0.0);
        for (int i = 0; i < n; ++i) {
            std::vector<Neighbour> others{{row[i], 0, 1, yes}, {below[i], 0, -1, hasBelow}};
            if (i > 0) others.push_back({mid[i - 1], -1, 0, yes});
            if (i + 1 < n) others.push_back({mid[i + 1], 1, 0, yes});
            sum = b.add(sum, unionMean(b, mid[i], others, h, side, centre));
        }
        std::vector<ValueId> next{
            b.add(v[0], b.constF(1.0)),
            b.add(v[1], b.select(b.gt(v[0], b.constF(0.5)), sum, b.constF(0.0)))};
        carry(next, mid);
        carry(next, row);
        return next;
    });
    return b.mul(out[1], b.constF(1.0 / (n * n)));
}

// The pixel cut into n x n squares, each read to first order about its centre: their mean ink,
// and whether any square holds the stroke of a member other than its own: a neighbour's reading
// that stands off the square's own (`bends`) and whose member's stroke, read straight from the
// neighbour, reaches into the square. Where none does, each square holds its own member's stroke
// alone and the mean is exact to first order. A loop over the rows of squares (the family's
// expression is written out once a row, not once a square), carrying the row below's readings to
// compare with. `near`: the squares' mean distance to their members in world units, each held
// to kTubeReach fine parts' sides; `crossed`: the share of neighbouring pairs of which one
// holds the other's stroke (whether the members may be crowded: DistanceTubes.h);
// `coherence`: how nearly the squares' normals run one way or its opposite, the length of
// the mean of (cos 2 theta, sin 2 theta) over those with a gradient (1 for parallel members,
// about 0 for dots or a grid's two directions; a square on a kink, where float meets the
// gradient's vanishing far more often than double, has no direction and is not counted).
// `axis`: the direction they run along, as a unit normal along the pixel's sides (its sense
// unknown): the half angle of that mean.
// `cos2`, `sin2`, `directed`: the sums of those doubled angles and how many there are, and
// `ways` the parts' directions as a grid's lines run (DistanceGrid.h).
struct Parts {
    ValueId mean, bent, near, crossed, coherence;
    Normal axis;
    ValueId cos2, sin2, directed;
    std::vector<ValueId> ways;
};
Parts partsMean(ir::Builder& b, const DistanceAt& at, ValueId h, const PixelFootprint& pixel,
                const Reading& centre, int n) {
    const ValueId side = b.div(pixel.size, b.constF(n));
    // Carried: the row, the sum of the squares' means, how many pairs hold another's stroke,
    // the sum of their (held) distances, the sums of their normals' doubled angles' cosines
    // and sines and how many have a normal, whether a pair's distance is the greater of the
    // two readings (boundedBy), and the row below's readings, four values a square.
    const ValueId most =
        b.mul(b.div(pixel.size, b.constF(kDistanceFineTaps)), b.constF(kTubeReach));
    const PartDirections ways(b, centre);
    constexpr size_t kWaysAt = 8, kRowAt = kWaysAt + PartDirections::kCarried;
    std::vector<ValueId> init(kRowAt + 4 * n, b.constF(0.0));
    const std::vector<ValueId> waysStart = ways.start();
    std::copy(waysStart.begin(), waysStart.end(), init.begin() + kWaysAt);
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{b.lt(v[0], b.constF(n))};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const std::vector<Reading> row = readRow(b, at, pixel, place(b, v[0], n), n);
        ValueId sum = v[1];
        ValueId near = v[3];
        ValueId cos2 = v[4], sin2 = v[5], directed = v[6];
        std::vector<ValueId> partWays(v.begin() + kWaysAt, v.begin() + kRowAt);
        const ValueId rowAt = b.mul(place(b, v[0], n), pixel.size);
        for (int i = 0; i < n; ++i) {
            const Reading& r = row[i];
            sum = b.add(sum, firstOrderMean(b, r, h, side, centre));
            const ValueId away = b.div(r.d, heldLength(b, r));
            near = b.add(near, b.min(b.denan(away, most), most));
            // A vanishing gradient (a kink) has no direction.
            const ValueId some = b.gt(r.length, b.constF(0.0)); // false on NaN too
            const DoubledAngle a = doubledAngle(b, r);
            const ValueId c = a.cos2, s2 = a.sin2;
            cos2 = b.add(cos2, b.select(some, c, b.constF(0.0)));
            sin2 = b.add(sin2, b.select(some, s2, b.constF(0.0)));
            directed = b.add(directed, b.select(some, b.constF(1.0), b.constF(0.0)));
            const PixelPoint at{b.mul(place(b, b.constF(i), n), pixel.size), rowAt};
            partWays = ways.add(partWays, away, c, s2, some, at);
        }
        std::vector<ValueId> flags;
        ValueId bounded = v[7];
        // The squares r and s, s (da, dc) sides from r: each way round.
        auto pair = [&](const Reading& r, const Reading& s, double da, double dc, ValueId counts) {
            flags.push_back(otherReaches(b, r, s, da, dc, side, h));
            flags.push_back(otherReaches(b, s, r, -da, -dc, side, h));
            const ValueId either = b.emit(Op::Or, {boundedBy(b, r, s, da, dc, side, h),
                                                   boundedBy(b, s, r, -da, -dc, side, h)});
            bounded = b.select(b.emit(Op::And, {counts, either}), b.constF(1.0), bounded);
        };
        for (int i = 0; i + 1 < n; ++i) pair(row[i], row[i + 1], 1, 0, b.constB(true));
        // How many pairs hold another's stroke, each way round counted once.
        auto pairsIn = [&](ValueId count, const std::vector<ValueId>& each) {
            for (size_t k = 0; k + 1 < each.size(); k += 2)
                count = b.add(count, b.select(b.emit(Op::Or, {each[k], each[k + 1]}), b.constF(1.0),
                                              b.constF(0.0)));
            return count;
        };
        ValueId count = pairsIn(v[2], flags);
        flags.clear();
        const std::vector<Reading> previous = carriedRow(v, kRowAt, n);
        const ValueId hasPrevious = b.gt(v[0], b.constF(0.0));
        for (int i = 0; i < n; ++i) pair(previous[i], row[i], 0, 1, hasPrevious);
        // The first row has none below it.
        count = b.select(b.gt(v[0], b.constF(0.0)), pairsIn(count, flags), count);
        std::vector<ValueId> next{
            b.add(v[0], b.constF(1.0)), sum, count, near, cos2, sin2, directed, bounded};
        next.insert(next.end(), partWays.begin(), partWays.end());
        carry(next, row);
        return next;
    });
    const double each = 1.0 / (n * n);
    // The half angle of (c, s) = (cos 2 theta, sin 2 theta): (1 + c, s) and (s, 1 - c) both
    // run along theta, each well away from 0 where the other nears it.
    const ValueId c = out[4], s2 = out[5], r = b.hypot(c, s2);
    const ValueId ahead = b.emit(Op::Ge, {c, b.constF(0.0)});
    const ValueId au = b.select(ahead, b.add(r, c), s2), av = b.select(ahead, s2, b.sub(r, c));
    const ValueId al = b.max(b.hypot(au, av), b.constF(1e-30));
    return {b.mul(out[1], b.constF(each)),
            b.emit(Op::Or, {b.gt(out[2], b.constF(0.0)), b.gt(out[7], b.constF(0.5))}),
            b.mul(out[3], b.constF(each)),
            b.div(out[2], b.constF(2 * n * (n - 1))),
            b.div(r, b.max(out[6], b.constF(1.0))),
            {b.div(au, al), b.div(av, al)},
            out[4],
            out[5],
            out[6],
            std::vector<ValueId>(out.begin() + kWaysAt, out.begin() + kRowAt)};
}

// The index a crowd of parallel members runs by (CrowdEstimate::runs), from the pixel centre's
// reading: its member's spacing L along the normal is how far the next member's foot stands
// from its own, read past the end of the centre's ray (its member's foot to the ridge,
// DistanceTubes.h: rayThrough), the centre stands t0 = d / |grad d| along the normal n from its
// member, so the index
// runs t0 / L there and n / L per world unit across the pixel (members at the integers, the
// nearest at 0), and the stroke is h / (|grad d| L) to either side of each. A centre on a kink
// (on a member, to the last bit: its gradient vanishes, as float meets far more often than
// double) stands on its member, the parts' axis for its normal. Read where `trust` > 0, else 0.
// Returns kRunsRead values: the index, |grad index|, its world components, the stroke's
// half-width across the members in world units, the pixel's mean ink as a phase family's in
// closed form (Prefilter.h, squareMeanInk: exact for straight evenly spaced members), and how
// far that is taken over the parts (kClosedFrom to kClosedFull members a pixel); and 1 where
// the probe past the centre's ray read a member crossing it (RayLength::across), with that
// probe's place.
constexpr size_t kRunsRead = 10;
// The grid's values distanceFamilyCrowd carries out of its branches: its trust, half-width,
// whether it runs three ways, and each of its three ways' index, gradient (length and
// components) and mean.
constexpr size_t kGridValues = 18;
// The screen's values distanceFamilyCrowd carries out of its branches, the dots' or the
// rings': how far it is weighed, its generators with their gradients, and its members' outer
// and inner radii (the inner 0 for dots).
constexpr size_t kScreenValues = 9;
// The gradient (per world unit) of a second or third strand that stands for no lines: a beat with
// it is never the slowest (FineUnion.cpp, strandCorrelation).
constexpr double kNoWay = 1e6;
Vals runsRead(ir::Builder& b, const DistanceAt& at, const Reading& centre, Normal axis,
              ValueId halfWidth, const PixelFootprint& pixel, ValueId trust) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    return b.ifThenElse(
        b.gt(trust, zero),
        [&] {
            const ValueId some = b.gt(centre.length, zero); // false on NaN too
            const Reading r{b.select(some, centre.d, zero), b.select(some, centre.gu, axis.u),
                            b.select(some, centre.gv, axis.v), b.select(some, centre.length, one)};
            const RayLength ray = rayThrough(b, at, pixel, r, {zero, zero},
                                             b.mul(pixel.size, b.constF(kRunsReach)), true);
            // Held above a ten-thousandth of a pixel for the divisions below (a ray's ridge
            // stands past its first probe, never at 0).
            const ValueId spacing = b.max(ray.next, b.mul(pixel.size, b.constF(1e-4)));
            const ValueId length = heldLength(b, r);
            const ValueId per = b.div(one, b.mul(spacing, length)); // 1 / (L |grad d|)
            // The gradient along the pixel's sides in the world's axes.
            const Offset g = worldOf(b, r.gu, r.gv, pixel);
            const ValueId index = b.mul(r.d, per);
            const ValueId half = b.div(halfWidth, length);
            auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
            const ValueId mean =
                squareMeanInk(value(index), value(b.mul(b.abs(b.mul(r.gu, per)), pixel.size)),
                              value(b.mul(b.abs(b.mul(r.gv, per)), pixel.size)),
                              value(b.mul(halfWidth, per)))
                    .id;
            Vals out{index,
                     b.div(one, spacing),
                     b.mul(g.ox, per),
                     b.mul(g.oy, per),
                     half,
                     mean,
                     b.smoothstep(b.constF(kClosedFrom), b.constF(kClosedFull),
                                  b.div(pixel.size, spacing)),
                     b.select(ray.across, one, zero),
                     ray.acrossAt.u,
                     ray.acrossAt.v};
            for (ValueId& v : out) v = b.denan(v, zero);
            return out;
        },
        [&] { return Vals(kRunsRead, zero); });
}

} // namespace

CrowdEstimate distanceFamilyCrowd(ir::Builder& b, ValueId distance, const DistanceAt& at,
                                  ValueId halfWidth, const PixelFootprint& pixel) {
    const Reading centre = readAt(b, distance, pixel);
    // Each corner against the centre's first-order reading: where one reads off it, a member
    // other than the centre's straight one is nearer there, which matters where a stroke
    // other than the centre's may ink the pixel. Every point of the pixel nearer that corner
    // than its centre stands within half a side of the corner, and a distance changes by
    // about its gradient's length a world unit (kGrowth to spare for one that grows across the
    // pixel): where the corner's distance stands further than that past h, no such point is
    // inked. So a ridge between two resolved members whose strokes stop short of it is read
    // as the centre says, and a pixel that holds members closer than it is read in parts.
    const ValueId reach =
        b.add(halfWidth, b.mul(b.constF(0.5 * kGrowth), b.mul(centre.length, pixel.size)));
    std::vector<ValueId> parts;
    for (double a : {-0.5, 0.5})
        for (double c : {-0.5, 0.5}) {
            Offset o = offsetOf(b, b.constF(a), b.constF(c), pixel);
            ValueId there = at(b, o.ox, o.oy);
            // Where the corner reads further than the centre's reading says, and that
            // reading's stroke reaches the corner, the stroke stops short of where the
            // centre's reading puts it (a box's or a Chebyshev dot's corner: the greater of
            // two distances, DistanceFamily.cpp boundedBy).
            const ValueId said = firstOrderAt(b, centre, a, c, pixel.size);
            parts.push_back(b.emit(Op::And, {bends(b, centre, there, said, pixel.size),
                                             b.lt(b.min(there, said), reach)}));
        }
    // Where the centre's gradient vanishes (a kink met to the last bit) there is no reading to
    // trust: the parts.
    parts.push_back(b.emit(Op::Not, {b.gt(centre.length, b.constF(0.0))}));
    const ValueId parted = anyOf(b, parts);
    CrowdEstimate out;
    // [the pixel's mean ink, the trust in the index its members run by, runsRead's values]
    const Vals read = b.ifThenElse(
        parted,
        [&] {
            Parts coarse = partsMean(b, at, halfWidth, pixel, centre, kDistanceTaps);
            // Parts that all read one way may be a grid whose lines alias with the parts'
            // lattice (at zooms where the parts stand nearly a whole number of lines apart):
            // not parallel where a few points off that lattice (crossingSeen), or the probe
            // past the centre's ray, read a member crossing them. Its place is where the
            // grid's second way is read from (gridRead).
            const ValueId oneWay =
                b.smoothstep(b.constF(kRunsFrom), b.constF(kRunsFull), coarse.coherence);
            const Vals looked = b.ifThenElse(
                b.gt(oneWay, b.constF(0.0)),
                [&] {
                    const CrossingStart seen = crossingSeen(b, at, pixel, coarse.cos2, coarse.sin2);
                    return Vals{b.select(seen.found, b.constF(1.0), b.constF(0.0)), seen.at.u,
                                seen.at.v};
                },
                [&] { return Vals(3, b.constF(0.0)); });
            const ValueId seen = b.gt(looked[0], b.constF(0.5));
            const ValueId parallel = b.select(seen, b.constF(0.0), oneWay);
            const Vals runs = runsRead(b, at, centre, coarse.axis, halfWidth, pixel, parallel);
            const ValueId crossedRay = b.gt(runs[7], b.constF(0.5));
            const ValueId trust = b.select(crossedRay, b.constF(0.0), parallel);
            const CrossingStart crossing{
                b.emit(Op::Or, {seen, crossedRay}),
                {b.select(seen, looked[1], runs[8]), b.select(seen, looked[2], runs[9])}};
            // Members closer than the parts: finer parts, behind their own branch; members
            // finer than those, their tubes (DistanceTubes.h), the fine parts handing over to
            // them as the samples' rays shorten; and where they run parallel (`trust`), the
            // closed form of the index they run by, handed over to from 2 to 3 members a
            // pixel (kClosedFrom). The tubes are read only where the coarse parts' members
            // stand near enough, and cross enough of them, that the hand-over may begin
            // (kTubeGate, kCrossedGate), and the closed form wherever the index is trusted.
            auto fine = [&] {
                return Vals{finePartsMean(b, at, halfWidth, pixel, centre, kDistanceFineTaps)};
            };
            const ValueId fineSide = b.div(pixel.size, b.constF(kDistanceFineTaps));
            const ValueId crossed =
                b.emit(Op::Or, {b.emit(Op::Ge, {coarse.crossed, b.constF(kCrossedGate)}),
                                b.lt(coarse.near, b.mul(fineSide, b.constF(kParallelGate)))});
            const ValueId near = b.lt(coarse.near, b.mul(fineSide, b.constF(kTubeGate)));
            const ValueId mayCrowd = b.emit(Op::And, {near, crossed});
            // Where the members are dots on a lattice (DistanceDots.h), read where the index
            // the members run by is not wholly trusted and they may crowd: a dot screen's mean
            // in closed form. Read before a grid's: a square dot's faces run two ways, as a
            // grid's lines do, but a grid is no screen of dots (along its lines its distance
            // does not grow).
            const ValueId one = b.constF(1.0);
            const ScreenRead dots = dotsRead(b, at, pixel, halfWidth, centre,
                                             b.emit(Op::And, {b.lt(trust, one), near}));
            // Where the members run two ways (a grid's lines) rather than one, each way's
            // index and the pair's mean in closed form (DistanceGrid.h), read where neither
            // the index the members run by nor the dots are wholly trusted. The closed forms
            // are trusted `closedTrust` over the tubes, each weighed by the trust the ones
            // before it leave, and taken over the parts by `closedCrowded`.
            const ValueId dotsWeight = b.mul(b.sub(one, trust), dots.trust);
            const ValueId pointsTrust = b.add(trust, dotsWeight);
            const GridRead grid =
                gridRead(b, at, pixel, halfWidth, coarse.ways, coarse.cos2, coarse.sin2,
                         coarse.directed, b.lt(pointsTrust, one), crossing);
            const ValueId gridWeight = b.mul(b.sub(one, pointsTrust), grid.trust);
            // Where the members are rings about a lattice's points (DistanceRings.h), read
            // where none of those is wholly trusted (read before the grid, they cost a grid's
            // pixels a fifth more): two dot screens' difference in closed form, by which the
            // union lays them on other layers too (LatticeShape::inner).
            const ValueId othersTrust = b.add(pointsTrust, gridWeight);
            const ScreenRead rings = ringsRead(b, at, pixel, halfWidth, centre,
                                               b.emit(Op::And, {b.lt(othersTrust, one), near}));
            const ValueId ringsWeight = b.mul(b.sub(one, othersTrust), rings.trust);
            const ValueId closedTrust = b.add(othersTrust, ringsWeight);
            auto closedHandOver = [&](ValueId members) {
                return b.smoothstep(b.constF(kClosedFrom), b.constF(kClosedFull), members);
            };
            auto dotsHandOver = [&](ValueId members) {
                return b.smoothstep(b.constF(kDotsClosedFrom), b.constF(kDotsClosedFull), members);
            };
            auto weighed = [&](ValueId runsValue, ValueId gridValue, ValueId dotsValue,
                               ValueId ringsValue) {
                const ValueId sum =
                    b.add(b.add(b.mul(trust, runsValue), b.mul(gridWeight, gridValue)),
                          b.add(b.mul(dotsWeight, dotsValue), b.mul(ringsWeight, ringsValue)));
                return b.select(b.gt(closedTrust, b.constF(0.0)), b.div(sum, closedTrust),
                                b.constF(0.0));
            };
            const ValueId closedMean = weighed(runs[5], grid.mean, dots.mean, rings.mean);
            const ValueId closedCrowded =
                weighed(runs[6], closedHandOver(grid.members), dotsHandOver(dots.members),
                        dotsHandOver(rings.members));
            // A crowd's mean and how far it is taken over the fine parts (`crowded`): by the
            // tubes and the closed forms where the members may crowd, by the closed forms
            // alone where they stand apart, and where the coarse parts read no member bending,
            // their mean with the dots' and the rings' closed forms, taken whole.
            auto crowd = [&] {
                const Vals tubes = b.ifThenElse(
                    b.lt(closedTrust, b.constF(1.0)),
                    [&] {
                        const TubeEstimate t = distanceTubesMean(b, at, halfWidth, pixel);
                        return Vals{t.mean, t.crowded};
                    },
                    [&] {
                        return Vals{b.constF(0.0), b.constF(0.0)};
                    });
                return Vals{b.mix(tubes[0], closedMean, closedTrust),
                            b.mix(tubes[1], closedCrowded, closedTrust)};
            };
            auto apart = [&] { return Vals{closedMean, b.mul(closedTrust, closedCrowded)}; };
            const Vals taken = b.ifThenElse(
                coarse.bent, [&] { return b.ifThenElse(mayCrowd, crowd, apart); },
                [&] {
                    const ValueId withDots = b.mix(coarse.mean, dots.mean,
                                                   b.mul(dotsWeight, dotsHandOver(dots.members)));
                    return Vals{b.mix(withDots, rings.mean,
                                      b.mul(ringsWeight, dotsHandOver(rings.members))),
                                b.constF(1.0)};
                });
            // The fine parts handing over to the crowd's mean by `crowded`, behind one branch
            // for both ways a crowd is read (written in each, the kernel held them twice).
            // Where the coarse parts stand, crowded is 1 and the mix their mean.
            const ValueId mean = taken[0], crowded = taken[1];
            const ValueId parts =
                b.ifThenElse(b.lt(crowded, b.constF(1.0)), fine, [&] { return Vals{mean}; })[0];
            Vals out{b.mix(parts, mean, crowded)};
            out.push_back(trust);
            out.insert(out.end(), runs.begin(), runs.end());
            out.insert(out.end(), {grid.trust, grid.halfWidth, grid.threeWays});
            for (const GridRead::Way& w : grid.ways)
                out.insert(out.end(), {w.index, w.grad, w.gradX, w.gradY, w.mean});
            // The screen the union of fine layers reads: the rings' where they are weighed
            // over the dots (the two weights sum to 1 at most, so one of them at most passes
            // a half, where the union takes the screen).
            const ValueId ringsScreen = b.gt(ringsWeight, dotsWeight);
            auto pick = [&](ValueId ring, ValueId dot) { return b.select(ringsScreen, ring, dot); };
            out.insert(out.end(),
                       {b.max(dotsWeight, ringsWeight), pick(rings.u, dots.u),
                        pick(rings.ux, dots.ux), pick(rings.uy, dots.uy), pick(rings.v, dots.v),
                        pick(rings.vx, dots.vx), pick(rings.vy, dots.vy),
                        pick(rings.radius, dots.radius), pick(rings.inner, dots.inner)});
            return out;
        },
        // Not parted, the centre's gradient does not vanish: it stands for itself.
        [&] {
            Vals out(2 + kRunsRead + kGridValues + kScreenValues, b.constF(0.0));
            out[0] = firstOrderMean(b, centre, halfWidth, pixel.size, centre);
            return out;
        });
    out.nearest = read[0];
    const ValueId trust = read[1];
    // Where the grid's two or three ways are trusted over the parallel members' one, its first
    // way's index stands for the layer's, and its second and third are the layer's second and
    // third strands.
    const size_t g = 2 + kRunsRead;
    const ValueId twoWays = read[g];
    const ValueId grid = b.gt(twoWays, trust);
    const ValueId three = b.emit(Op::And, {grid, b.gt(read[g + 2], b.constF(0.5))});
    auto way = [&](size_t w, size_t k) { return read[g + 3 + 5 * w + k]; };
    CrowdEstimate::Runs runs;
    runs.footprint.index = b.select(grid, way(0, 0), read[2]);
    runs.footprint.grad = b.select(grid, way(0, 1), read[3]);
    runs.footprint.gradX = b.select(grid, way(0, 2), read[4]);
    runs.footprint.gradY = b.select(grid, way(0, 3), read[5]);
    runs.footprint.trust = b.max(trust, twoWays);
    runs.halfWidth = b.select(grid, read[g + 1], read[6]);
    const ValueId steep = b.constF(kNoWay);
    runs.second.index = way(1, 0);
    runs.second.grad = b.select(grid, way(1, 1), steep);
    runs.second.gradX = b.select(grid, way(1, 2), steep);
    runs.second.gradY = b.select(grid, way(1, 3), steep);
    runs.second.trust = b.select(grid, twoWays, b.constF(0.0));
    runs.third.index = way(2, 0);
    runs.third.grad = b.select(three, way(2, 1), steep);
    runs.third.gradX = b.select(three, way(2, 2), steep);
    runs.third.gradY = b.select(three, way(2, 3), steep);
    runs.third.trust = b.select(three, twoWays, b.constF(0.0));
    runs.twoWays = b.select(grid, twoWays, b.constF(0.0));
    runs.means = {way(0, 4), way(1, 4), way(2, 4)};
    // Where the members are read as a screen of dots or rings, that screen's shape, one member
    // at each whole (u, v): its shortest rows are among (1, 0), (0, 1) and the two diagonals
    // (the basis is reduced), and the union matches another layer's rows with the nearest.
    const size_t d = g + kGridValues;
    CrowdEstimate::LatticeShape screen;
    screen.u = read[d + 1], screen.ux = read[d + 2], screen.uy = read[d + 3];
    screen.v = read[d + 4], screen.vx = read[d + 5], screen.vy = read[d + 6];
    screen.sites = {{{0.0, 0.0}}};
    screen.shortest = {{{1, 0}}, {{0, 1}}, {{1, 1}}, {{1, -1}}};
    screen.radius = read[d + 7];
    screen.inner = read[d + 8];
    screen.dots = b.gt(read[d], b.constF(0.5));
    runs.screen = screen;
    out.runs = runs;
    // Read in parts, the nearest member's stroke is not the layer's strokes where the members
    // crowd or cross, and stroke pairs take the layer as independent there. Where they run
    // parallel and stand apart it still is, as a phase family's nearest is: handed over to the
    // union of fine layers as they crowd (kCrowdFrom to kCrowdFull members a pixel), as a
    // phase family's is (StrokePairs.cpp).
    const ValueId members = b.mul(out.runs->footprint.grad, pixel.size);
    const ValueId alone =
        b.mul(trust, b.sub(b.constF(1.0),
                           b.smoothstep(b.constF(kCrowdFrom), b.constF(kCrowdFull), members)));
    out.strokesCrowded = b.select(parted, b.sub(b.constF(1.0), alone), b.constF(0.0));
    return out;
}

} // namespace moire::lower
