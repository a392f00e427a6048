// The triangle lattice's edges over the square pixel, exactly (docs/filtering.md, "The triangle
// lattice's edges over the pixel"). Its edges are three families of whole lines, u, v and
// u + v whole, each averaged over the pixel in closed form; laid as independent inks they miss
// what the strokes share where the three meet, which the pairs' covariances read only for
// strokes resolved apart, and the crowded share only where many points fall in a pixel.
// Between, with the rows about a pixel apart, a pixel holds a few of the lattice's points and
// both readings were up to 0.03 off. The paper the strokes leave is each triangle shrunk by
// the stroke's half-width from its three sides, a triangle again, whose area within the pixel
// is a sum over its sides in closed form (HoneycombInPixel.h, polygonInSquare): exact while
// the triangles taken hold every point of the pixel.
#pragma once

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/HoneycombInPixel.h"

#include <array>
#include <cmath>

namespace moire::lower {

// Where the 3 x 3 cells about the pixel's centre hold the whole pixel, by rows of the u or v
// lines a pixel. A pixel reaches 0.71 pixel from its centre, under sqrt(1/2) of an index step
// a row a pixel, and the centre's own cell begins anywhere in the step before it, so one cell
// to either side holds the pixel up to sqrt2 rows a pixel (a little less, to spare). Past it
// the lattice's points crowd, and their overlaps are read by the share (LatticeCrowd.cpp).
constexpr double kTriOneBlockRows = 1.4;
// Where the 2 x 2 cells nearest the pixel's centre hold it (paperOfNearCells): the pixel spans
// under half an index step to either side, to sqrt(1/2) rows a pixel.
constexpr double kTriNearRows = 0.7;

// The triangle lattice's cells about the square pixel [-1/2, 1/2]^2: (u, v) the generators at
// the pixel's centre, e1 and e2 their steps (the offsets that advance u and v by 1) along the
// pixel's sides in pixels, and each family's stroke in index units, a = h |grad u|, b = h
// |grad v|, c = h |grad (u + v)|. A cell [0, 1]^2 of (u, v) holds two triangles, u + v below 1
// and above; shrunk, the lower is u >= a, v >= b, u + v <= 1 - c, corners (a, b), (a + t, b),
// (a, b + t), and the upper its reflection through the cell's centre, t = 1 - a - b - c their legs
// (none where t <= 0). Both run counterclockwise in (u, v), so the steps' turn gives every
// triangle one sense. `fu, fv` is the pixel's centre within its cell.
template <class T>
struct TrianglesInSquare {
    T fu, fv, e1u, e1v, e2u, e2v;
    std::array<std::array<std::array<T, 2>, 3>, 2> shapes;
};
template <class T>
TrianglesInSquare<T> trianglesInSquare(T u, T v, T e1u, T e1v, T e2u, T e2v, T a, T b, T c) {
    using std::floor;
    using std::max;
    const T zero = ir::literal(u, 0.0), one = ir::literal(u, 1.0);
    const T t = max(one - a - b - c, zero);
    return {u - floor(u),
            v - floor(v),
            e1u,
            e1v,
            e2u,
            e2v,
            {{{{{a, b}, {a + t, b}, {a, b + t}}},
              {{{one - a, one - b}, {one - a - t, one - b}, {one - a, one - b - t}}}}}};
}

// The paper the two triangles of the cell (i, j) cells from the centre's leave within the
// pixel, each signed alike.
template <class T, class N>
T paperOfTriangleCell(const TrianglesInSquare<T>& h, N i, N j) {
    T sum = ir::literal(h.fu, 0.0);
    for (const auto& shape : h.shapes) {
        std::array<std::array<T, 2>, 3> moved;
        for (size_t k = 0; k < 3; ++k) {
            // The corner's index offset from the pixel's centre, through the steps.
            const T du = shape[k][0] + i - h.fu, dv = shape[k][1] + j - h.fv;
            moved[k] = {du * h.e1u + dv * h.e2u, du * h.e1v + dv * h.e2v};
        }
        sum = sum + polygonInSquare(moved);
    }
    return sum;
}

// `sum` plus the paper the cells `ring` cells from the centre's (the cells (i, j) with
// max(|i|, |j|) = ring) leave within the pixel.
template <class T>
T paperOfTriangleRing(const TrianglesInSquare<T>& h, int ring, T sum) {
    using std::abs;
    using std::max;
    for (int i = -ring; i <= ring; ++i)
        for (int j = -ring; j <= ring; ++j)
            if (max(abs(i), abs(j)) == ring)
                sum = sum + paperOfTriangleCell(h, double(i), double(j));
    return sum;
}

// The paper the 2 x 2 cells nearest the pixel's centre leave within it: the two to either
// side of the whole u nearest it, and of the whole v. Where the pixel spans under half an
// index step to either side of its centre (kTriNearRows), they hold it.
template <class T>
T paperOfNearCells(const TrianglesInSquare<T>& h) {
    const T one = ir::literal(h.fu, 1.0), zero = ir::literal(h.fu, 0.0);
    const T iu = ir::select(ir::lessThan(h.fu, ir::literal(h.fu, 0.5)), zero - one, zero);
    const T iv = ir::select(ir::lessThan(h.fv, ir::literal(h.fu, 0.5)), zero - one, zero);
    T sum = zero;
    for (const T& i : {iu, iu + one})
        for (const T& j : {iv, iv + one}) sum = sum + paperOfTriangleCell(h, i, j);
    return sum;
}

// The paper the triangle lattice's strokes leave within the square pixel (its share of the
// pixel, 0 to 1), from the cells up to `reach` from the centre's: 1 within kTriOneBlockRows,
// n within about n sqrt2 rows a pixel.
template <class T>
T trianglePaperInSquare(T u, T v, T e1u, T e1v, T e2u, T e2v, T a, T b, T c, int reach) {
    const TrianglesInSquare<T> h = trianglesInSquare(u, v, e1u, e1v, e2u, e2v, a, b, c);
    T sum = ir::literal(u, 0.0);
    for (int ring = 0; ring <= reach; ++ring) sum = paperOfTriangleRing(h, ring, sum);
    return paperShare(sum);
}

} // namespace moire::lower
