#include "compiler/lower/LatticeCrowd.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/HoneycombInPixel.h"
#include "compiler/lower/Prefilter.h"
#include "compiler/lower/TriangleInPixel.h"

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <vector>

namespace moire::lower {

using ir::ValueId;

namespace {

constexpr double kSqrt3 = std::numbers::sqrt3;
constexpr double kPi = std::numbers::pi;

// Each kind as the unstretched lattice (u, with spacing s) sees it: the unit normals of the
// families of lines its edges lie on (or, for the points, its rows), their spacing over s,
// the cell's area over s^2 and the points a cell holds, and the directions of a cell's edges
// with their length over s (the edges one cell owns: each is shared by two).
struct Geometry {
    int families;
    std::array<std::array<double, 2>, 3> normals;
    double rowSpacing; // between neighbouring parallel lines (or rows of points), over s
    double cellArea;   // over s^2
    double points;     // per cell
    std::array<std::array<double, 2>, 3> edges; // a cell's own edges' directions (length s)
};

Geometry geometryOf(LatticeKind kind) {
    switch (kind) {
    case LatticeKind::Square:
        // Lines x = k s and y = k s; a cell of s^2 owns one edge along each.
        return {2, {{{1, 0}, {0, 1}, {0, 0}}}, 1.0, 1.0, 1.0, {{{0, 1}, {1, 0}, {0, 0}}}};
    case LatticeKind::Triangle:
        // Three families of lines s sqrt3 / 2 apart; a rhombic cell of s^2 sqrt3 / 2 holds one
        // point and owns one edge along each of the three directions.
        return {3,   {{{0, 1}, {-kSqrt3 / 2, 0.5}, {kSqrt3 / 2, 0.5}}}, kSqrt3 / 2, kSqrt3 / 2,
                1.0, {{{1, 0}, {0.5, kSqrt3 / 2}, {-0.5, kSqrt3 / 2}}}};
    case LatticeKind::Hex:
        // A honeycomb of side s: its edges lie on lines s sqrt3 / 2 apart with normals at 0,
        // 60 and 120 degrees; a hexagon of 3 sqrt3 / 2 s^2 holds two corners and owns three
        // of its six edges, one along each direction.
        return {3,   {{{1, 0}, {0.5, kSqrt3 / 2}, {-0.5, kSqrt3 / 2}}}, kSqrt3 / 2, 1.5 * kSqrt3,
                2.0, {{{0, 1}, {-kSqrt3 / 2, 0.5}, {kSqrt3 / 2, 0.5}}}};
    }
    return {};
}

// The generators' steps in the world, the columns of the inverse of their gradients, along
// the pixel's sides in pixels: e1 = (u, v) advanced by (1, 0), e2 by (0, 1).
struct PixelSteps {
    ValueId e1u, e1v, e2u, e2v;
};
PixelSteps pixelSteps(ir::Builder& b, const LatticeCrowdInputs& in, const PixelFootprint& pixel) {
    ValueId det = b.sub(b.mul(in.genUX, in.genVY), b.mul(in.genUY, in.genVX));
    const PixelSides e1 = onPixelSides(b, b.div(in.genVY, det), b.div(b.neg(in.genVX), det), pixel);
    const PixelSides e2 = onPixelSides(b, b.div(b.neg(in.genUY), det), b.div(in.genUX, det), pixel);
    return {b.div(e1.u, in.pixel), b.div(e1.v, in.pixel), b.div(e2.u, in.pixel),
            b.div(e2.v, in.pixel)};
}

// The dots' mean over the pixel where the lattice draws its points (LatticeCrowdInputs, t the
// stroke): the nearest dot, whose centre stands `distance` back along the distance's gradient
// (a point's distance grows radially from it), and its neighbours, each a disc over the
// pixel in pixel units (discInSquare). Where the gradient is not known (the pixel's centre on
// the point) the dot is centred on the pixel. Sets `engaged` for the points' hand-over to the
// cells' share.
ValueId dotsInPixel(ir::Builder& b, LatticeKind kind, const LatticeCrowdInputs& in, ValueId t,
                    ValueId& engaged) {
    auto c = [&](double v) { return b.constF(v); };
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
    ValueId gx = b.emit(ir::Op::DerivX, {in.distance});
    ValueId gy = b.emit(ir::Op::DerivY, {in.distance});
    const PixelSides g = onPixelSides(b, gx, gy, pixel);
    ValueId back = b.div(b.neg(in.distance), in.pixel);
    ValueId cu = b.denan(b.mul(back, g.u), c(0.0)), cv = b.denan(b.mul(back, g.v), c(0.0));
    ValueId r = b.div(b.mul(t, c(0.5)), in.pixel);
    // The discs are measured behind a branch on the lattice drawing its points (a uniform).
    auto nearestDot = [&] { return discInSquare(value(cu), value(cv), value(r)).id; };
    auto points = [&](const std::function<ValueId()>& dots) {
        return b.ifThenElse(
            in.drawEdges, [&] { return std::vector<ValueId>{c(0.0)}; },
            [&] { return std::vector<ValueId>{dots()}; })[0];
    };
    if (in.genU == ir::kNoValue) return points(nearestDot);
    // The neighbours, as steps (du, dv) of the generators: the square lattice's eight within
    // a diagonal step, the triangle lattice's twelve within sqrt3 steps (its first two
    // shells), and the honeycomb's six corners of its own kind sqrt3 s away (the hexagons'
    // centres' steps) and three of the other kind s away. The corners of one kind stand at
    // (1/3, 1/3) of the centres' cell, the other kind's at (2/3, 2/3), so u + v at the
    // nearest corner tells which it is, and the other kind's three stand +-(1/3, 1/3),
    // +-(-2/3, 1/3), +-(1/3, -2/3) from it. In every kind the next ring out is two of the
    // nearest neighbours' distance away.
    struct Step {
        double du, dv;
        bool flips; // the honeycomb's other kind: taken with the nearest corner's sign
    };
    std::vector<Step> steps;
    if (kind == LatticeKind::Square) {
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j)
                if (i != 0 || j != 0) steps.push_back({double(i), double(j), false});
    } else {
        for (auto [i, j] : {std::pair{1, 0}, {0, 1}, {1, -1}})
            for (int sign : {1, -1}) steps.push_back({double(sign * i), double(sign * j), false});
        if (kind == LatticeKind::Triangle) {
            for (auto [i, j] : {std::pair{1, 1}, {2, -1}, {1, -2}})
                for (int sign : {1, -1})
                    steps.push_back({double(sign * i), double(sign * j), false});
        } else {
            for (auto [i, j] : {std::pair{1.0, 1.0}, {-2.0, 1.0}, {1.0, -2.0}})
                steps.push_back({i / 3.0, j / 3.0, true});
        }
    }
    const auto [e1u, e1v, e2u, e2v] = pixelSteps(b, in, pixel);
    ValueId sign = c(1.0);
    if (kind == LatticeKind::Hex) {
        // u + v at the nearest corner: at the pixel's, less the gradients along the way back.
        ValueId backX = b.mul(b.neg(in.distance), gx), backY = b.mul(b.neg(in.distance), gy);
        ValueId at = b.add(b.add(in.genU, in.genV), b.add(b.mul(b.add(in.genUX, in.genVX), backX),
                                                          b.mul(b.add(in.genUY, in.genVY), backY)));
        sign = b.select(b.gt(b.emit(ir::Op::Fract, {at}), c(0.5)), c(1.0), c(-1.0));
    }
    std::vector<std::pair<ValueId, ValueId>> offsets;
    ValueId shortest = c(1e30);
    for (const Step& st : steps) {
        ValueId du = st.flips ? b.mul(sign, c(st.du)) : c(st.du);
        ValueId dv = st.flips ? b.mul(sign, c(st.dv)) : c(st.dv);
        ValueId ou = b.add(b.mul(du, e1u), b.mul(dv, e2u));
        ValueId ov = b.add(b.mul(du, e1v), b.mul(dv, e2v));
        offsets.push_back({ou, ov});
        shortest = b.min(shortest, b.hypot(ou, ov));
    }
    // The dots counted are every dot that reaches the pixel while the next ring stands beyond
    // a dot's radius and half the pixel's diagonal: the points hand over to the cells' share
    // as that ring comes within reach, from (r + 0.71) / step = 1.6 to 2 (step the nearest
    // neighbours' distance), where the rows of a lattice of thin dots are already about half
    // a pixel apart (in place of the rows' 1.33 to 1 pixel).
    ValueId ring = b.div(b.add(r, c(kHalfDiagonal)), b.max(shortest, c(1e-9)));
    ValueId pointsEngaged = b.smoothstep(c(1.6), c(2.0), ring);
    engaged = b.select(in.drawEdges, engaged, b.denan(pointsEngaged, c(1.0)));
    // Behind a branch: only where a neighbour's dot can reach the pixel and the dots are not
    // handed over whole.
    ValueId reach = b.emit(ir::Op::And, {b.lt(shortest, b.add(b.mul(r, c(2.0)), c(1.5))),
                                         b.lt(pointsEngaged, c(1.0))});
    return points([&] {
        ValueId dot = nearestDot();
        return b.ifThenElse(
            reach,
            [&] {
                ValueId sum = dot;
                for (const auto& [ou, ov] : offsets)
                    sum = b.add(
                        sum, discInSquare(value(b.add(cu, ou)), value(b.add(cv, ov)), value(r)).id);
                return std::vector<ValueId>{b.denan(b.min(sum, c(1.0)), dot)};
            },
            [&] { return std::vector<ValueId>{dot}; })[0];
    });
}

// sin(x) / x, 1 where x is within 1e-4 of 0.
ValueId sinc(ir::Builder& b, ValueId x) {
    return b.select(b.lt(b.abs(x), b.constF(1e-4)), b.constF(1.0), b.div(b.sin(x), x));
}

// The box filter's ripple about a lattice's share of the plane (docs/filtering.md, "The box
// filter's ripple"). A lattice's ink is periodic in the generators' indices (u, v): f = sum over
// m of F_m e^(2 pi i m . (u, v)), its harmonic m a wave of world frequency k_m = m1 grad u +
// m2 grad v, and F_0 the share. The square pixel's mean of a wave is the wave at its centre
// times sin(pi f) / (pi f) for each of its sides, f the wave's cycles a pixel along it; so the
// box-filtered ink is the share plus, over the pairs +-m (F_m real: each kind's ink is
// symmetric about a cell's centre or site), 2 F_m times both sides' factors times
// cos(2 pi m . (u, v)). `harmonic` gives F_m from m and k_m; the harmonics taken are those with
// |m1|, |m2| <= kRippleOrders.
constexpr int kRippleOrders = 2;
using Harmonic = std::function<ValueId(ValueId m1, ValueId m2, ValueId kx, ValueId ky)>;
ValueId latticeRipple(ir::Builder& b, const LatticeCrowdInputs& in, const Harmonic& harmonic) {
    auto c = [&](double v) { return b.constF(v); };
    const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
    const double side = 2 * kRippleOrders + 1;
    // Harmonic j of the (2 M + 1)^2 about 0, those after 0 in that order: one of each pair.
    std::vector<ValueId> out = b.loop(
        {c((side * side + 1) / 2), c(0.0)},
        [&](std::span<const ValueId> v) {
            return std::vector<ValueId>{b.lt(v[0], c(side * side))};
        },
        [&](std::span<const ValueId> v) {
            const ValueId row = b.floor(b.div(v[0], c(side)));
            const ValueId m1 = b.sub(row, c(kRippleOrders));
            const ValueId m2 = b.sub(b.sub(v[0], b.mul(row, c(side))), c(kRippleOrders));
            const ValueId kx = b.add(b.mul(m1, in.genUX), b.mul(m2, in.genVX));
            const ValueId ky = b.add(b.mul(m1, in.genUY), b.mul(m2, in.genVY));
            const ValueId box = boxTransfer(b, kx, ky, pixel);
            // The wave's phase, its whole cycles dropped first for float's sake far out.
            const ValueId phase =
                b.emit(ir::Op::Fract, {b.add(b.mul(m1, in.genU), b.mul(m2, in.genV))});
            const ValueId wave = b.cos(b.mul(phase, c(2.0 * kPi)));
            const ValueId term = b.mul(b.mul(c(2.0), harmonic(m1, m2, kx, ky)), b.mul(box, wave));
            return std::vector<ValueId>{b.add(v[0], c(1.0)), b.add(v[1], term)};
        });
    return b.denan(out[1], c(0.0));
}

// A dot screen's harmonics: F_m = |det(grad u, grad v)| pi r^2 (2 J1(z) / z) S_m at
// z = 2 pi r |k_m|, each dot's transform (discTransform) times the cells a unit of area holds,
// and S_m the sum of e^(-2 pi i m . a) over the cell's sites a: 1 for one site, and for the
// honeycomb's corners at (1/3, 1/3) and (2/3, 2/3), 2 where m1 + m2 is a multiple of 3, else
// -1. The dots laid apart, as the share takes them.
ValueId dotRipple(ir::Builder& b, LatticeKind kind, const LatticeCrowdInputs& in, ValueId r) {
    auto c = [&](double v) { return b.constF(v); };
    const ValueId cells = b.abs(b.sub(b.mul(in.genUX, in.genVY), b.mul(in.genUY, in.genVX)));
    return latticeRipple(b, in, [&](ValueId m1, ValueId m2, ValueId kx, ValueId ky) {
        const ValueId harmonic = dotHarmonic(b, cells, r, kx, ky);
        if (kind != LatticeKind::Hex) return harmonic;
        const ValueId third = b.div(b.add(m1, m2), c(3.0));
        const ValueId whole = b.lt(b.abs(b.sub(third, b.round(third))), c(0.1));
        return b.mul(harmonic, b.select(whole, c(2.0), c(-1.0)));
    });
}

// The honeycomb's shrunk hexagon's bounds (HoneycombInPixel.h) for strokes of half-width
// `half`, and its edges' share of the plane, exactly: 1 less the hexagon's area.
std::array<ir::BuiltValue, 3> hexBoundsOf(ir::Builder& b, const LatticeCrowdInputs& in,
                                          ValueId half) {
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    return hexBounds(value(half), value(in.genUX), value(in.genUY), value(in.genVX),
                     value(in.genVY));
}
ValueId hexEdgeShare(ir::Builder& b, const LatticeCrowdInputs& in, ValueId half) {
    const ValueId paper = insetHexagonArea(hexBoundsOf(b, in, half)).id;
    return b.clamp(b.sub(b.constF(1.0), paper), b.constF(0.0), b.constF(1.0));
}

// A honeycomb's edges' harmonics (latticeRipple): the ink is 1 less the paper, each cell's
// hexagon shrunk from its sides about its centre (insetHexagon, in (u, v), where a cell has
// area 1), so F_m is minus the shrunk hexagon's transform at w = 2 pi m. By the divergence
// theorem (e^(-i w . q) is the divergence of i w e^(-i w . q) / |w|^2) a polygon's transform is
// (i / |w|^2) times the sum over its sides of (w . N) sinc(w . e / 2) e^(-i w . c), e the side,
// c its middle, N = (e_y, -e_x) its outward normal times its length (counterclockwise) and
// sinc(x) = sin(x) / x; a hexagon's opposite sides pair to
// (2 / |w|^2) sum over three sides of (w . N) sinc(w . e / 2) sin(w . c).
ValueId hexEdgeRipple(ir::Builder& b, const LatticeCrowdInputs& in, ValueId half) {
    auto c = [&](double v) { return b.constF(v); };
    const auto corners = insetHexagon(hexBoundsOf(b, in, half));
    return latticeRipple(b, in, [&](ValueId m1, ValueId m2, ValueId, ValueId) {
        const ValueId wu = b.mul(m1, c(2.0 * kPi)), wv = b.mul(m2, c(2.0 * kPi));
        ValueId sum = c(0.0);
        for (int j = 0; j < 3; ++j) {
            const auto& p = corners[j];
            const auto& q = corners[j + 1];
            const ValueId eu = (q[0] - p[0]).id, ev = (q[1] - p[1]).id;
            const ValueId cu = ((p[0] + q[0]) * 0.5).id, cv = ((p[1] + q[1]) * 0.5).id;
            const ValueId normal = b.sub(b.mul(wu, ev), b.mul(wv, eu));
            const ValueId along = b.mul(b.add(b.mul(wu, eu), b.mul(wv, ev)), c(0.5));
            const ValueId at = b.add(b.mul(wu, cu), b.mul(wv, cv));
            sum = b.add(sum, b.mul(b.mul(normal, sinc(b, along)), b.sin(at)));
        }
        const ValueId w2 = b.add(b.mul(wu, wu), b.mul(wv, wv));
        return b.neg(b.div(b.mul(sum, c(2.0)), w2));
    });
}

// A lattice's edges over the pixel where they are not whole lines laid as independent inks
// (the honeycomb's, HoneycombInPixel.h; the triangle lattice's, whose lines meet at its
// points, TriangleInPixel.h): 1 less the paper its strokes leave there, from the cells that
// hold the pixel up to `oneRows` rows a pixel (`first`, a sum of their paper), with the next
// ring of cells added up to `lastRows` where there is one (`more`, by a branch); handed over
// to the crowded reading (`engaged`) in the last kEdgesHandOver rows a pixel before
// `lastRows`. Behind a branch: only where the pixel reaches a stroke (the nearest edge within
// half its diagonal), `gate` holds (where given) and it is not handed over whole; elsewhere
// `elsewhere`, or the distance form.
constexpr double kEdgesHandOver = 0.4;
struct EdgesReading {
    double oneRows = 0.0, lastRows = 0.0;
    std::function<ir::BuiltValue()> first;
    std::function<ir::BuiltValue(ir::BuiltValue)> more;
    ValueId gate = ir::kNoValue, elsewhere = ir::kNoValue;
};
ValueId edgesInPixel(ir::Builder& b, const LatticeCrowdInputs& in, ValueId half, ValueId members,
                     ValueId& engaged, const EdgesReading& r) {
    auto c = [&](double v) { return b.constF(v); };
    const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
    const ValueId handed = b.smoothstep(c(r.lastRows - kEdgesHandOver), c(r.lastRows), members);
    engaged = b.select(in.drawEdges, handed, engaged);
    const ValueId reach = b.add(half, b.mul(in.pixel, c(kHalfDiagonal)));
    ValueId inside =
        b.emit(ir::Op::And, {b.emit(ir::Op::And, {in.drawEdges, b.lt(in.distance, reach)}),
                             b.lt(handed, c(1.0))});
    if (r.gate != ir::kNoValue) inside = b.emit(ir::Op::And, {inside, r.gate});
    // The ink over the pixel from the paper its cells leave.
    auto inkOf = [&](ir::BuiltValue sum) {
        return std::vector<ValueId>{b.denan(b.sub(c(1.0), paperShare(sum).id), c(0.0))};
    };
    return b.ifThenElse(
        inside,
        [&] {
            // The first cells once, the next ring's added behind a branch.
            const ir::BuiltValue near = r.first();
            if (!r.more) return inkOf(near);
            return b.ifThenElse(
                b.lt(members, c(r.oneRows)), [&] { return inkOf(near); },
                [&] { return inkOf(r.more(near)); });
        },
        [&] {
            if (r.elsewhere != ir::kNoValue) return std::vector<ValueId>{r.elsewhere};
            return std::vector<ValueId>{
                distanceInk(b, in.distance, half, ir::kNoValue, ir::kNoValue, pixel)};
        })[0];
}

// A honeycomb's edges over the pixel (edgesInPixel): the hexagon about the pixel's centre and
// its neighbours to kOneRingRows, the next ring's to kTwoRingsRows.
ValueId hexEdgesInPixel(ir::Builder& b, const LatticeCrowdInputs& in, ValueId half, ValueId members,
                        ValueId& engaged) {
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
    std::optional<HexagonsInSquare<ir::BuiltValue>> hexagons;
    EdgesReading r;
    r.oneRows = kOneRingRows;
    r.lastRows = kTwoRingsRows;
    r.first = [&] {
        const PixelSteps e = pixelSteps(b, in, pixel);
        hexagons = hexagonsInSquare(value(in.genU), value(in.genV), value(e.e1u), value(e.e1v),
                                    value(e.e2u), value(e.e2v), hexBoundsOf(b, in, half));
        return paperOfCells(*hexagons, 0, kOneRingCells, value(b.constF(0.0)));
    };
    r.more = [&](ir::BuiltValue sum) {
        return paperOfCells(*hexagons, kOneRingCells, kHexRings.size(), sum);
    };
    return edgesInPixel(b, in, half, members, engaged, r);
}

// The triangle lattice's edges over the pixel (edgesInPixel): the 2 x 2 cells nearest the
// pixel's centre to kTriNearRows, the 3 x 3 about its cell to kTriOneBlockRows. Only where the
// strokes of two of its three families reach the pixel, which is where its lines may meet there:
// elsewhere one family's lines at most ink it, and `strands`, the families laid as independent,
// each averaged over the pixel, is exact. Each family's stroke in index units is the half-width
// times its gradient's length.
ValueId triangleEdgesInPixel(ir::Builder& b, const LatticeCrowdInputs& in, ValueId half,
                             ValueId members, ValueId strands, ValueId& engaged) {
    auto c = [&](double v) { return b.constF(v); };
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
    const ValueId wx = b.add(in.genUX, in.genVX), wy = b.add(in.genUY, in.genVY);
    const std::array<std::array<ValueId, 3>, 3> families{{{in.genU, in.genUX, in.genUY},
                                                          {in.genV, in.genVX, in.genVY},
                                                          {b.add(in.genU, in.genV), wx, wy}}};
    const ValueId reach = b.add(half, b.mul(in.pixel, c(kHalfDiagonal)));
    std::array<ValueId, 3> near{};
    for (size_t k = 0; k < 3; ++k) {
        const auto& [f, gx, gy] = families[k];
        const ValueId apart = b.div(b.abs(b.sub(f, b.round(f))), b.hypot(gx, gy));
        near[k] = b.lt(apart, reach);
    }
    auto both = [&](size_t i, size_t j) { return b.emit(ir::Op::And, {near[i], near[j]}); };
    EdgesReading r;
    r.oneRows = r.lastRows = kTriOneBlockRows;
    r.gate = b.emit(ir::Op::Or, {b.emit(ir::Op::Or, {both(0, 1), both(0, 2)}), both(1, 2)});
    r.elsewhere = strands;
    r.first = [&] {
        const PixelSteps e = pixelSteps(b, in, pixel);
        auto across = [&](ValueId gx, ValueId gy) { return value(b.mul(half, b.hypot(gx, gy))); };
        const TrianglesInSquare<ir::BuiltValue> cells = trianglesInSquare(
            value(in.genU), value(in.genV), value(e.e1u), value(e.e1v), value(e.e2u), value(e.e2v),
            across(in.genUX, in.genUY), across(in.genVX, in.genVY), across(wx, wy));
        // The 2 x 2 cells nearest the centre where they hold the pixel, else the 3 x 3.
        return value(b.ifThenElse(
            b.lt(members, c(kTriNearRows)),
            [&] { return std::vector<ValueId>{paperOfNearCells(cells).id}; },
            [&] {
                return std::vector<ValueId>{
                    paperOfTriangleRing(cells, 1, paperOfTriangleRing(cells, 0, value(c(0.0)))).id};
            })[0]);
    };
    return edgesInPixel(b, in, half, members, engaged, r);
}

} // namespace

