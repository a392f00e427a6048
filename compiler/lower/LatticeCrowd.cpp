#include "compiler/lower/LatticeCrowd.h"

#include "compiler/ir/Semantics.h"
#include "compiler/lower/Prefilter.h"

#include <array>
#include <cmath>
#include <numbers>
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

} // namespace

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
    // Points: a disc of radius t / 2 about each, pi t^2 / 4 a point, the discs apart.
    ValueId dots = b.div(b.mul(c(g.points * kPi / 4.0), b.mul(t, t)), area);
    // Edges: a stroke t wide along each edge a cell owns, less what the strokes meeting at a
    // corner share, counted by laying the edge directions over one another as independent
    // (exact for the square's two perpendicular families, first order at three).
    ValueId blank = c(1.0);
    for (int k = 0; k < g.families; ++k) {
        const auto [ex, ey] = g.edges[k];
        ValueId length = b.mul(s, b.hypot(b.mul(c(ex), sx), b.mul(c(ey), sy)));
        ValueId share = b.min(b.div(b.mul(t, length), area), c(1.0));
        blank = b.mul(blank, b.sub(c(1.0), share));
    }
    ValueId edges = b.sub(c(1.0), blank);
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
            // few percent. Past resolved, the exact share is a closed form: the paper left is
            // each triangle shrunk by t/2 from its sides, (1 - t / (2 r))^2 of it, r its
            // inradius (2 area / perimeter); the independent union's share in that limit is
            // 1 - prod(1 - t |grad f_i|). Their difference is added as the points crowd (the
            // hand-over `engaged` above), where the resolved strokes' own means are exact
            // but at the points.
            ValueId e1 = b.mul(s, sx);
            ValueId e2 = b.mul(s, b.hypot(b.mul(c(0.5), sx), b.mul(c(kSqrt3 / 2), sy)));
            ValueId inradius = b.div(b.mul(b.mul(s, s), b.mul(b.mul(sx, sy), c(kSqrt3 / 2))),
                                     b.add(e1, b.mul(c(2.0), e2)));
            ValueId left = b.max(b.sub(c(1.0), b.div(t, b.mul(c(2.0), inradius))), c(0.0));
            ValueId spread = c(1.0);
            for (const Family& f : lines)
                spread = b.mul(spread, b.sub(c(1.0), b.min(b.mul(t, b.hypot(f.gx, f.gy)), c(1.0))));
            edges = b.add(edges, b.mul(out.engaged, b.sub(spread, b.mul(left, left))));
        }
        out.engaged = b.select(in.drawEdges, c(1.0), out.engaged);
    }
    out.mean = b.min(b.select(in.drawEdges, edges, dots), c(1.0));
    return out;
}

} // namespace moire::lower
