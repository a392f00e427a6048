#include "compiler/lower/LatticeUnion.h"

#include "compiler/lower/HoneycombInPixel.h"
#include "compiler/lower/LatticeCrowd.h"

#include <functional>
#include <map>
#include <numbers>
#include <span>
#include <utility>

namespace moire::lower {

using ir::ValueId;

namespace {

// A screen's row of dots as a phase with its gradient, sign (m u + n v) for a short row vector
// (m, n), and the phase each of its sites stands at past the whole numbers, sign (m s_u +
// n s_v).
struct Row {
    ValueId phase, gx, gy;
    std::vector<ValueId> shifts;
};

// Both senses of each of a screen's shortest row vectors.
std::vector<Row> screenRows(ir::Builder& b, const CrowdEstimate::LatticeShape& p) {
    std::vector<Row> rows;
    for (const auto& [m, n] : p.shortest)
        for (double sign : {1.0, -1.0}) {
            auto combine = [&](ValueId u, ValueId v) {
                return b.mul(b.constF(sign), b.add(b.mul(b.constF(m), u), b.mul(b.constF(n), v)));
            };
            Row r{combine(p.u, p.v), combine(p.ux, p.vx), combine(p.uy, p.vy), {}};
            for (const auto& site : p.sites)
                r.shifts.push_back(b.constF(sign * (m * site[0] + n * site[1])));
            rows.push_back(r);
        }
    return rows;
}

// The row whose gradient is nearest (gx, gy), carried through selects.
Row nearestRow(ir::Builder& b, const std::vector<Row>& rows, ValueId gx, ValueId gy) {
    ValueId best = b.constF(1e30);
    Row out = rows.front();
    for (const Row& r : rows) {
        ValueId dx = b.sub(gx, r.gx), dy = b.sub(gy, r.gy);
        ValueId apart = b.add(b.mul(dx, dx), b.mul(dy, dy));
        ValueId nearer = b.lt(apart, best);
        best = b.select(nearer, apart, best);
        out.phase = b.select(nearer, r.phase, out.phase);
        out.gx = b.select(nearer, r.gx, out.gx);
        out.gy = b.select(nearer, r.gy, out.gy);
        for (size_t k = 0; k < out.shifts.size(); ++k)
            out.shifts[k] = b.select(nearer, r.shifts[k], out.shifts[k]);
    }
    return out;
}

// A screen's member as discs about its point: a dot is its disc; a ring (LatticeShape::inner)
// is the disc within its outer edge less the disc within its inner one. Every closed form of a
// screen below (its share, its harmonics, the overlap of its members with another layer's) is
// linear in the member, so a ring's is the outer disc's less the inner one's: the sum over the
// discs of f(radius), the inner one's taken away, behind a branch on its radius, so that dots
// given by their distance (whose screen may be a ring's, its inner radius 0 for dots) pay
// nothing for it.
ValueId overDiscs(ir::Builder& b, const CrowdEstimate::LatticeShape& p,
                  const std::function<ValueId(ValueId)>& f) {
    const ValueId outer = f(p.radius);
    if (p.inner == ir::kNoValue) return outer;
    const ValueId zero = b.constF(0.0);
    return b.ifThenElse(
        b.gt(p.inner, zero), [&] { return std::vector<ValueId>{b.sub(outer, f(p.inner))}; },
        [&] { return std::vector<ValueId>{outer}; })[0];
}

// A lattice's generators' steps in the world, the columns of the inverse of their gradients
// (det their determinant): (u, v) advanced by (1, 0) and by (0, 1).
struct WorldSteps {
    ValueId e1x, e1y, e2x, e2y;
};
WorldSteps worldSteps(ir::Builder& b, const CrowdEstimate::LatticeShape& p, ValueId det) {
    return {b.div(p.vy, det), b.div(b.neg(p.vx), det), b.div(b.neg(p.uy), det), b.div(p.ux, det)};
}

// A screen's cells a world area: |det(grad u, grad v)|.
ValueId cellsPerArea(ir::Builder& b, const CrowdEstimate::LatticeShape& p) {
    return b.abs(b.sub(b.mul(p.ux, p.vy), b.mul(p.uy, p.vx)));
}

// A screen's share of the plane, its sites' dots over its cell.
ValueId screenShare(ir::Builder& b, const CrowdEstimate::LatticeShape& p) {
    const ValueId area = overDiscs(b, p, [&](ValueId r) { return b.mul(r, r); });
    const ValueId disc = b.mul(b.constF(std::numbers::pi * double(p.sites.size())), area);
    return b.min(b.mul(disc, cellsPerArea(b, p)), b.constF(1.0));
}

// A dot screen's harmonics of the first order, m = (m1, m2) with |m1|, |m2| <= 1 and m != 0, as
// the box filter's ripple takes them (LatticeCrowd.cpp, dotRipple): the amplitude F_m (each
// dot's transform times the cells a world area holds and the sum of the sites' phases, here a
// constant: real for every kind's sites), the world frequency k_m = m1 grad u + m2 grad v, and
// the phase m . (u, v) at the pixel's centre, in cycles.
struct ScreenHarmonic {
    ValueId amplitude, kx, ky, phase;
};
std::vector<ScreenHarmonic> firstHarmonics(ir::Builder& b, const CrowdEstimate::LatticeShape& p) {
    auto c = [&](double v) { return b.constF(v); };
    const ValueId cells = cellsPerArea(b, p);
    std::vector<ScreenHarmonic> out;
    for (int m1 = -1; m1 <= 1; ++m1)
        for (int m2 = -1; m2 <= 1; ++m2) {
            if (m1 == 0 && m2 == 0) continue;
            double sites = 0.0;
            for (const auto& a : p.sites)
                sites += std::cos(2.0 * std::numbers::pi * (m1 * a[0] + m2 * a[1]));
            ScreenHarmonic h;
            h.kx = b.add(b.mul(c(m1), p.ux), b.mul(c(m2), p.vx));
            h.ky = b.add(b.mul(c(m1), p.uy), b.mul(c(m2), p.vy));
            const ValueId member =
                overDiscs(b, p, [&](ValueId r) { return dotHarmonic(b, cells, r, h.kx, h.ky); });
            h.amplitude = b.mul(member, c(sites));
            h.phase = b.add(b.mul(c(m1), p.u), b.mul(c(m2), p.v));
            out.push_back(h);
        }
    return out;
}

// Two dot screens' first harmonics beating, of whatever kinds: the pixel's mean of the product
// of f1 = sum F_m e^(2 pi i m . q1) and f2 = sum G_n e^(2 pi i n . q2), less the product of
// the two screens' own pixel means (each its share and its ripple), is to the first order
//   sum over m, n != 0 of F_m G_n (T(k_m + k_n) - T(k_m) T(k_n)) cos(2 pi (m . q1 + n . q2)),
// T the square pixel's transfer (boxTransfer). A pair whose harmonics nearly cancel,
// k_m + k_n small, passes the pixel whole: the beat of a square screen with a triangle one whose
// rows stand as far apart, which the screens' matched rows do not read.
ValueId harmonicCovariance(ir::Builder& b, const CrowdEstimate::LatticeShape& p1,
                           const CrowdEstimate::LatticeShape& p2, const PixelFootprint& pixel) {
    auto c = [&](double v) { return b.constF(v); };
    const std::vector<ScreenHarmonic> h1 = firstHarmonics(b, p1), h2 = firstHarmonics(b, p2);
    // Each harmonic's fields, and its own transfer, as lists the pairs' loop picks from.
    struct Fields {
        std::vector<ValueId> kx, ky, phase, amplitude, transfer;
    };
    auto fieldsOf = [&](const std::vector<ScreenHarmonic>& hs) {
        Fields f;
        for (const ScreenHarmonic& h : hs) {
            f.kx.push_back(h.kx);
            f.ky.push_back(h.ky);
            f.phase.push_back(h.phase);
            f.amplitude.push_back(h.amplitude);
            f.transfer.push_back(boxTransfer(b, h.kx, h.ky, pixel));
        }
        return f;
    };
    const Fields f1 = fieldsOf(h1), f2 = fieldsOf(h2);
    // The pairs, the first's harmonic i in a loop and the second's eight in line within it,
    // summed in that order: each pair with the second's harmonic j is built into the kernel
    // once, where the 64 pairs written out were a sixth of a pair of dot screens' kernel. (All
    // 64 in one loop, both harmonics picked by index, built one pair where this builds eight,
    // and cost a scene of crowded screens a fifth more time, the picks outweighing the pair.)
    const std::vector<ValueId> out = b.loop(
        {c(0.0), c(0.0)},
        [&](std::span<const ValueId> v) {
            return std::vector<ValueId>{b.lt(v[0], c(double(h1.size())))};
        },
        [&](std::span<const ValueId> v) {
            const ValueId i = v[0];
            const ValueId kx = b.pick(i, f1.kx), ky = b.pick(i, f1.ky),
                          phase1 = b.pick(i, f1.phase);
            const ValueId amplitude = b.pick(i, f1.amplitude), transfer = b.pick(i, f1.transfer);
            ValueId sum = v[1];
            for (size_t j = 0; j < h2.size(); ++j) {
                const ValueId together =
                    boxTransfer(b, b.add(kx, f2.kx[j]), b.add(ky, f2.ky[j]), pixel);
                const ValueId weight = b.sub(together, b.mul(transfer, f2.transfer[j]));
                const ValueId phase = b.emit(ir::Op::Fract, {b.add(phase1, f2.phase[j])});
                const ValueId wave = b.cos(b.mul(phase, c(2.0 * std::numbers::pi)));
                sum = b.add(sum, b.mul(b.mul(amplitude, f2.amplitude[j]), b.mul(weight, wave)));
            }
            return std::vector<ValueId>{b.add(i, c(1.0)), sum};
        });
    return b.denan(out[1], c(0.0));
}

// The offsets at which the pair is sampled over the pixel: kDotPairTaps^2 points, in pixels
// along its sides.
std::vector<std::pair<double, double>> taps() {
    std::vector<std::pair<double, double>> out;
    for (int i = 0; i < kDotPairTaps; ++i)
        for (int j = 0; j < kDotPairTaps; ++j)
            out.push_back({(i + 0.5) / kDotPairTaps - 0.5, (j + 0.5) / kDotPairTaps - 0.5});
    return out;
}

// The sum over the taps of what `body(a, e, sum)` adds to `sum` at the tap (a, e): a loop of
// the kernel over them, each tap's offsets picked from the list by its place, so a tap's terms
// are written once where writing them per tap wrote them kDotPairTaps^2 times. The taps are
// summed in the list's order, as they were in line.
ValueId sumOverTaps(ir::Builder& b, const std::function<ValueId(ValueId, ValueId, ValueId)>& body) {
    std::vector<ValueId> as, es;
    for (const auto& [a, e] : taps()) {
        as.push_back(b.constF(a));
        es.push_back(b.constF(e));
    }
    const ValueId count = b.constF(double(as.size()));
    using Vals = std::vector<ValueId>;
    const Vals out = b.loop(
        Vals{b.constF(0.0), b.constF(0.0)},
        [&](std::span<const ValueId> v) { return Vals{b.lt(v[0], count)}; },
        [&](std::span<const ValueId> v) {
            const ValueId sum = body(b.pick(v[0], as), b.pick(v[0], es), v[1]);
            return Vals{b.add(v[0], b.constF(1.0)), sum};
        });
    return out[1];
}

// A phase `d` at a tap (a, e) of the pixel, its gradient g along the pixel's sides.
ValueId atTap(ir::Builder& b, ValueId d, const PixelSides& g, const PixelFootprint& pixel,
              ValueId a, ValueId e) {
    return b.add(d, b.mul(pixel.size, b.add(b.mul(g.u, a), b.mul(g.v, e))));
}

// The second lattice as the first moved, about the pixel: each of the first's generators
// (u1, v1) matched with the second's row nearest it (f_u, f_v). The beat is the offset
// u1 - f_u, v1 - f_v, whose gradients along the pixel's sides (gu, gv) step it over the pixel
// and weigh it (its transfer); rho = sqrt |det(grad u1, grad v1) / det(grad f_u, grad f_v)| is
// the second's pitch over the first's. `det` is the first's generators' determinant.
struct Matched {
    const CrowdEstimate::LatticeShape* p1 = nullptr;
    Row fu{}, fv{};
    PixelSides gu{}, gv{};
    ValueId det = ir::kNoValue, rho = ir::kNoValue;
};
Matched match(ir::Builder& b, const CrowdEstimate::LatticeShape& p1,
              const CrowdEstimate::LatticeShape& p2, const PixelFootprint& pixel) {
    const std::vector<Row> rows = screenRows(b, p2);
    Matched m;
    m.p1 = &p1;
    m.fu = nearestRow(b, rows, p1.ux, p1.uy);
    m.fv = nearestRow(b, rows, p1.vx, p1.vy);
    m.gu = onPixelSides(b, b.sub(p1.ux, m.fu.gx), b.sub(p1.uy, m.fu.gy), pixel);
    m.gv = onPixelSides(b, b.sub(p1.vx, m.fv.gx), b.sub(p1.vy, m.fv.gy), pixel);
    m.det = b.sub(b.mul(p1.ux, p1.vy), b.mul(p1.uy, p1.vx));
    const ValueId d2 = b.sub(b.mul(m.fu.gx, m.fv.gy), b.mul(m.fu.gy, m.fv.gx));
    m.rho = b.sqrt(b.div(b.abs(m.det), b.max(b.abs(d2), b.constF(1e-30))));
    return m;
}

// The weight of a pair of crowded lattices' correlation: the least of their crowding
// (dotsCrowded) times the beat's transfer over the pixel, that of its faster row (1 where a
// pixel spans little of a beat, 0 where it spans a whole one).
ValueId weightOf(ir::Builder& b, const Matched& m, const CrowdEstimate::LatticeShape& p2,
                 const PixelFootprint& pixel) {
    const ValueId beat = b.min(transfer(b, m.gu, pixel), transfer(b, m.gv, pixel));
    return b.mul(b.min(dotsCrowded(b, *m.p1, pixel), dotsCrowded(b, p2, pixel)),
                 b.clamp(beat, b.constF(0.0), b.constF(1.0)));
}

// At a tap of the pixel: the offset by which the second lattice stands moved on the first,
// in the first's cells, (u1 - f_u, v1 - f_v) at the tap less its nearest whole step. It runs
// with the beat, slowly and smoothly, where the nearest points of the two lattices jump from
// cell to cell.
std::array<ValueId, 2> offsetAt(ir::Builder& b, const Matched& m, const PixelFootprint& pixel,
                                ValueId a, ValueId e) {
    auto residual = [&](ValueId x) { return b.sub(x, b.round(x)); };
    return {residual(atTap(b, b.sub(m.p1->u, m.fu.phase), m.gu, pixel, a, e)),
            residual(atTap(b, b.sub(m.p1->v, m.fv.phase), m.gv, pixel, a, e))};
}

// A line (index f) with the lattice's row nearest its direction (nearestRow): the beat's
// gradient along the pixel's sides (the line's less the row's), the line's and the row's,
// the line's period in the world, and its phase per unit of the row's across them (1 where
// the periods match).
struct LineOnRow {
    Row row;
    PixelSides beat, gf, gr;
    ValueId period, perRow;
};
LineOnRow lineOnRow(ir::Builder& b, const std::vector<Row>& rows, const Footprint& f,
                    const PixelFootprint& pixel) {
    LineOnRow out;
    out.row = nearestRow(b, rows, f.gradX, f.gradY);
    const Row& row = out.row;
    out.beat = onPixelSides(b, b.sub(f.gradX, row.gx), b.sub(f.gradY, row.gy), pixel);
    out.gf = onPixelSides(b, f.gradX, f.gradY, pixel);
    out.gr = onPixelSides(b, row.gx, row.gy, pixel);
    out.period = b.div(b.constF(1.0), b.max(f.grad, b.constF(1e-12)));
    out.perRow = b.div(b.add(b.mul(f.gradX, row.gx), b.mul(f.gradY, row.gy)),
                       b.max(b.add(b.mul(row.gx, row.gx), b.mul(row.gy, row.gy)), b.constF(1e-24)));
    return out;
}

// A crowded lattice's covariance with lines, the lines taken one by one and as independent
// of one another, as strandCorrelation takes them (FineUnion.cpp): blank paper prod(1 -
// m_x)(1 - m) times prod over the lines of (1 + cov_x / ((1 - m_x)(1 - m))), m the lattice's
// own mean over the pixel (`laid`) and m_x a line's. A line's cov_x is E held to the pixel's
// own means, E sqrt(m m_x / (a d)) - m m_x (E the mean of the two inks' product over the plane
// at the pixel, a and d their shares of the plane: E where both crowd, m = a), weighted by
// the least of the two's crowding and the beat's transfer (`beat`, the line's gradient less
// its row's, along the pixel's sides).
struct LineFold {
    ValueId laid, share, crowded, blank, factor;
};
LineFold startFold(ir::Builder& b, ValueId laid, ValueId share, ValueId crowded) {
    return {laid, share, crowded, b.sub(b.constF(1.0), laid), b.constF(1.0)};
}
void foldLine(ir::Builder& b, LineFold& fold, const Strand& x, ValueId e, ValueId duty,
              const PixelSides& beat, const PixelFootprint& pixel) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    const Footprint& f = x.footprint;
    const ValueId weight =
        b.mul(b.mul(b.min(fold.crowded, unresolved(b, f, pixel)), pastFirst(b, f)),
              b.clamp(transfer(b, beat, pixel), zero, one));
    const ValueId own = b.mul(fold.laid, x.mean);
    const ValueId held = b.sqrt(b.div(own, b.max(b.mul(fold.share, duty), b.constF(1e-12))));
    const ValueId cov = b.mul(weight, b.sub(b.mul(e, held), own));
    const ValueId paper = b.mul(b.sub(one, x.mean), b.sub(one, fold.laid));
    const ValueId ratio = b.max(b.div(cov, b.max(paper, b.constF(1e-12))), b.constF(-1.0));
    fold.blank = b.mul(fold.blank, b.sub(one, x.mean));
    fold.factor = b.mul(fold.factor, b.add(one, b.denan(ratio, zero)));
}
ValueId foldedCovariance(ir::Builder& b, const LineFold& fold) {
    return b.mul(fold.blank, b.sub(fold.factor, b.constF(1.0)));
}

} // namespace

