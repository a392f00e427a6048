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

// Probes a ray spends finding the dot across its cell's edge: from a sixteenth of a pixel
// out it doubles until it leaves the cell (three doublings reach half a pixel, past the cell
// of dots two a pixel), then each probe past a bisector halves the number of cells it stood
// past, about.
constexpr int kRayProbes = 10;
// A probe stands this share past the bisector it steps back to: well past float's rounding of
// the world's coordinates (with the frame's centre 600 units out and dots 0.05 apart, a
// thousandth of the bisector fell within it, and 6% of the rays read c0's own dot there).
// Where one still reads c0's own dot, the next stands kOnwards further out.
constexpr double kPastBisector = 0.02, kOnwards = 1.1;
// A ray settles where a probe reads the dot the last one read (its foot within kSameDot of
// the vector to it), or where it stands within kNearBisector of the bisector of the dot it
// reads: a ray through a corner of c0's cell (where three cells meet) reads either of two dots
// as far, and both are c0's neighbours.
constexpr double kSameDot = 0.25, kNearBisector = 0.05;
// The second ray's turn from the first dot's direction: square to it, it would run through a
// corner of a triangular lattice's hexagonal cell, and a square lattice's where the first ray
// read a diagonal neighbour.
constexpr double kSecondTurn = 75.0;
// A probe reads c0's own dot while its foot stands within this share of its step.
constexpr double kSameFoot = 0.5;
// The dots' shape: kShapeLooks points a radius r from c0, a thirteenth of a turn apart, read
// the distance's gauge there, N(theta) = d / r (a dot's distance grows linearly along every
// ray from its centre: a disc's, a square's Chebyshev max(|dx|, |dy|), a diamond's, an
// ellipse's), and the stroke's edge stands h / N(theta) out, so the dot's area is the mean of
// (h / N)^2 / 2 over the turn: within 0.5% for a square, a hexagon or a diamond at any turn over
// thirteen looks (1% to 2.6% over nine; exact for a disc). kGaugeLooks of them again at r / 2
// must read half as far, within kGaugeFrom to be trusted and not at all past kGaugeFull: a
// distance that does not grow so about c0 (a ring about the point, whose c0 is on the ring)
// is not a screen of dots.
constexpr int kShapeLooks = 13, kGaugeLooks = 3;
constexpr double kGaugeFrom = 0.02, kGaugeFull = 0.04;
// A point of a finer lattice at a half-step of the cell: the dot read there within this share
// of the shorter step. A dot read elsewhere must stand on the lattice's points within
// kOnLattice of a step.
constexpr double kFinerWithin = 0.25, kOnLattice = 0.1;
// The basis's two vectors must stand at more than about 6 degrees (their cross product over
// their lengths' product).
constexpr double kLeastSine = 0.1;
// The dots' strokes apart: the dot's furthest edge under this share of half the nearest dots'
// distance.
constexpr double kApart = 0.95;
// Lagrange's reduction steps: the basis read is two relevant vectors, one step from reduced.
constexpr int kReduceSteps = 3;

struct Vec {
    ValueId u, v;
};
ValueId dot(ir::Builder& b, Vec a, Vec c) {
    return b.add(b.mul(a.u, c.u), b.mul(a.v, c.v));
}
ValueId cross(ir::Builder& b, Vec a, Vec c) {
    return b.sub(b.mul(a.u, c.v), b.mul(a.v, c.u));
}
Vec plus(ir::Builder& b, Vec a, Vec c) {
    return {b.add(a.u, c.u), b.add(a.v, c.v)};
}
Vec scaled(ir::Builder& b, Vec a, ValueId k) {
    return {b.mul(a.u, k), b.mul(a.v, k)};
}
Vec chosen(ir::Builder& b, ValueId c, Vec a, Vec other) {
    return {b.select(c, a.u, other.u), b.select(c, a.v, other.v)};
}