ValueId dotHarmonic(ir::Builder& b, ValueId cells, ValueId r, ValueId kx, ValueId ky) {
    const ValueId dot = b.mul(b.mul(cells, b.constF(kPi)), b.mul(r, r));
    const ValueId z = b.mul(b.mul(r, b.constF(2.0 * kPi)), b.hypot(kx, ky));
    return b.mul(dot, discTransform(ir::BuiltValue(b, z)).id);
}

ValueId boxTransfer(ir::Builder& b, ValueId kx, ValueId ky, const PixelFootprint& pixel) {
    auto sincPi = [&](ValueId f) { return sinc(b, b.mul(f, b.constF(kPi))); };
    const PixelSides f = onPixelSides(b, kx, ky, pixel);
    return b.mul(sincPi(b.mul(f.u, pixel.size)), sincPi(b.mul(f.v, pixel.size)));
}

ValueId dotScreenMean(ir::Builder& b, const LatticeCrowdInputs& in, ValueId r) {
    const ValueId cells = b.abs(b.sub(b.mul(in.genUX, in.genVY), b.mul(in.genUY, in.genVX)));
    const ValueId share = b.mul(b.mul(cells, b.constF(kPi)), b.mul(r, r));
    return b.clamp(b.add(share, dotRipple(b, LatticeKind::Square, in, r)), b.constF(0.0),
                   b.constF(1.0));
}

