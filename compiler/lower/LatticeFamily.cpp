// The three builtin lattices (spec §3.6), as straight-line IR: rounding, a handful of
// candidate distances and selects, no loops and no branches.
//
// Frames. The layer hands us p = (px, py) in its own frame. The lattice is built in an
// unstretched frame u = (px / sx, py / sy) with `spacing` s between neighbouring points, and
// drawn stretched by S = diag(sx, sy): lattice point z sits at S z in the layer's frame.
// Rounding happens in u (that is, in the stretched lattice's own basis, as the spec says);
// every distance is measured in the layer's frame, i.e. in world units.
//
// Which point is "nearest" under a stretch. Rounding in u finds the point nearest in the
// unstretched metric. Under an anisotropic S that is often not the point nearest in world
// units: a stretched A2 lattice's Voronoi cell is no longer S times the hexagon rounding
// works in, and at scale (3, 0.5) the rounded point can be five times farther than the
// nearest one. A dot drawn at a point would then be clipped flat where the next point's
// rounding cell begins. So the rounded point is only the start: the vertex distance is the
// world distance to the nearest of a few candidates around it, and the index is that
// candidate's. Which candidates suffice, and why, is said at each kind below; the tests
// check every kind against an exhaustive search at scales from 1:10 to 10:1.
//
// Edges need no such care: each edge family is a set of straight lines or the sides of a
// convex cell, and a straight side's world distance is its residual in u divided by
// |S^-1 n| = |(n_x / sx, n_y / sy)| for its unit normal n (the per-facet division of §3.6;
// S maps the line <u, n> = c to <w, S^-1 n> = c). That is exact under any scale.
#include "compiler/lower/LatticeFamily.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lower/LatticeCrowd.h"

#include <cmath>
#include <numbers>