// The centre of the dot nearest p, read there as r: the foot of p's reading, and the foot of
// the reading at that foot. A disc's foot is its centre; a square's (a Chebyshev distance) is
// on one of its centre lines, whose own foot is the centre. Where the second reading has no
// gradient (the foot on the centre to the last bit), the first foot.
PixelPoint dotCentre(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     const Reading& r, PixelPoint p) {
    const PixelPoint f = footFrom(b, r, p, false);
    const PixelPoint g = footFrom(b, readThere(b, at, pixel, f), f, false);
    return {b.denan(g.u, f.u), b.denan(g.v, f.v)};
}

// The dot across c0's cell's edge along the unit direction a: `found` where the ray settled
// (a probe just past the bisector of c0 and the dot it read read that dot again), and the
// vector from c0 to that dot. `start`: the first probe's distance from c0.
struct Across {
    ValueId found;
    Vec w;
};
Across acrossAlong(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                   const CentreOf& centreOf, PixelPoint c0, Vec a, ValueId start) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    // Carried: the probe, its distance, the vector read (and whether one was), and settled:
    // where a probe reads the dot the last one read, it stepped back to just past that dot's
    // bisector with c0.
    Vals init{zero, start, zero, zero, zero, zero};
    auto more = [&](std::span<const ValueId> v) {
        return Vals{b.emit(Op::And, {b.lt(v[0], b.constF(kRayProbes)), b.lt(v[5], b.constF(0.5))})};
    };
    const Vals out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const ValueId s = v[1];
        const PixelPoint q{b.add(c0.u, b.mul(s, a.u)), b.add(c0.v, b.mul(s, a.v))};
        const Reading r = readThere(b, at, pixel, q);
        const PixelPoint f = centreOf(b, r, q); // NaN on a kink: read again further
        const Vec w{b.sub(f.u, c0.u), b.sub(f.v, c0.v)};
        const ValueId length = b.hypot(w.u, w.v);
        const ValueId ahead = dot(b, w, a);
        const ValueId other = b.emit(
            Op::And, {b.emit(Op::Ge, {length, b.mul(s, b.constF(kSameFoot))}), b.gt(ahead, zero)});
        // The bisector of c0 and the dot read, along the ray: the probe stands past it.
        const ValueId bisector = b.div(b.mul(length, length), b.mul(ahead, b.constF(2.0)));
        const ValueId back = b.mul(bisector, b.constF(1.0 + kPastBisector));
        const ValueId again =
            b.lt(b.hypot(b.sub(w.u, v[3]), b.sub(w.v, v[4])), b.mul(length, b.constF(kSameDot)));
        const ValueId nearBisector = b.le(s, b.mul(bisector, b.constF(1.0 + kNearBisector)));
        const ValueId settled = b.emit(
            Op::And, {other, b.emit(Op::Or, {b.emit(Op::And, {b.gt(v[2], b.constF(0.5)), again}),
                                             nearBisector})});
        const ValueId valid = b.emit(Op::Eq, {length, length});
        const ValueId stepped =
            b.emit(Op::And, {valid, b.emit(Op::Not, {b.gt(v[2], b.constF(0.5))})});
        const ValueId further = b.mul(s, b.select(stepped, b.constF(2.0), b.constF(kOnwards)));
        return Vals{b.add(v[0], one),           b.select(other, back, further),
                    b.select(other, one, v[2]), b.select(other, w.u, v[3]),
                    b.select(other, w.v, v[4]), b.select(settled, one, zero)};
    });
    return {b.gt(out[5], b.constF(0.5)), {out[3], out[4]}};
}

// Lagrange's reduction of the basis (p, q): the shorter first, the second less the whole
// multiple of the first nearest its projection.
void reduce(ir::Builder& b, Vec& p, Vec& q) {
    for (int i = 0; i < kReduceSteps; ++i) {
        const ValueId swap = b.lt(dot(b, q, q), dot(b, p, p));
        const Vec first = chosen(b, swap, q, p), second = chosen(b, swap, p, q);
        const ValueId k =
            b.round(b.div(dot(b, first, second), b.max(dot(b, first, first), b.constF(1e-30))));
        p = first;
        q = plus(b, second, scaled(b, first, b.neg(k)));
    }
}