CrowdEstimate latticeCrowd(ir::Builder& b, LatticeKind kind, const LatticeCrowdInputs& in) {
    const Geometry g = geometryOf(kind);
    auto c = [&](double v) { return b.constF(v); };
    ValueId s = b.max(b.abs(in.spacing), c(1e-9));
    ValueId sx = b.max(b.abs(in.sx), c(1e-9)), sy = b.max(b.abs(in.sy), c(1e-9));
    ValueId t = b.max(in.stroke, c(0.0));
    // The densest rows, in world units: a line <u, n> = c of the unstretched lattice is
    // <w, S^-1 n> = c in the world, so parallel lines h apart in u are h / |S^-1 n| apart.
    ValueId densest = c(1e30);
    for (int k = 0; k < g.families; ++k) {
        const auto [nx, ny] = g.normals[k];
        ValueId apart =
            b.div(b.mul(s, c(g.rowSpacing)), b.hypot(b.div(c(nx), sx), b.div(c(ny), sy)));
        densest = b.min(densest, apart);
    }
    ValueId members = b.div(in.pixel, densest);
    CrowdEstimate out;
    out.engaged = b.smoothstep(c(kCrowdFrom), c(kCrowdFull), members);
    ValueId area = b.mul(b.mul(b.mul(s, s), c(g.cellArea)), b.mul(sx, sy)); // a cell, world
    // The share of the plane strokes `width` wide cover where the cells crowd, a closed form
    // of the lattice's geometry. Points: a disc of radius width / 2 about each, pi width^2 / 4
    // a point, the discs apart. Edges: a stroke along each edge a cell owns, width |S e| s over
    // the cell's area for each direction (a family of lines width |grad f| of the plane),
    // less what the strokes meeting at a corner share, counted by laying the directions over
    // one another as independent (exact for the square's two perpendicular families); for
    // the triangle lattice, whose three lines all meet at its points, exactly: the paper left
    // is each triangle shrunk by width / 2 from its sides, (1 - width / (2 r))^2 of it, r its
    // inradius (2 area / perimeter).
    std::vector<ValueId> lengths;
    for (int k = 0; k < g.families; ++k) {
        const auto [ex, ey] = g.edges[k];
        lengths.push_back(b.mul(s, b.hypot(b.mul(c(ex), sx), b.mul(c(ey), sy))));
    }
    ValueId inradius = ir::kNoValue;
    if (kind == LatticeKind::Triangle) {
        ValueId e1 = b.mul(s, sx);
        ValueId e2 = b.mul(s, b.hypot(b.mul(c(0.5), sx), b.mul(c(kSqrt3 / 2), sy)));
        inradius = b.div(b.mul(b.mul(s, s), b.mul(b.mul(sx, sy), c(kSqrt3 / 2))),
                         b.add(e1, b.mul(c(2.0), e2)));
    }
    const double points = g.points;
    auto independentEdges = [lengths, area](ir::Builder& bb, ValueId width) {
        ValueId blank = bb.constF(1.0);
        for (ValueId length : lengths) {
            ValueId share = bb.min(bb.div(bb.mul(width, length), area), bb.constF(1.0));
            blank = bb.mul(blank, bb.sub(bb.constF(1.0), share));
        }
        return bb.sub(bb.constF(1.0), blank);
    };
    auto exactEdges = [independentEdges, inradius](ir::Builder& bb, ValueId width) {
        if (inradius == ir::kNoValue) return independentEdges(bb, width);
        ValueId left =
            bb.max(bb.sub(bb.constF(1.0), bb.div(width, bb.mul(bb.constF(2.0), inradius))),
                   bb.constF(0.0));
        return bb.sub(bb.constF(1.0), bb.mul(left, left));
    };
    auto dotShare = [points, area](ir::Builder& bb, ValueId width) {
        return bb.div(bb.mul(bb.constF(points * kPi / 4.0), bb.mul(width, width)), area);
    };
    // The honeycomb's edges leave each hexagon shrunk from its sides, whose area is exact
    // (HoneycombInPixel.h): laid as independent, its three directions' strokes, which meet
    // at its corners, were counted light by up to 5% of their ink.
    const bool hexCells = kind == LatticeKind::Hex && in.genU != ir::kNoValue;
    out.share = [exactEdges, dotShare, hexCells, in](ir::Builder& bb, ValueId half) {
        ValueId width = bb.mul(bb.max(half, bb.constF(0.0)), bb.constF(2.0));
        ValueId edges = hexCells ? hexEdgeShare(bb, in, half) : exactEdges(bb, width);
        return bb.min(bb.select(in.drawEdges, edges, dotShare(bb, width)), bb.constF(1.0));
    };
    ValueId dots = dotShare(b, t);
    ValueId edges = hexCells ? hexEdgeShare(b, in, b.mul(t, c(0.5))) : independentEdges(b, t);
    if (kind != LatticeKind::Hex && in.genU != ir::kNoValue) {
        // Whole lines: the edges u, v in Z (and u + v for the triangle lattice), each a phase
        // family averaged over the square pixel as phaseFamilyFields' are (meanInk).
        struct Family {
            ValueId index, gx, gy;
        };
        std::vector<Family> lines{{in.genU, in.genUX, in.genUY}, {in.genV, in.genVX, in.genVY}};
        if (kind == LatticeKind::Triangle)
            lines.push_back(
                {b.add(in.genU, in.genV), b.add(in.genUX, in.genVX), b.add(in.genUY, in.genVY)});
        const PixelFootprint pixel{in.pixel, in.cosTurn, in.sinTurn};
        ValueId half = b.mul(t, c(0.5));
        ValueId paper = c(1.0);
        for (const Family& f : lines) {
            Footprint fp{f.index, b.max(b.hypot(f.gx, f.gy), c(ir::kTiny)), f.gx, f.gy,
                         std::nullopt};
            ValueId mean = meanInk(b, fp, ir::kNoValue, half, pixel);
            paper = b.mul(paper, b.sub(c(1.0), mean));
            out.strands.push_back(fp);
            out.strandMeans.push_back(mean);
        }
        out.strandsOn = in.drawEdges;
        edges = b.sub(c(1.0), paper);
        if (kind == LatticeKind::Triangle) {
            // The triangle lattice's three lines meet at its points, where laid as independent
            // they count the strokes' overlaps as if spread over the plane: light by up to a
            // few percent. Past resolved the exact share above stands in for the independent
            // union's, added as the points crowd (the hand-over `engaged` above), where the
            // resolved strokes' own means are exact but at the points.
            edges =
                b.add(edges, b.mul(out.engaged, b.sub(exactEdges(b, t), independentEdges(b, t))));
        }
        out.engaged = b.select(in.drawEdges, c(1.0), out.engaged);
    }
    out.mean = b.min(b.select(in.drawEdges, edges, dots), c(1.0));
    if (in.genU != ir::kNoValue) {
        // The lattice's shape for the union of two lattices (LatticeUnion.h). The
        // triangle lattice's generators and the honeycomb's centres' are 60 degrees apart, so
        // their reciprocal vectors are 120 degrees apart and their sum is as short; the
        // honeycomb's corners stand at a third and two thirds of its centres' cell.
        CrowdEstimate::LatticeShape p;
        p.u = in.genU, p.ux = in.genUX, p.uy = in.genUY;
        p.v = in.genV, p.vx = in.genVX, p.vy = in.genVY;
        p.sites = {{{0.0, 0.0}}};
        p.shortest = {{{1, 0}}, {{0, 1}}};
        p.radius = b.mul(t, c(0.5));
        p.dots = b.emit(ir::Op::Not, {in.drawEdges});
        if (kind != LatticeKind::Square) p.shortest.push_back({1, 1});
        if (kind == LatticeKind::Triangle) {
            // A rhombic cell's two triangles: (0, 0), (1, 0), (0, 1), where v >= 0, u >= 0 and
            // u + v <= 1, and (1, 0), (0, 1), (1, 1), the same lines' other sides at 1, 1
            // and 1. The first has area 1/2 with b summing to 1.
            p.normals = {{{0.0, -1.0}, {-1.0, 0.0}, {1.0, 1.0}}};
            p.kappa = 0.5;
            p.cells = {{std::array<double, 3>{0.0, 0.0, 1.0}, std::nullopt},
                       {std::nullopt, std::array<double, 3>{1.0, 1.0, -1.0}}};
        } else if (kind == LatticeKind::Hex) {
            // The hexagon about a centre, its corners at +-(1/3, 1/3), +-(-1/3, 2/3) and
            // +-(2/3, -1/3): |u + 2v| <= 1, |2u + v| <= 1 and |u - v| <= 1. Of area 1 (a
            // cell), which is 6 kappa: the triangle with b = (1, 1, 1) has area 9 kappa.
            p.normals = {{{1.0, 2.0}, {-2.0, -1.0}, {1.0, -1.0}}};
            p.kappa = 1.0 / 6.0;
            p.cells = {
                {std::array<double, 3>{1.0, 1.0, 1.0}, std::array<double, 3>{1.0, 1.0, 1.0}}};
        }
        if (kind == LatticeKind::Hex)
            p.sites = {{{1.0 / 3.0, 1.0 / 3.0}}, {{2.0 / 3.0, 2.0 / 3.0}}};
        out.shape = p;
    }
    if (in.distance != ir::kNoValue) {
        ValueId dot = dotsInPixel(b, kind, in, t, out.engaged);
        const ValueId half = b.mul(t, c(0.5));
        const bool triangleCells = kind == LatticeKind::Triangle && in.genU != ir::kNoValue;
        // The triangle lattice's edges meet other layers' strokes by their strands (as whole
        // lines, StrokePairs.h), wherever its own ink is read: its nearest edge's stroke
        // takes no part, as before its ink was read over the pixel.
        if (triangleCells) out.strokesCrowded = out.engaged;
        ValueId edge =
            hexCells ? hexEdgesInPixel(b, in, half, members, out.engaged)
            : triangleCells
                ? triangleEdgesInPixel(b, in, half, members, b.min(edges, c(1.0)), out.engaged)
                : distanceInk(b, in.distance, half, ir::kNoValue, ir::kNoValue,
                              PixelFootprint{in.pixel, in.cosTurn, in.sinTurn});
        out.nearest = b.select(in.drawEdges, edge, dot);
        if (in.genU != ir::kNoValue) {
            // Where the share is drawn, the box filter's ripple about it (behind a branch):
            // the dots', and the honeycomb's edges'. The square and triangle lattices' edges
            // are whole lines, each averaged over the pixel as it is.
            auto none = [&] { return std::vector<ValueId>{c(0.0)}; };
            const ValueId ripple = b.ifThenElse(
                b.gt(out.engaged, c(0.0)),
                [&] {
                    return b.ifThenElse(
                        in.drawEdges,
                        [&] {
                            if (!hexCells) return none();
                            return std::vector<ValueId>{hexEdgeRipple(b, in, half)};
                        },
                        [&] { return std::vector<ValueId>{dotRipple(b, kind, in, half)}; });
                },
                none)[0];
            out.mean = b.clamp(b.add(out.mean, ripple), c(0.0), c(1.0));
        }
        if (hexCells)
            out.strokesCrowded = b.select(
                in.drawEdges, b.smoothstep(c(kCrowdFrom), c(kCrowdFull), members), out.engaged);
    }
    return out;
}

} // namespace moire::lower