namespace moire::lower {

namespace {

using ir::ValueId;

constexpr double kSqrt3 = std::numbers::sqrt3;
constexpr double kPi = std::numbers::pi;

// What every kind needs: the point in both frames, the spacing and the stretch.
struct LatticeFrame {
    ValueId px, py; // the layer's frame (world units)
    ValueId ux, uy; // unstretched: (px / sx, py / sy)
    ValueId s, sx, sy;
    bool generators = true; // also the generators' index fields (not for the envelope's taps)
};

// A running minimum over candidate points: the world distance and the integer pair of the
// nearest so far, and the distance of the next nearest (`second`, kNoMember before a second
// candidate). Strict `<` keeps the earlier candidate on a tie, so the rounded point wins ties
// and the index never flickers between equidistant points for no reason.
struct Nearest {
    ValueId d, i, j;
    ValueId second;
};
void consider(ir::Builder& b, Nearest& best, ValueId d, ValueId i, ValueId j) {
    ValueId closer = b.lt(d, best.d);
    best.second = b.select(closer, best.d, b.min(best.second, d));
    best.d = b.select(closer, d, best.d);
    best.i = b.select(closer, i, best.i);
    best.j = b.select(closer, j, best.j);
}

// World distance from p to the line family {<u, n> = c + k h} (n a unit normal in u, k any
// integer): the residual to the nearest line in u, over |S^-1 n|.
ValueId lineFamilyDistance(ir::Builder& b, const LatticeFrame& f, double nx, double ny, ValueId h) {
    ValueId along = b.add(b.mul(f.ux, b.constF(nx)), b.mul(f.uy, b.constF(ny)));
    ValueId residual = b.abs(b.wrap(along, h));
    return b.div(residual, b.hypot(b.div(b.constF(nx), f.sx), b.div(b.constF(ny), f.sy)));
}

// The nearest point of the A2 lattice with basis a1 = step (1, 0), a2 = step (1/2, sqrt3/2)
// to (x, y), as its coordinates (i, j). Conway and Sloane's rule for A2: with fractional
// coordinates (u, v), the three numbers (u, v, -u-v) are the point's coordinates in the
// plane x + y + z = 0 of R^3, where A2 is the integer points and the metric is the plane's
// own (|i a1 + j a2|^2 = i^2 + ij + j^2 is half of i^2 + j^2 + (i+j)^2). Round all three;
// the rounded sum is -1, 0 or 1, and when it is not 0 the coordinate that moved the most is
// the one to move back, which is the same as recomputing it from the other two.
// Returns the continuous coordinates (u, v) too: the lattice's generators (setGenerators).
struct A2Point {
    ValueId i, j; // the nearest point
    ValueId u, v; // (x, y) in the basis, before rounding
};
A2Point a2Round(ir::Builder& b, ValueId x, ValueId y, ValueId step) {
    ValueId v = b.div(b.mul(y, b.constF(2.0 / kSqrt3)), step);
    ValueId u = b.sub(b.div(x, step), b.mul(v, b.constF(0.5)));
    ValueId w = b.neg(b.add(u, v));
    ValueId ru = b.round(u), rv = b.round(v), rw = b.round(w);
    ValueId du = b.abs(b.sub(ru, u)), dv = b.abs(b.sub(rv, v)), dw = b.abs(b.sub(rw, w));
    // u moved the most: u = -v - w. Else v moved more than w: v = -u - w. (Else w gets the
    // blame, and since only (u, v) is returned, nothing needs recomputing.)
    ValueId fixU = b.emit(ir::Op::And, {b.gt(du, dv), b.gt(du, dw)});
    ValueId fixV = b.emit(ir::Op::And, {b.emit(ir::Op::Not, {fixU}), b.gt(dv, dw)});
    ValueId i = b.select(fixU, b.neg(b.add(rv, rw)), ru);
    ValueId j = b.select(fixV, b.neg(b.add(ru, rw)), rv);
    return {i, j, u, v};
}

// The two generators' index fields (spec §3.6, §4.1): the continuous coordinates (u, v) of
// the point in the basis that the pattern repeats by, whose integer level sets are the
// lattice's two generating row families. Their gradients come from forward-mode AD, as a
// phase family's do, not from the basis: the layer's frame (origin, a rotation that may be
// a field of x and y, the viewer's motion) lies between the world and (px, py), and AD
// carries all of it. Nothing the render draws reads them, so a plain frame does not
// change; the character search does (Characters.h).
void setGenerators(ir::Builder& b, const LatticeFrame& f, LayerFields& out, ValueId u, ValueId v) {
    if (!f.generators) return;
    out.genU = u;
    out.genUX = b.emit(ir::Op::DerivX, {u});
    out.genUY = b.emit(ir::Op::DerivY, {u});
    out.genV = v;
    out.genVX = b.emit(ir::Op::DerivX, {v});
    out.genVY = b.emit(ir::Op::DerivY, {v});
}

// Square lattice: points at s (i, j). Stretched, it is a rectangular lattice, whose Voronoi
// cells are the rectangles that rounding each axis finds, so rounding is already the world-
// nearest point at any scale. Edges are the grid lines through the points (the sides of
// the square cells whose corners the points are), x = s sx i and y = s sy j.
// Generators: (u, v) = (px / (s sx), py / (s sy)), the point's coordinates on the grid.
LayerFields squareLattice(ir::Builder& b, const LatticeFrame& f, ValueId drawEdges) {
    ValueId u = b.div(f.ux, f.s), v = b.div(f.uy, f.s);
    ValueId i = b.round(u), j = b.round(v);
    ValueId ex = b.mul(f.sx, f.s), ey = b.mul(f.sy, f.s); // the world steps
    ValueId rx = b.sub(f.px, b.mul(ex, i)), ry = b.sub(f.py, b.mul(ey, j));
    ValueId vertex = b.hypot(rx, ry);
    // The next nearest point: the rounded one's neighbour across the nearer side of its
    // rectangle, along x or along y.
    ValueId alongX = b.hypot(b.sub(b.abs(rx), ex), ry), alongY = b.hypot(rx, b.sub(b.abs(ry), ey));
    ValueId edge =
        b.min(lineFamilyDistance(b, f, 1.0, 0.0, f.s), lineFamilyDistance(b, f, 0.0, 1.0, f.s));
    LayerFields out;
    out.distance = b.select(drawEdges, edge, vertex);
    out.index = i;
    out.aux0 = j;
    out.runnerUp = b.min(alongX, alongY);
    setGenerators(b, f, out, u, v);
    return out;
}

// Triangle lattice: A2, point (i, j) at s (i + j/2, j sqrt3/2), so neighbours are s apart
// along 0, 60 and 120 degrees. Cube rounding in u finds the nearest point exactly when the
// scale is isotropic. Stretched, the lattice's Delaunay triangles are either the stretched
// equilateral triangles (when none is obtuse, sy/sx >= 1/sqrt3) or the flipped pairs of
// them; in both cases a point's rounding cell lies inside the triangles around the rounded
// point z, and the nearest lattice point of a point in one of those triangles is one of
// its corners or the point across its longest side, all of them z or a neighbour of z
// (the apex case: with z the obtuse corner, the point across is 2 rows away, but its
// bisector lies beyond the part of z's rounding cell in that triangle). So z and its six
// neighbours hold the world-nearest point at every scale.
// Edges: the triangles' sides, three line families through the points, each h = s sqrt3/2
// apart, with normals at 90, 150 and 30 degrees: the level sets of the generators v, u and
// u + v (the point's coordinates in the basis (a1, a2)).
LayerFields triangleLattice(ir::Builder& b, const LatticeFrame& f, ValueId drawEdges) {
    auto [i, j, u, v] = a2Round(b, f.ux, f.uy, f.s);
    // The offset from the rounded point to p, in world units, and the world steps to its
    // neighbours: a1 = S s (1, 0), a2 = S s (1/2, sqrt3/2), and a2 - a1.
    ValueId half = b.constF(0.5);
    ValueId stepX = b.mul(f.sx, f.s), stepY = b.mul(f.sy, f.s);
    ValueId rx = b.sub(f.px, b.mul(stepX, b.add(i, b.mul(j, half))));
    ValueId ry = b.sub(f.py, b.mul(stepY, b.mul(j, b.constF(kSqrt3 / 2))));
    ValueId a2x = b.mul(stepX, half), a2y = b.mul(stepY, b.constF(kSqrt3 / 2));
    struct Step {
        ValueId dx, dy; // world offset of the neighbour
        double di, dj;  // its coordinate offset
    };
    const Step steps[] = {
        {stepX, b.constF(0.0), 1, 0}, {a2x, a2y, 0, 1}, {b.sub(a2x, stepX), a2y, -1, 1}};
    Nearest best{b.hypot(rx, ry), i, j, b.constF(kNoMember)};
    for (const Step& st : steps) {
        for (double sign : {1.0, -1.0}) {
            ValueId sg = b.constF(sign);
            ValueId d = b.hypot(b.sub(rx, b.mul(sg, st.dx)), b.sub(ry, b.mul(sg, st.dy)));
            consider(b, best, d, b.add(i, b.constF(sign * st.di)),
                     b.add(j, b.constF(sign * st.dj)));
        }
    }
    ValueId h = b.mul(f.s, b.constF(kSqrt3 / 2));
    ValueId edge = b.min(lineFamilyDistance(b, f, 0.0, 1.0, h),
                         b.min(lineFamilyDistance(b, f, -kSqrt3 / 2, 0.5, h),
                               lineFamilyDistance(b, f, kSqrt3 / 2, 0.5, h)));
    LayerFields out;
    out.distance = b.select(drawEdges, edge, best.d);
    out.index = best.i;
    out.aux0 = best.j;
    out.runnerUp = best.second;
    setGenerators(b, f, out, u, v);
    return out;
}

// Hex lattice: a honeycomb of regular hexagons of side s, flat sides facing +-x as in the
// stdlib's `hexagons` family. The hexagons' centres are an A2 lattice of spacing s sqrt3
// (basis c1 = s sqrt3 (1, 0), c2 = s sqrt3 (1/2, sqrt3/2)) and each hexagon is its centre's
// Voronoi cell, so cube rounding in u finds the hexagon holding p, and q = u - centre lies
// inside it.
// Points: the hexagons' corners, at s (cos, sin)(30 + 60k degrees) from the centre. They
// are indexed by their coordinates in the A2 lattice they belong to, of spacing s with
// basis l1 = s (cos 30, sin 30), l2 = s (0, 1) (centres are the points of that lattice
// with m - n divisible by 3: c1 = 2 l1 - l2, c2 = l1 + l2). The nearest corner of a point's
// own (stretched) hexagon is its nearest honeycomb vertex: unstretched, the vertices'
// Voronoi cells are the triangles between three centres, which tile each hexagon; stretched,
// any vertex outside the hexagon is reached through one of its sides, and the nearest
// vertex to a point of a side is one of that side's ends. So the six corners are the only
// candidates, at any scale.
// Edges: the hexagon's sides, as a support form. Inside a convex cell the distance to its
// boundary is the least distance to a side's line, (apothem - <q, n_k>) / |S^-1 n_k| over
// the six outward normals n_k at 60k degrees (apothem s sqrt3/2), and since p is inside
// its own cell, no other hexagon's side can be nearer. Opposite sides share |S^-1 n|, so
// each pair is one term with |<q, n_k>|.
// Generators: the point's coordinates in the centres' basis (c1, c2). The honeycomb repeats
// by the centres' lattice, not by the corners' (whose index the point carries), so that is
// the lattice whose integer combinations are the pattern's harmonics.
LayerFields hexLattice(ir::Builder& b, const LatticeFrame& f, ValueId drawEdges) {
    ValueId pitch = b.mul(f.s, b.constF(kSqrt3)); // between centres
    auto [ci, cj, cu, cv] = a2Round(b, f.ux, f.uy, pitch);
    ValueId cx = b.mul(pitch, b.add(ci, b.mul(cj, b.constF(0.5))));
    ValueId cy = b.mul(pitch, b.mul(cj, b.constF(kSqrt3 / 2)));
    ValueId qx = b.sub(f.ux, cx), qy = b.sub(f.uy, cy); // in u, inside the hexagon

    // The centre in the corners' lattice: ci c1 + cj c2 = (2 ci + cj) l1 + (cj - ci) l2.
    ValueId m0 = b.add(b.add(ci, ci), cj), n0 = b.sub(cj, ci);
    struct Corner {
        double angleDeg;
        double dm, dn; // its offset in (l1, l2)
    };
    static constexpr Corner kCorners[] = {{30, 1, 0},   {90, 0, 1},   {150, -1, 1},
                                          {210, -1, 0}, {270, 0, -1}, {330, 1, -1}};
    auto corner = [&](const Corner& c) {
        double a = c.angleDeg * kPi / 180.0;
        // World offset from the corner to p: S (q - s (cos a, sin a)).
        ValueId dx = b.mul(f.sx, b.sub(qx, b.mul(f.s, b.constF(std::cos(a)))));
        ValueId dy = b.mul(f.sy, b.sub(qy, b.mul(f.s, b.constF(std::sin(a)))));
        return Nearest{b.hypot(dx, dy), b.add(m0, b.constF(c.dm)), b.add(n0, b.constF(c.dn)),
                       b.constF(kNoMember)};
    };
    Nearest best = corner(kCorners[0]);
    for (int k = 1; k < 6; ++k) {
        Nearest c = corner(kCorners[k]);
        consider(b, best, c.d, c.i, c.j);
    }

    ValueId apothem = b.mul(f.s, b.constF(kSqrt3 / 2));
    ValueId edge = ir::kNoValue;
    for (int k = 0; k < 3; ++k) {
        double a = k * kPi / 3.0, nx = std::cos(a), ny = std::sin(a);
        ValueId reach = b.abs(b.add(b.mul(qx, b.constF(nx)), b.mul(qy, b.constF(ny))));
        ValueId gap = b.div(b.sub(apothem, reach),
                            b.hypot(b.div(b.constF(nx), f.sx), b.div(b.constF(ny), f.sy)));
        edge = k == 0 ? gap : b.min(edge, gap);
    }
    LayerFields out;
    out.distance = b.select(drawEdges, edge, best.d);
    out.index = best.i;
    out.aux0 = best.j;
    out.runnerUp = best.second;
    setGenerators(b, f, out, cu, cv);
    return out;
}

// The fields at `in`, the generators' index fields with them when `generators`.
LayerFields solve(ir::Builder& b, LatticeKind kind, const LatticeInputs& in, bool generators) {
    MOIRE_CHECK(!in.scale.empty() && in.scale.size() <= 2,
                "a lattice's scale is one or two numbers");
    // All three point sets are symmetric under x -> -x and y -> -y, so a negative spacing or
    // scale draws the same lattice; taking magnitudes keeps the apothem and the per-facet
    // norms positive. A zero scale divides by zero, and the resulting NaN coverage is no ink.
    LatticeFrame f;
    f.px = in.px;
    f.py = in.py;
    f.s = b.abs(in.spacing);
    f.sx = b.abs(in.scale[0]);
    f.sy = b.abs(in.scale.size() == 2 ? in.scale[1] : in.scale[0]);
    f.ux = b.div(in.px, f.sx);
    f.uy = b.div(in.py, f.sy);
    f.generators = generators;
    ValueId drawEdges = b.emit(ir::Op::Ne, {in.edges, b.constF(0.0)});
    switch (kind) {
    case LatticeKind::Square:
        return squareLattice(b, f, drawEdges);
    case LatticeKind::Triangle:
        return triangleLattice(b, f, drawEdges);
    case LatticeKind::Hex:
        return hexLattice(b, f, drawEdges);
    }
    MOIRE_ICE("unknown lattice kind");
}

// The generating steps of each kind in the unstretched frame, per unit of spacing: the basis
// whose coordinates are the generators (u, v) of setGenerators.
struct Basis {
    double c1x, c1y, c2x, c2y;
};
Basis basisOf(LatticeKind kind) {
    switch (kind) {
    case LatticeKind::Square:
        return {1, 0, 0, 1};
    case LatticeKind::Triangle:
        return {1, 0, 0.5, kSqrt3 / 2};
    case LatticeKind::Hex: // the centres', s sqrt3 apart
        return {kSqrt3, 0, kSqrt3 / 2, 1.5};
    }
    MOIRE_ICE("unknown lattice kind");
}

} // namespace

LayerFields latticeFields(ir::Builder& b, LatticeKind kind, const LatticeInputs& in) {
    LayerFields out = solve(b, kind, in, true);
    // The phase sample (Envelope.h): the lattice advanced by (du, dv) is the lattice at the
    // point moved by du c1 + dv c2 (stretched into the layer's frame), solved there anew.
    const Basis c = basisOf(kind);
    out.sample.z = out.distance;
    out.sample.up = out.sample.down = b.constF(kNoMember);
    out.sample.floor = b.constF(0.0);
    LatticeInputs at = in;
    auto moved = [c, at, kind](ir::Builder& bb, ValueId du, ValueId dv) {
        ValueId s = bb.abs(at.spacing);
        ValueId sx = at.scale[0], sy = at.scale.size() == 2 ? at.scale[1] : at.scale[0];
        auto step = [&](double a, double d) {
            return bb.mul(s, bb.add(bb.mul(du, bb.constF(a)), bb.mul(dv, bb.constF(d))));
        };
        LatticeInputs there = at;
        there.px = bb.add(at.px, bb.mul(bb.abs(sx), step(c.c1x, c.c2x)));
        there.py = bb.add(at.py, bb.mul(bb.abs(sy), step(c.c1y, c.c2y)));
        return solve(bb, kind, there, false).distance;
    };
    ValueId sx = b.abs(in.scale[0]), sy = b.abs(in.scale.size() == 2 ? in.scale[1] : in.scale[0]);
    ValueId cell =
        b.mul(b.mul(b.abs(in.spacing), b.constF(std::hypot(c.c1x, c.c1y))), b.sqrt(b.mul(sx, sy)));
    ValueId dots = b.emit(ir::Op::Eq, {in.edges, b.constF(0.0)});
    out.sample.lattice = LatticeSample{moved, cell, dots};
    return out;
}

FamilyBuilder latticeBuilder(LatticeKind kind) {
    return [kind](ir::Builder& b, const FamilyInputs& in) {
        MOIRE_CHECK(in.params.size() == 2, "a lattice takes (scale, edges)");
        const LayerFrame& at = in.at;
        LayerFields out =
            latticeFields(b, kind, {at.qx, at.qy, at.spacing, in.params[0], in.params[1][0]});
        // Under the mean filter, where its members crowd, the share of the plane they cover
        // (LatticeCrowd.h). Not where a field is encoded: it moves the members by its own
        // gradient, which the closed form does not know.
        if (in.crowd && in.enc.field == ir::kNoValue) {
            const std::vector<ValueId>& scale = in.params[0];
            LatticeCrowdInputs crowd;
            crowd.spacing = at.spacing;
            crowd.sx = scale[0];
            crowd.sy = scale.size() == 2 ? scale[1] : scale[0];
            crowd.stroke = in.layerProp("stroke")[0];
            crowd.pixel = b.div(in.band.a, b.constF(kAntialiasPixels));
            crowd.drawEdges = b.emit(ir::Op::Ne, {in.params[1][0], b.constF(0.0)});
            crowd.genU = out.genU, crowd.genUX = out.genUX, crowd.genUY = out.genUY;
            crowd.genV = out.genV, crowd.genVX = out.genVX, crowd.genVY = out.genVY;
            crowd.cosTurn = in.cosTurn;
            crowd.sinTurn = in.sinTurn;
            crowd.distance = out.distance;
            out.crowd = latticeCrowd(b, kind, crowd);
        }
        return out;
    };
}

} // namespace moire::lower