ValueId dotsCrowded(ir::Builder& b, const CrowdEstimate::LatticeShape& p,
                    const PixelFootprint& pixel) {
    ValueId rows = b.min(b.hypot(p.ux, p.uy), b.hypot(p.vx, p.vy));
    return b.smoothstep(b.constF(kCrowdFrom), b.constF(kCrowdFull), b.mul(rows, pixel.size));
}

// Over a pixel that holds many dots of each screen, the first screen's generators (u1, v1)
// and the second's matched rows (f_u, f_v) advance together: the second screen is the first
// moved by delta = (u1 - f_u, v1 - f_v) of the first's cells, and delta runs with the beat,
// grad delta = (grad u1 - grad f_u, grad v1 - grad f_v), slowly where the rows match. At a
// given delta the mean of the product of the two screens over the plane is the overlap of
// a dot of each, once a cell:
//   E(delta) = n sum_{i, j} sum_corners lens(|delta + s_j - s_i - corner|)
// with s the sites of each screen, the corners those of the first's cell that the offset
// falls in (the nearest two of them: a dot of the other screen at the third reaches the dot
// only where the dots nearly touch their own neighbours), and n the pairs a world area,
// sqrt(|det1 det2|) (det the generators' determinant, cells a world area): where the
// pitches differ, either screen's count of cells alone is off by as much. It is sampled at
// kDotPairTaps^2 points of the pixel, delta stepped along the pixel's sides. The weight is
// the least of the two screens' crowding (dotsCrowded) times the beat's transfer over the
// pixel (footprintTransfer of its faster row): 1 where a pixel spans little of a beat, 0
// where it spans a whole one and the even grey of the union of the means stands. Where the
// rows do not match (other kinds, a turn near the screens' half symmetry) the beat is fast
// and the weight is 0.
Ink dotCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                   const PixelFootprint& pixel) {
    const CrowdEstimate::LatticeShape& p1 = *l1.shape;
    const CrowdEstimate::LatticeShape& p2 = *l2.shape;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0);
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const Matched m = match(b, p1, p2, pixel);
    // The first screen's steps in the world: the columns of the inverse of its gradients.
    const auto [e1x, e1y, e2x, e2y] = worldSteps(b, p1, m.det);
    // The sites' differences, s_j - s_i, each with the number of pairs that share it.
    std::map<std::pair<double, double>, int> differences;
    for (const auto& si : p1.sites)
        for (const auto& sj : p2.sites) ++differences[{sj[0] - si[0], sj[1] - si[1]}];
    const ValueId sum = sumOverTaps(b, [&](ValueId a, ValueId e, ValueId acc) {
        const auto [tu, tv] = offsetAt(b, m, pixel, a, e);
        for (const auto& [offset, pairs] : differences) {
            ValueId qu = b.add(tu, c(offset.first)), qv = b.add(tv, c(offset.second));
            qu = b.sub(qu, b.floor(qu));
            qv = b.sub(qv, b.floor(qv));
            // The two nearest of the cell's corners: a third reaches the dot only where the
            // dots nearly touch their own neighbours.
            ValueId nearest = c(1e30), next = c(1e30);
            for (int cu : {0, 1})
                for (int cv : {0, 1}) {
                    ValueId ou = b.sub(qu, c(cu)), ov = b.sub(qv, c(cv));
                    ValueId x = b.add(b.mul(ou, e1x), b.mul(ov, e2x));
                    ValueId y = b.add(b.mul(ou, e1y), b.mul(ov, e2y));
                    ValueId d = b.hypot(x, y);
                    next = b.min(next, b.max(nearest, d));
                    nearest = b.min(nearest, d);
                }
            for (ValueId d : {nearest, next}) {
                const ValueId lens = overDiscs(b, p1, [&](ValueId r1) {
                    return overDiscs(b, p2, [&](ValueId r2) {
                        return lensArea(value(d), value(r1), value(r2)).id;
                    });
                });
                acc = b.add(acc, b.mul(c(pairs), lens));
            }
        }
        return acc;
    });
    // Pairs per world area: a cell of either screen holds one, so where their pitches differ
    // the two counts differ by as much; the geometric mean of the two.
    const ValueId pairs = b.sqrt(b.mul(cellsPerArea(b, p1), cellsPerArea(b, p2)));
    const ValueId e = b.mul(b.mul(sum, pairs), c(1.0 / double(taps().size())));
    const ValueId weight = weightOf(b, m, p2, pixel);
    // E is the plane's mean; a pixel that holds a few dots of each holds its own share of
    // the pairs that overlap, E m1 / a1 as the first screen's dots read it and E m2 / a2 as
    // the second's: their geometric mean, E where the dots crowd (m = a).
    const ValueId a1 = screenShare(b, p1), a2 = screenShare(b, p2);
    const ValueId held = b.sqrt(b.div(b.mul(l1.laid, l2.laid), b.max(b.mul(a1, a2), c(1e-12))));
    const ValueId own = b.mul(l1.laid, l2.laid);
    ValueId cov = b.mul(weight, b.sub(b.mul(e, held), own));
    // Where the matched rows carry no beat (screens of different kinds, or turned past their
    // match), the first harmonics' own (harmonicCovariance), as crowded as the two screens are;
    // behind a branch on that weight.
    const ValueId crowded = b.min(dotsCrowded(b, p1, pixel), dotsCrowded(b, p2, pixel));
    const ValueId unmatched = b.max(b.sub(crowded, weight), zero);
    cov = b.add(cov, b.ifThenElse(
                         b.gt(unmatched, zero),
                         [&] {
                             return std::vector<ValueId>{
                                 b.mul(unmatched, harmonicCovariance(b, p1, p2, pixel))};
                         },
                         [&] { return std::vector<ValueId>{zero}; })[0]);
    cov = b.select(b.emit(ir::Op::And, {p1.dots, p2.dots}), cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

// A line x of the lines' layer (index f, gradient grad f, a period L = 1 / |grad f| in the
// world) and the screen's row nearest its direction (phase phi, nearest as dotCorrelation
// matches them) advance together over the pixel: a dot at a site whose row phase stands s past
// the whole numbers has its centre delta + s periods from the nearest line, delta = f - phi,
// which runs with the beat. Each dot is inked by the lines as much as it lies within their
// strokes, the disc within the strip of half-width h about each of the three nearest lines
// (discInStrip), so the mean of the product of the screen and the lines over the plane is
//   E(delta) = cells x sum over sites of sum_{n = -1, 0, 1} discInStrip((wrap(delta + s) + n) L, h,
//   r)
// sampled at kDotPairTaps^2 points of the pixel. Its weight is the least of the screen's
// crowding and the line's (unresolved, FineUnion.cpp) times the beat's transfer; the pixel's
// own share of the overlap is E sqrt(m_d m_x / (a d_x)) as for two screens (d_x the line's duty
// 2 h / L). The lines of a lattice of edges each beat so, taken as independent of one another
// as strandCorrelation takes them: blank paper prod(1 - m)(1 - m_d) times prod over the lines of
// (1 + cov_x / ((1 - m_x)(1 - m_d))).
Ink dotLineCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                       bool dotsFirst, const PixelFootprint& pixel) {
    const FineLayer& dots = dotsFirst ? l1 : l2;
    const FineLayer& lines = dotsFirst ? l2 : l1;
    const CrowdEstimate::LatticeShape& p = *dots.shape;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0), one = c(1.0);
    if (lines.strands.empty()) return {zero, zero, zero, zero}; // the honeycomb's edges
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const std::vector<Row> rows = screenRows(b, p);
    const ValueId cells = cellsPerArea(b, p), share = screenShare(b, p);
    const ValueId crowded = dotsCrowded(b, p, pixel);
    const ValueId half = b.max(lines.sweep.halfWidth, zero);
    LineFold fold = startFold(b, dots.laid, share, crowded);
    for (const Strand& x : lines.strands) {
        const Footprint& f = x.footprint;
        const LineOnRow on = lineOnRow(b, rows, f, pixel);
        const Row& row = on.row;
        const PixelSides &g = on.beat, &gf = on.gf, &gr = on.gr;
        const ValueId period = on.period, perRow = on.perRow;
        const ValueId sum = sumOverTaps(b, [&](ValueId a, ValueId e, ValueId acc) {
            const ValueId phase = atTap(b, f.index, gf, pixel, a, e);
            const ValueId rowPhase = atTap(b, row.phase, gr, pixel, a, e);
            for (ValueId shift : row.shifts) {
                // The row of dots of this site nearest the tap, and the lines' phase at it.
                ValueId past = b.sub(rowPhase, shift);
                past = b.sub(past, b.round(past));
                ValueId atDot = b.sub(phase, b.mul(perRow, past));
                ValueId centre = b.mul(b.wrap(atDot, one), period);
                for (double n : {-1.0, 0.0, 1.0}) {
                    ValueId at = b.add(centre, b.mul(c(n), period));
                    acc = b.add(acc, overDiscs(b, p, [&](ValueId r) {
                                    return discInStrip(value(at), value(half), value(r)).id;
                                }));
                }
            }
            return acc;
        });
        const ValueId e = b.mul(b.mul(sum, cells), c(1.0 / double(taps().size())));
        const ValueId duty = b.clamp(b.mul(c(2.0), b.mul(half, f.grad)), zero, one);
        foldLine(b, fold, x, e, duty, g, pixel);
    }
    ValueId cov = b.select(p.dots, foldedCovariance(b, fold), zero);
    if (lines.strandsOn != ir::kNoValue) cov = b.select(lines.strandsOn, cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

bool sameCells(const CrowdEstimate::LatticeShape& a, const CrowdEstimate::LatticeShape& b) {
    if (a.cells.empty() || a.cells.size() != b.cells.size() || a.normals != b.normals) return false;
    for (size_t i = 0; i < a.cells.size(); ++i)
        if (a.cells[i].upper != b.cells[i].upper || a.cells[i].lower != b.cells[i].lower)
            return false;
    return true;
}

// Each lattice's ink is its edges' strokes, 1 - I with I the paper they leave: its cells,
// each side moved in by the stroke's half-width h (world), which moves the bound b_i of a
// side with normal m_i (in the generators' coordinates) by h |m_i J| (J the generators'
// gradients: m_i J is the side's normal in the world, of that length). The two layers' inks
// then have the covariance of their papers, E[I1 I2] - i1 i2 (i the papers' shares). About a
// point the second lattice is the first moved by the offset t (offsetAt) and scaled by rho =
// sqrt(|det1 / det2|) (its pitch over the first's, det the generators' determinant); the
// scale's drift from cell to cell is the beat, which t carries. Over the few cells about the
// point the second is taken at the first's period: its pattern scaled by 1 / rho, its cells
// the first's shape moved in by h2 / rho (its paper's share unchanged). The mean of I1 I2 is
// then the overlap of the first's cells with those moved by t and by the whole steps about
// it, cellArea of the least bounds of the two, over a cell:
//   E[I1 I2](t) = sum over the cells a, b of sum_{n in {-1, 0, 1}^2} area(a, b + t + n)
// whose mean over t is i1 i2. (The second's cells scaled by rho but stepped by the first's
// whole steps stood 4% of a cell off their own at pitches 0.5 and 0.52: 0.0124 RMSE where
// this reads 0.0077.) Sampled at kDotPairTaps^2 points of the pixel and weighted as two dot
// screens are (dotCorrelation), by the least crowding and the beat's transfer.
Ink cellCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                    const PixelFootprint& pixel) {
    const CrowdEstimate::LatticeShape& p1 = *l1.shape;
    const CrowdEstimate::LatticeShape& p2 = *l2.shape;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0), one = c(1.0);
    using Bounds = std::array<ir::BuiltValue, 3>;
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const Matched m = match(b, p1, p2, pixel);
    // The sides' normals in the world, their lengths, and the second lattice's scale.
    std::array<ValueId, 3> length{};
    for (int i = 0; i < 3; ++i) {
        const auto [m, n] = p1.normals[i];
        length[i] = b.hypot(b.add(b.mul(c(m), p1.ux), b.mul(c(n), p1.vx)),
                            b.add(b.mul(c(m), p1.uy), b.mul(c(n), p1.vy)));
    }
    const ValueId rho = m.rho;
    // A cell's bounds, moved in by the stroke.
    auto inset = [&](const std::array<double, 3>& bound, ValueId half) {
        Bounds out{value(zero), value(zero), value(zero)};
        for (int i = 0; i < 3; ++i) out[i] = value(b.sub(c(bound[i]), b.mul(half, length[i])));
        return out;
    };
    struct Inset {
        std::optional<Bounds> upper, lower;
    };
    // A lattice's cells at the first's period: its stroke scaled by 1 / shrink.
    auto insets = [&](const CrowdEstimate::LatticeShape& p, ValueId shrink) {
        std::vector<Inset> out;
        const ValueId half = b.div(b.max(p.radius, zero), shrink);
        for (const auto& cell : p.cells) {
            Inset in;
            if (cell.upper) in.upper = inset(*cell.upper, half);
            if (cell.lower) in.lower = inset(*cell.lower, half);
            out.push_back(in);
        }
        return out;
    };
    const std::vector<Inset> first = insets(p1, one), second = insets(p2, rho);
    // The area of a region of bounds on one side or both.
    auto area = [&](const Inset& r) {
        if (r.upper) return cellArea(*r.upper, r.lower, p1.kappa).id;
        return cellArea(*r.lower, std::optional<Bounds>{}, p1.kappa).id;
    };
    auto least = [&](const std::optional<Bounds>& x, const std::optional<Bounds>& y) {
        if (!x) return y;
        if (!y) return x;
        return std::optional<Bounds>{
            Bounds{min((*x)[0], (*y)[0]), min((*x)[1], (*y)[1]), min((*x)[2], (*y)[2])}};
    };
    std::vector<std::array<ValueId, 2>> steps;
    for (int iu = -1; iu <= 1; ++iu)
        for (int iv = -1; iv <= 1; ++iv) steps.push_back({c(iu), c(iv)});
    const ValueId sum = sumOverTaps(b, [&](ValueId a, ValueId e, ValueId acc) {
        const auto [tu, tv] = offsetAt(b, m, pixel, a, e);
        for (const auto& step : steps) {
            const ValueId su = b.add(tu, step[0]), sv = b.add(tv, step[1]);
            std::array<ir::BuiltValue, 3> along{value(zero), value(zero), value(zero)};
            for (int i = 0; i < 3; ++i)
                along[i] =
                    value(b.add(b.mul(c(p1.normals[i][0]), su), b.mul(c(p1.normals[i][1]), sv)));
            for (const Inset& x : first)
                for (const Inset& y : second) {
                    // The second's cell moved by s: its upper bounds grow by m . s, its
                    // lower ones shrink.
                    Inset moved;
                    if (y.upper)
                        moved.upper = Bounds{(*y.upper)[0] + along[0], (*y.upper)[1] + along[1],
                                             (*y.upper)[2] + along[2]};
                    if (y.lower)
                        moved.lower = Bounds{(*y.lower)[0] - along[0], (*y.lower)[1] - along[1],
                                             (*y.lower)[2] - along[2]};
                    acc = b.add(acc,
                                area({least(x.upper, moved.upper), least(x.lower, moved.lower)}));
                }
        }
        return acc;
    });
    const ValueId e = b.mul(sum, c(1.0 / double(taps().size())));
    ValueId i1 = zero, i2 = zero;
    for (const Inset& x : first) i1 = b.add(i1, area(x));
    for (const Inset& y : second) i2 = b.add(i2, area(y));
    const ValueId weight = weightOf(b, m, p2, pixel);
    ValueId cov = b.mul(weight, b.sub(e, b.mul(i1, i2)));
    const ValueId edges =
        b.emit(ir::Op::And, {b.emit(ir::Op::Not, {p1.dots}), b.emit(ir::Op::Not, {p2.dots})});
    cov = b.select(edges, cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

bool honeycombCells(const CrowdEstimate::LatticeShape& p) {
    return p.cells.size() == 1 && p.cells[0].upper && p.cells[0].lower;
}

// A honeycomb's cell shrunk by its strokes (insetHexagon), in the world: its corners through
// the generators' steps (det their determinant), those steps, and its share of the cell, i_h.
struct WorldHexagon {
    std::array<std::array<ir::BuiltValue, 2>, 6> corners;
    ir::BuiltValue e1x, e1y, e2x, e2y;
    ir::BuiltValue paperShare;
};
WorldHexagon worldHexagon(ir::Builder& b, const CrowdEstimate::LatticeShape& p, ValueId det) {
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const auto bounds =
        hexBounds(value(p.radius), value(p.ux), value(p.uy), value(p.vx), value(p.vy));
    const auto corners = insetHexagon(bounds);
    const ir::BuiltValue paperShare = insetHexagonArea(bounds);
    const WorldSteps steps = worldSteps(b, p, det);
    const ir::BuiltValue e1x = value(steps.e1x), e1y = value(steps.e1y);
    const ir::BuiltValue e2x = value(steps.e2x), e2y = value(steps.e2y);
    std::array<std::array<ir::BuiltValue, 2>, 6> world;
    for (size_t k = 0; k < 6; ++k)
        world[k] = {corners[k][0] * e1x + corners[k][1] * e2x,
                    corners[k][0] * e1y + corners[k][1] * e2y};
    return {world, e1x, e1y, e2x, e2y, paperShare};
}

// A line x of the lines' layer (index f, a period L = 1 / |grad f| in the world) and the
// honeycomb's row nearest its direction (phase r = a u + b v, whole at every centre; a row of
// centres, (1, 0), (0, 1), (1, 1), or of the lines the sides lie on, (1, 2), (2, 1), (1, -1))
// advance together over the pixel: at a tap the centres of the nearest row, r - round(r) rows
// back, stand at the lines' phase f_c = f - perRow (r - round(r)), which runs with the beat,
// so line n crosses each such hexagon (n - f_c) L from its centre along the lines' normal.
// The paper both layers leave is then the shrunk hexagon (insetHexagon, mapped to the world
// through the generators' steps) less its parts within the strokes of the lines that reach
// it, five about the nearest (polygonInBand in the frame of the lines), once a cell:
//   E[I_h I_x] = cells (area(H) - sum_n area(H within line n's stroke)),
// sampled at kDotPairTaps^2 points of the pixel. As inks (c = 1 - I) the product's mean is
// 1 - i_h - i_x + E[I_h I_x], i the papers' shares; weighted and held to the pixel's own
// means as dotLineCorrelation weighs a screen's, and the lines of a lattice of edges taken
// as independent of one another the same way.
Ink hexLineCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                       bool cellsFirst, const PixelFootprint& pixel) {
    const FineLayer& hex = cellsFirst ? l1 : l2;
    const FineLayer& lines = cellsFirst ? l2 : l1;
    const CrowdEstimate::LatticeShape& p = *hex.shape;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0), one = c(1.0);
    if (lines.strands.empty()) return {zero, zero, zero, zero}; // a honeycomb's edges
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    // The rows, as screenRows reads a screen with one site at the centres.
    CrowdEstimate::LatticeShape rowsOf = p;
    rowsOf.sites = {{{0.0, 0.0}}};
    rowsOf.shortest = {{{1, 0}}, {{0, 1}}, {{1, 1}}, {{1, 2}}, {{2, 1}}, {{1, -1}}};
    const std::vector<Row> rows = screenRows(b, rowsOf);
    const ValueId det = b.sub(b.mul(p.ux, p.vy), b.mul(p.uy, p.vx));
    const WorldHexagon hexagon = worldHexagon(b, p, det);
    const ir::BuiltValue paperShare = hexagon.paperShare;
    const ValueId cells = b.abs(det);
    const ValueId crowded = dotsCrowded(b, p, pixel);
    const ValueId lineHalf = b.max(lines.sweep.halfWidth, zero);
    const ValueId ah = b.sub(one, paperShare.id); // the honeycomb's share of ink
    LineFold fold = startFold(b, hex.laid, ah, crowded);
    for (const Strand& x : lines.strands) {
        const Footprint& f = x.footprint;
        const LineOnRow on = lineOnRow(b, rows, f, pixel);
        const Row& row = on.row;
        const PixelSides &g = on.beat, &gf = on.gf, &gr = on.gr;
        const ValueId period = on.period, perRow = on.perRow;
        // The hexagon in the lines' frame: y along their normal, x along them (a right-handed
        // frame, so the corners keep their sense).
        const ir::BuiltValue nx = value(b.div(f.gradX, b.max(f.grad, c(1e-12))));
        const ir::BuiltValue ny = value(b.div(f.gradY, b.max(f.grad, c(1e-12))));
        std::array<std::array<ir::BuiltValue, 2>, 6> shape;
        for (size_t k = 0; k < 6; ++k) {
            const auto& [wx, wy] = hexagon.corners[k];
            shape[k] = {wx * ny - wy * nx, wx * nx + wy * ny};
        }
        const ValueId h = b.min(lineHalf, b.mul(period, c(0.5)));
        const ValueId sum = sumOverTaps(b, [&](ValueId a, ValueId e, ValueId acc) {
            const ValueId phase = atTap(b, f.index, gf, pixel, a, e);
            const ValueId rowPhase = atTap(b, row.phase, gr, pixel, a, e);
            const ValueId past = b.sub(rowPhase, b.round(rowPhase));
            const ValueId atCentre = b.sub(phase, b.mul(perRow, past));
            const ValueId nearest = b.round(atCentre);
            ValueId covered = zero;
            for (double n : {-2.0, -1.0, 0.0, 1.0, 2.0}) {
                const ValueId y = b.mul(b.sub(b.add(nearest, c(n)), atCentre), period);
                covered =
                    b.add(covered,
                          b.abs(polygonInBand(shape, value(b.sub(y, h)), value(b.add(y, h))).id));
            }
            return b.add(acc, b.sub(paperShare.id, b.mul(cells, covered)));
        });
        const ValueId paperBoth = b.mul(sum, c(1.0 / double(taps().size())));
        const ValueId duty = b.clamp(b.mul(c(2.0), b.mul(lineHalf, f.grad)), zero, one);
        // The inks' product: 1 - i_h - i_x + E[I_h I_x].
        const ValueId e = b.add(b.sub(b.add(ah, duty), one), paperBoth);
        foldLine(b, fold, x, e, duty, g, pixel);
    }
    ValueId cov = b.select(p.dots, zero, foldedCovariance(b, fold));
    if (lines.strandsOn != ir::kNoValue) cov = b.select(lines.strandsOn, cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

// A dot of the screen, at its site j in the matched rows' phases (the rows' shifts), stands
// where the honeycomb's (u, v) = t + shift_j + n, t the beat's offset at the tap, n whole: in
// the world, from the centre of the hexagon at (0, 0), through the honeycomb's steps. With the
// screen taken at the honeycomb's period (its dots' radius r / rho, rho its pitch over the
// honeycomb's: the screen's share kept, as cellCorrelation takes a second lattice), the mean
// over the plane of the paper both leave a cell is
//   E[I_h D](t) = cells x sum over the sites j of sum_{n whole} area(H within the dot at
//   t + shift_j + n)
// (H the shrunk hexagon; discInPolygon), read at the pixel's centre. The hexagons tile the
// plane, so the sum over n is one dot's area within every hexagon: within
// the three whose centres stand nearest its own (a dot of radius under half a side reaches no
// other's paper). As
// inks (the honeycomb's 1 - I_h, the screen's D) the product's mean is d - E[I_h D], held to
// the pixel's own means and weighted as two screens are.
Ink hexDotCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                      bool cellsFirst, const PixelFootprint& pixel) {
    const FineLayer& hex = cellsFirst ? l1 : l2;
    const FineLayer& dots = cellsFirst ? l2 : l1;
    const CrowdEstimate::LatticeShape& ph = *hex.shape;
    const CrowdEstimate::LatticeShape& pd = *dots.shape;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0), one = c(1.0);
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const Matched m = match(b, ph, pd, pixel);
    const WorldHexagon hexagon = worldHexagon(b, ph, m.det);
    const ValueId paperShare = hexagon.paperShare.id; // in cells: i_h
    const auto& shape = hexagon.corners;
    const ir::BuiltValue &e1x = hexagon.e1x, &e1y = hexagon.e1y;
    const ir::BuiltValue &e2x = hexagon.e2x, &e2y = hexagon.e2y;
    const ValueId cells = b.abs(m.det);
    // The screen's members at the honeycomb's period: each disc's radius over rho.
    auto atPeriod = [&](ValueId r) { return b.div(b.max(r, zero), m.rho); };
    // At the pixel's centre (2 x 2 taps read the tests' pairs the same to 1e-4 with four times
    // the loop's work: the beat's change across the pixel is its transfer's), one loop over the
    // three hexagons nearest each dot, so that the kernel writes a disc's sides out once a site
    // (written out for every tap and every dot about a hexagon, the kernel was 3.4 MB of GLSL
    // that lavapipe took six minutes to compile).
    const int kNear = 3;
    const auto [tu, tv] = offsetAt(b, m, pixel, b.constF(0.0), b.constF(0.0));
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{b.lt(v[0], c(double(kNear)))};
    };
    const std::vector<ValueId> out = b.loop({zero, zero}, more, [&](std::span<const ValueId> v) {
        const ValueId near = v[0];
        ValueId sum = v[1];
        for (size_t j = 0; j < pd.sites.size(); ++j) {
            ValueId su = b.add(tu, m.fu.shifts[j]), sv = b.add(tv, m.fv.shifts[j]);
            su = b.sub(su, b.floor(su));
            sv = b.sub(sv, b.floor(sv));
            // The centres about a point of the cell [0, 1)^2: the triangle (0, 0), (1, 0),
            // (0, 1) below u + v = 1, (1, 1), (1, 0), (0, 1) above (the neighbours stand at
            // (1, -1) as at (1, 0) and (0, 1)).
            const ValueId above = b.gt(b.add(su, sv), one);
            const ValueId corner = b.select(above, one, zero);
            const ValueId isU = b.lt(near, c(0.5)), isV = b.lt(b.abs(b.sub(near, one)), c(0.5));
            const ValueId cu = b.select(isU, one, b.select(isV, zero, corner));
            const ValueId cv = b.select(isU, zero, b.select(isV, one, corner));
            const ir::BuiltValue qu = value(b.sub(su, cu)), qv = value(b.sub(sv, cv));
            const ir::BuiltValue x = qu * e1x + qv * e2x, y = qu * e1y + qv * e2y;
            sum = b.add(sum, overDiscs(b, pd, [&](ValueId r) {
                            return b.abs(discInPolygon(shape, x, y, value(atPeriod(r))).id);
                        }));
        }
        return std::vector<ValueId>{b.add(v[0], one), sum};
    });
    const ValueId paperDots = b.mul(cells, out[1]);
    const ValueId area = overDiscs(b, pd, [&](ValueId r) {
        const ValueId q = atPeriod(r);
        return b.mul(q, q);
    });
    const ValueId dotShare =
        b.min(b.mul(cells, b.mul(c(std::numbers::pi * double(pd.sites.size())), area)), one);
    const ValueId inkHex = b.sub(one, paperShare);
    const ValueId e = b.sub(dotShare, paperDots); // E[(1 - I_h) D]
    const ValueId held =
        b.sqrt(b.div(b.mul(hex.laid, dots.laid), b.max(b.mul(inkHex, dotShare), c(1e-12))));
    const ValueId weight = weightOf(b, m, pd, pixel);
    ValueId cov = b.mul(weight, b.sub(b.mul(e, held), b.mul(hex.laid, dots.laid)));
    cov = b.select(b.emit(ir::Op::And, {b.emit(ir::Op::Not, {ph.dots}), pd.dots}), cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

} // namespace moire::lower