// The dot about c0 (its distance's gradient `length` a distance unit, the stroke's half-width
// `halfWidth`): its gauge in kShapeLooks directions turned from n, a radius r out, and
// kGaugeLooks of them again at r / 2. Its area is the mean of (h / N)^2 / 2 over the turn.
struct DotShape {
    // The radius of the disc of the dot's area, which the closed form's ripple and the union
    // take for the dot's shape (exact for a round dot; for another, its share is exact and its
    // harmonics a disc's); its furthest edge from c0; and how far its distance grows linearly
    // from c0 (1 trusted, 0 not: a ring about the point, a grid's or a ring's line).
    ValueId equal, furthest, gauged;
};
DotShape dotShape(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel, PixelPoint c0,
                  Normal n, ValueId length, ValueId halfWidth) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0), half = b.constF(0.5);
    const ValueId radius = b.div(halfWidth, length);
    // A loop over the looks, the family's expression written out once for the look and
    // once for the nearer one (behind a branch), not once a look.
    const ValueId every = b.constF(double(kShapeLooks / kGaugeLooks));
    const Vals shape = b.loop(
        {zero, zero, zero, zero},
        [&](std::span<const ValueId> v) { return Vals{b.lt(v[0], b.constF(kShapeLooks))}; },
        [&](std::span<const ValueId> v) {
            const ValueId angle =
                b.mul(b.add(v[0], b.constF(0.25)), b.constF(2.0 * std::numbers::pi / kShapeLooks));
            const ValueId cu = b.cos(angle), cv = b.sin(angle);
            const Vec e{b.sub(b.mul(n.u, cu), b.mul(n.v, cv)),
                        b.add(b.mul(n.u, cv), b.mul(n.v, cu))};
            auto distanceAt = [&](ValueId out) {
                return readThere(b, at, pixel,
                                 {b.add(c0.u, b.mul(out, e.u)), b.add(c0.v, b.mul(out, e.v))})
                    .d;
            };
            const ValueId d = distanceAt(radius);
            const ValueId edge = b.div(b.mul(halfWidth, radius), b.max(d, b.constF(1e-30)));
            // Every (kShapeLooks / kGaugeLooks)-th look, kGaugeLooks of them.
            const ValueId slot = b.div(v[0], every);
            const ValueId nearer =
                b.emit(Op::And, {b.lt(b.abs(b.sub(slot, b.round(slot))), b.constF(0.01)),
                                 b.lt(slot, b.constF(kGaugeLooks - 0.5))});
            const ValueId off = b.ifThenElse(
                nearer,
                [&] {
                    const ValueId inner = distanceAt(b.mul(radius, half));
                    return Vals{b.div(b.abs(b.sub(b.mul(inner, b.constF(2.0)), d)),
                                      b.max(d, b.constF(1e-30)))};
                },
                [&] { return Vals{zero}; })[0];
            return Vals{b.add(v[0], one), b.add(v[1], b.mul(edge, edge)), b.max(v[2], edge),
                        b.max(v[3], b.denan(off, one))};
        });
    ValueId dotArea = shape[1];
    const ValueId furthest = shape[2], gaugeOff = shape[3];
    dotArea = b.mul(dotArea, b.constF(std::numbers::pi / kShapeLooks));
    const ValueId equal = b.sqrt(b.div(dotArea, b.constF(std::numbers::pi)));
    const ValueId gauged = b.sub(
        one, b.smoothstep(b.constF(kGaugeFrom), b.constF(kGaugeFull), b.denan(gaugeOff, one)));
    return {equal, furthest, gauged};
}

} // namespace

DotLattice dotLattice(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                      const CentreOf& centreOf, PixelPoint c0, Normal n, ValueId start,
                      ValueId furthest) {
    const ValueId half = b.constF(0.5);
    const Across first = acrossAlong(b, at, pixel, centreOf, c0, {n.u, n.v}, start);
    const ValueId firstLength = b.max(b.hypot(first.w.u, first.w.v), b.constF(1e-30));
    const double turn = kSecondTurn * std::numbers::pi / 180.0;
    const ValueId tc = b.constF(std::cos(turn)), ts = b.constF(std::sin(turn));
    const Vec turned{b.div(b.sub(b.mul(first.w.u, tc), b.mul(first.w.v, ts)), firstLength),
                     b.div(b.add(b.mul(first.w.u, ts), b.mul(first.w.v, tc)), firstLength)};
    const Across second = acrossAlong(b, at, pixel, centreOf, c0, turned, start);
    Vec p = first.w, q = second.w;
    reduce(b, p, q);
    // The three half-steps of the cell: the dot read there is a corner of the cell,
    // or, where the lattice is twice as fine, a point at the half-step itself,
    // which the basis takes in place of the vector it halves. A dot read anywhere
    // else is off the lattice.
    const Vec diagonal = plus(b, p, q);
    const Vec halves[3] = {scaled(b, p, half), scaled(b, q, half), scaled(b, diagonal, half)};
    const ValueId det0 = cross(b, p, q);
    const ValueId step = b.hypot(p.u, p.v);
    ValueId lattice = b.constB(true);
    ValueId finer[3];
    for (int k = 0; k < 3; ++k) {
        const PixelPoint at_{b.add(c0.u, halves[k].u), b.add(c0.v, halves[k].v)};
        const PixelPoint dot_ = centreOf(b, readThere(b, at, pixel, at_), at_);
        const Vec fromHalf{b.sub(dot_.u, at_.u), b.sub(dot_.v, at_.v)};
        finer[k] = b.lt(b.hypot(fromHalf.u, fromHalf.v), b.mul(step, b.constF(kFinerWithin)));
        // The dot's place in the basis's coordinates, whole on the lattice.
        const Vec fromC0{b.sub(dot_.u, c0.u), b.sub(dot_.v, c0.v)};
        const ValueId cu = b.div(cross(b, fromC0, q), det0);
        const ValueId cv = b.div(cross(b, p, fromC0), det0);
        const ValueId whole =
            b.emit(Op::And, {b.lt(b.abs(b.sub(cu, b.round(cu))), b.constF(kOnLattice)),
                             b.lt(b.abs(b.sub(cv, b.round(cv))), b.constF(kOnLattice))});
        lattice = b.emit(Op::And, {lattice, b.emit(Op::Or, {whole, finer[k]})});
    }
    // A finer lattice: its point halves p, q, or the diagonal (in q's place).
    const Vec halfQ = chosen(b, finer[1], halves[1], halves[2]);
    const ValueId halvesQ = b.emit(Op::Or, {finer[1], finer[2]});
    p = chosen(b, finer[0], halves[0], p);
    q = chosen(b, b.emit(Op::And, {b.emit(Op::Not, {finer[0]}), halvesQ}), halfQ, q);
    reduce(b, p, q);
    const ValueId area = b.abs(cross(b, p, q));
    const ValueId shortest = b.hypot(p.u, p.v);
    const ValueId sine = b.div(area, b.max(b.mul(shortest, b.hypot(q.u, q.v)), b.constF(1e-30)));
    ValueId ok = b.emit(Op::And, {first.found, second.found});
    ok = b.emit(Op::And, {ok, lattice});
    ok = b.emit(Op::And, {ok, b.gt(sine, b.constF(kLeastSine))});
    ok = b.emit(Op::And, {ok, b.lt(furthest, b.mul(shortest, b.constF(0.5 * kApart)))});
    return {{p.u, p.v}, {q.u, q.v}, area, ok};
}

ScreenOf screenOf(ir::Builder& b, const PixelFootprint& pixel, PixelPoint c0,
                  const DotLattice& lattice) {
    const Vec p{lattice.p.u, lattice.p.v}, q{lattice.q.u, lattice.q.v};
    // c0 + u p + v q is the point (u, v); at the pixel's centre, (u, v) solves u p + v q = -c0,
    // and their gradients along the pixel's sides are the rows of [p q]^-1, turned to the
    // world's axes.
    const ValueId det = cross(b, p, q);
    const Vec back{b.neg(c0.u), b.neg(c0.v)};
    const Offset gu = worldOf(b, b.div(q.v, det), b.div(b.neg(q.u), det), pixel);
    const Offset gv = worldOf(b, b.div(b.neg(p.v), det), b.div(p.u, det), pixel);
    LatticeCrowdInputs in;
    in.genU = b.div(cross(b, back, q), det), in.genUX = gu.ox, in.genUY = gu.oy;
    in.genV = b.div(cross(b, p, back), det), in.genVX = gv.ox, in.genVY = gv.oy;
    in.pixel = pixel.size, in.cosTurn = pixel.cosTurn, in.sinTurn = pixel.sinTurn;
    return {in, b.div(pixel.size, b.sqrt(b.max(lattice.area, b.constF(1e-30))))};
}

std::vector<ValueId> screenReadValues(ir::Builder& b, ValueId trust, ValueId mean,
                                      const ScreenOf& screen, ValueId radius, ValueId inner) {
    Vals out{trust, mean, screen.members};
    const Vals generators = screen.generators();
    out.insert(out.end(), generators.begin(), generators.end());
    out.insert(out.end(), {radius, inner});
    for (ValueId& x : out) x = b.denan(x, b.constF(0.0));
    return out;
}

ScreenRead screenReadOf(std::span<const ValueId> v) {
    return {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10]};
}

Reading besideCentre(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel) {
    return readThere(b, at, pixel, {b.div(pixel.size, b.constF(64.0)), b.constF(0.0)});
}

ScreenRead dotsRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                    ValueId halfWidth, const Reading& centre, ValueId wanted) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    const Vals read = b.ifThenElse(
        wanted,
        [&] {
            // A centre on its dot's centre, to the last bit, has no gradient: it is c0, and
            // its first ray runs along the pixel's first side.
            const ValueId some = b.gt(centre.length, zero); // false on NaN too
            const Normal unit = unitNormal(b, centre);
            const Normal n{b.select(some, unit.u, one), b.select(some, unit.v, zero)};
            const ValueId t0 = b.select(some, b.div(centre.d, heldLength(b, centre)), zero);
            const PixelPoint origin{zero, zero};
            const CentreOf centreOf = [&](ir::Builder& bb, const Reading& r, PixelPoint p) {
                return dotCentre(bb, at, pixel, r, p);
            };
            const PixelPoint read0 = centreOf(b, centre, origin);
            const PixelPoint c0{b.select(some, read0.u, zero), b.select(some, read0.v, zero)};
            // The distance's gradient length: the centre's, else (a centre on its dot's centre)
            // a reading beside it.
            const Reading beside = besideCentre(b, at, pixel);
            const ValueId length =
                b.max(b.select(some, centre.length, beside.length), b.constF(1e-30));
            const DotShape shape = dotShape(b, at, pixel, c0, n, length, halfWidth);
            const ValueId equal = shape.equal, furthest = shape.furthest, gauged = shape.gauged;
            // The rays and the lattice's checks only where the shape is a dot's, and crowded:
            // its furthest edge under a quarter of the pixel (dots two a pixel stand half a
            // pixel apart). A grid's or a ring's c0 is on a line, whose distance does not grow
            // along it: its edge there is far off.
            const ValueId shaped =
                b.emit(Op::And, {b.gt(gauged, zero),
                                 b.lt(furthest, b.mul(pixel.size, b.constF(kScreenMostEdge)))});
            return b.ifThenElse(
                shaped,
                [&] {
                    const ValueId start =
                        b.max(b.mul(b.abs(t0), b.constF(1.5)), b.div(pixel.size, b.constF(16.0)));
                    const DotLattice lattice =
                        dotLattice(b, at, pixel, centreOf, c0, n, start, furthest);
                    const ScreenOf screen = screenOf(b, pixel, c0, lattice);
                    const ValueId trust = b.select(lattice.ok, gauged, zero);
                    const ValueId mean = dotScreenMean(b, screen.in, equal);
                    return screenReadValues(b, trust, mean, screen, equal, zero);
                },
                [&] { return Vals(kScreenReadValues, zero); });
        },
        [&] { return Vals(kScreenReadValues, zero); });
    return screenReadOf(read);
}

} // namespace moire::lower
