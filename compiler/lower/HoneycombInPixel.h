// The honeycomb's edges over the square pixel, exactly (docs/filtering.md, "A honeycomb's edges
// over the pixel"). The square and triangle lattices' edges are whole lines, each a phase
// family averaged over the pixel in closed form; a honeycomb's are not, and read by the
// distance to its nearest edge a pixel that reaches a corner, where three edges meet, or two
// edges a cell apart, counted one stroke. Its ink is instead 1 less the paper its strokes
// leave: each hexagon shrunk by the stroke's half-width from its sides, a convex polygon, whose
// area within the pixel is a sum over its sides in closed form. The hexagon about the pixel's
// centre and its six neighbours reach every point within a side's length of it, which holds
// the whole pixel while a side is over 0.71 pixel long, and with the next ring twice that;
// finer than that the compose step hands over to the paper's share of the plane
// (LatticeCrowd.cpp).
#pragma once

#include "compiler/ir/BuiltValue.h"

#include <array>
#include <cmath>

namespace moire::lower {

// One side's share of a convex polygon's area within the square [-1/2, 1/2]^2, the side
// running from (xa, ya) to (xb, yb). Along a row y of the square a polygon is the span right
// of its sides that run down and left of those that run up (counterclockwise), so its area
// within the square is the sum over its sides of -sign(dy) times the integral, over the side's
// rows within the square, of the square's length right of the side, clamp(1/2 - x(y), 0, 1).
// x(y) is linear along the side, so that integral is the clamp's mean over [t0, t1] (t = 1/2 -
// x at the side's ends, clipped to the square's rows) times the rows it spans: (F(t1) -
// F(t0)) / (t1 - t0), F(t) = clamp(t, 0, 1)^2 / 2 + max(t - 1, 0) the clamp's integral, or the
// clamp at the middle where t1 and t0 are too close to divide by (the clamp is linear there
// but where a kink falls within 1e-3, which moves the area by less than 1e-3 of a row).
template <class T>
T sideInSquare(T xa, T ya, T xb, T yb) {
    using ir::literal;
    using std::abs;
    using std::max;
    using std::min;
    const T zero = literal(xa, 0.0), half = literal(xa, 0.5), one = literal(xa, 1.0);
    const T dy = yb - ya;
    const auto flat = ir::lessThan(abs(dy), literal(xa, 1e-9));
    const T slope = ir::select(flat, zero, (xb - xa) / ir::select(flat, one, dy));
    const T y0 = min(max(ya, -half), half), y1 = min(max(yb, -half), half);
    const T t0 = half - (xa + (y0 - ya) * slope), t1 = half - (xa + (y1 - ya) * slope);
    auto clamp = [&](T t) { return min(max(t, zero), one); };
    auto integral = [&](T t) {
        const T c = clamp(t);
        return c * c * 0.5 + max(t - 1.0, zero);
    };
    const T dt = t1 - t0;
    const auto close = ir::lessThan(abs(dt), literal(xa, 1e-3));
    const T mean = ir::select(close, clamp((t0 + t1) * 0.5),
                              (integral(t1) - integral(t0)) / ir::select(close, one, dt));
    return zero - (y1 - y0) * mean;
}

// The area within the square [-1/2, 1/2]^2 of a convex polygon, its N corners in order: the sum
// of its sides' shares (sideInSquare), positive for a counterclockwise polygon and negative
// for a clockwise one.
template <class T, size_t N>
T polygonInSquare(const std::array<std::array<T, 2>, N>& corners) {
    T sum = ir::literal(corners[0][0], 0.0);
    for (size_t k = 0; k < N; ++k) {
        const auto& a = corners[k];
        const auto& z = corners[(k + 1) % N];
        sum = sum + sideInSquare(a[0], a[1], z[0], z[1]);
    }
    return sum;
}

// The area of a convex polygon within the band y0 <= y <= y1 (y0 <= y1), its corners in
// order: along each row a polygon is the span between its sides, so by Green's theorem the
// area is the integral of x dy around it, here over the rows within the band, each side's
// share (y1' - y0') (x(y0') + x(y1')) / 2 with its ends held to the band. Positive for a
// counterclockwise polygon, negative for a clockwise one.
template <class T, size_t N>
T polygonInBand(const std::array<std::array<T, 2>, N>& corners, T y0, T y1) {
    using std::abs;
    using std::max;
    using std::min;
    const T zero = ir::literal(y0, 0.0), one = ir::literal(y0, 1.0);
    T sum = zero;
    for (size_t k = 0; k < N; ++k) {
        const auto& a = corners[k];
        const auto& z = corners[(k + 1) % N];
        const T dy = z[1] - a[1];
        const auto flat = ir::lessThan(abs(dy), ir::literal(y0, 1e-12));
        const T slope = ir::select(flat, zero, (z[0] - a[0]) / ir::select(flat, one, dy));
        const T ya = min(max(a[1], y0), y1), yb = min(max(z[1], y0), y1);
        const T xa = a[0] + (ya - a[1]) * slope, xb = a[0] + (yb - a[1]) * slope;
        sum = sum + (yb - ya) * (xa + xb) * 0.5;
    }
    return sum;
}

// The area of a disc of radius r about (cx, cy) within a polygon, its corners in order: the
// sum over its sides of the disc's share of the triangle the side makes with the disc's
// centre. Along a side from a to z (offsets from the centre) the part within the circle, from
// a + t1 (z - a) to a + t2 (z - a) (t1, t2 the roots of |a + t (z - a)| = r held to [0, 1],
// both 1 where the line misses the circle), gives the triangle's (p1 x p2) / 2, and the parts
// outside it the sectors r^2 theta / 2 of the angles they span, atan2(p x q, p . q). Positive
// for a counterclockwise polygon, negative for a clockwise one. A template over IR values in
// the kernel, over double in the tests.
template <class T, size_t N>
T discInPolygon(const std::array<std::array<T, 2>, N>& corners, T cx, T cy, T r) {
    using std::atan2;
    using std::max;
    using std::min;
    using std::sqrt;
    const T zero = ir::literal(cx, 0.0), one = ir::literal(cx, 1.0);
    const T rr = max(r, zero) * max(r, zero);
    auto cross = [](const std::array<T, 2>& p, const std::array<T, 2>& q) {
        return p[0] * q[1] - p[1] * q[0];
    };
    auto sector = [&](const std::array<T, 2>& p, const std::array<T, 2>& q) {
        return rr * atan2(cross(p, q), p[0] * q[0] + p[1] * q[1]) * 0.5;
    };
    T sum = zero;
    for (size_t k = 0; k < N; ++k) {
        const std::array<T, 2> a{corners[k][0] - cx, corners[k][1] - cy};
        const std::array<T, 2> z{corners[(k + 1) % N][0] - cx, corners[(k + 1) % N][1] - cy};
        const T dx = z[0] - a[0], dy = z[1] - a[1];
        const T A = max(dx * dx + dy * dy, ir::literal(cx, 1e-30));
        const T B = a[0] * dx + a[1] * dy, C = a[0] * a[0] + a[1] * a[1] - rr;
        const T disc = B * B - A * C;
        const auto meets = ir::lessThan(zero, disc);
        const T root = sqrt(max(disc, zero));
        const T t1 = ir::select(meets, min(max((zero - B - root) / A, zero), one), one);
        const T t2 = ir::select(meets, min(max((root - B) / A, zero), one), one);
        const std::array<T, 2> p1{a[0] + dx * t1, a[1] + dy * t1};
        const std::array<T, 2> p2{a[0] + dx * t2, a[1] + dy * t2};
        sum = sum + sector(a, p1) + cross(p1, p2) * 0.5 + sector(p2, z);
    }
    return sum;
}

// The honeycomb as its centres' generators (u, v) lay it: the centres at whole (u, v), the
// hexagon about each |m_k . q| <= 1 with q the offset from the centre and m = (1, 2), (2, 1),
// (1, -1), its corners +-(1/3, 1/3), +-(-1/3, 2/3), +-(-2/3, 1/3). Its six neighbours stand at
// +-(1, 0), +-(0, 1), +-(1, -1), and the next ring's twelve, which the neighbours' neighbours
// reach, at +-(1, 1), +-(2, -1), +-(1, -2) (across a corner) and +-(2, 0), +-(0, 2), +-(2, -2)
// (beyond a side).
constexpr std::array<std::array<double, 2>, 3> kHexNormals{{{1.0, 2.0}, {2.0, 1.0}, {1.0, -1.0}}};
// clang-format off
constexpr std::array<std::array<double, 2>, 19> kHexRings{{
    {0.0, 0.0},
    {1.0, 0.0}, {-1.0, 0.0}, {0.0, 1.0}, {0.0, -1.0}, {1.0, -1.0}, {-1.0, 1.0},
    {1.0, 1.0}, {-1.0, -1.0}, {2.0, -1.0}, {-2.0, 1.0}, {1.0, -2.0}, {-1.0, 2.0},
    {2.0, 0.0}, {-2.0, 0.0}, {0.0, 2.0}, {0.0, -2.0}, {2.0, -2.0}, {-2.0, 2.0}}};
// clang-format on
// The centre's hexagon and its six neighbours: kHexRings' first ring.
constexpr size_t kOneRingCells = 7;

// Where the hexagons about the pixel's centre hold the whole pixel, by rows of edges a pixel
// (the least spacing of the lines the sides lie on, over the pixel): the centre's and its
// six neighbours' within kOneRingRows, with the next ring's within kTwoRingsRows. One ring
// reaches a side's length s past the hexagon, two rings about 2.6 s; a pixel reaches 0.71
// pixel from its centre, and rows of edges stand s sqrt3 / 2 apart unstretched, so one ring
// holds to 1.63 rows a pixel and two to about 4.2, less under a stretch
// (HoneycombInPixel_test.cpp holds both to a count, turned and stretched up to 1.3).
constexpr double kOneRingRows = 1.45, kTwoRingsRows = 3.4;

// |grad(m_k . (u, v))| for the generators' gradients: a side moved in by h moves its bound
// by h times it, and the sides' lines stand 1 / it apart.
template <class T>
T hexSideRate(size_t k, T ux, T uy, T vx, T vy) {
    using std::hypot;
    const auto [m, n] = kHexNormals[k];
    return hypot(ux * m + vx * n, uy * m + vy * n);
}

// The hexagon shrunk to |m_k . q| <= B_k (each side moved in by the stroke's half-width, B_k = 1 -
// h |grad(m_k . (u, v))|, held at or above 0): its corners, counterclockwise in (u, v), each
// where two neighbouring sides' bounds meet. A bound past the other two's sum leaves its
// sides outside the hexagon the others make (a stroke wide against a stretched cell), and is
// held to that sum, where the corners on either side of it meet.
template <class T>
std::array<std::array<T, 2>, 6> insetHexagon(const std::array<T, 3>& bounds) {
    using std::max;
    using std::min;
    const T zero = ir::literal(bounds[0], 0.0);
    std::array<T, 3> b = {max(bounds[0], zero), max(bounds[1], zero), max(bounds[2], zero)};
    b = {min(b[0], b[1] + b[2]), min(b[1], b[0] + b[2]), min(b[2], b[0] + b[1])};
    const double third = 1.0 / 3.0;
    // u + 2v = B0 with 2u + v = B1; u + 2v = B0 with u - v = -B2; u - v = -B2 with 2u + v = -B1.
    const std::array<T, 2> c0{(b[1] * 2.0 - b[0]) * third, (b[0] * 2.0 - b[1]) * third};
    const std::array<T, 2> c1{(b[0] - b[2] * 2.0) * third, (b[0] + b[2]) * third};
    const std::array<T, 2> c2{(zero - b[1] - b[2]) * third, (b[2] * 2.0 - b[1]) * third};
    return {c0,
            c1,
            c2,
            {zero - c0[0], zero - c0[1]},
            {zero - c1[0], zero - c1[1]},
            {zero - c2[0], zero - c2[1]}};
}

// The shrunk hexagon's bounds for strokes of half-width `half` (world), the generators'
// gradients (ux, uy), (vx, vy): B_k = 1 - max(half, 0) |grad(m_k . (u, v))|.
template <class T>
std::array<T, 3> hexBounds(T half, T ux, T uy, T vx, T vy) {
    using std::max;
    const T h = max(half, ir::literal(half, 0.0));
    return {ir::literal(half, 1.0) - h * hexSideRate(0, ux, uy, vx, vy),
            ir::literal(half, 1.0) - h * hexSideRate(1, ux, uy, vx, vy),
            ir::literal(half, 1.0) - h * hexSideRate(2, ux, uy, vx, vy)};
}

// The shrunk hexagon's area in (u, v), where the whole hexagon is 1 (a cell): its paper's
// share of the plane. The shoelace over its corners.
template <class T>
T insetHexagonArea(const std::array<T, 3>& bounds) {
    const auto c = insetHexagon(bounds);
    T area = ir::literal(bounds[0], 0.0);
    for (size_t k = 0; k < 6; ++k)
        area = area + (c[k][0] * c[(k + 1) % 6][1] - c[(k + 1) % 6][0] * c[k][1]) * 0.5;
    return area;
}

// The hexagon of the centre nearest (u, v) in the hexagons' own measure: the one of the four
// whole points about it whose offset q has the least max_k |m_k . q|, the hexagon that holds
// the point. Returns q.
template <class T>
std::array<T, 2> offsetInHexagon(T u, T v) {
    using std::abs;
    using std::floor;
    using std::max;
    const T fu = u - floor(u), fv = v - floor(v);
    std::array<T, 2> best{fu, fv};
    T least = ir::literal(u, 1e30);
    for (double cu : {0.0, 1.0})
        for (double cv : {0.0, 1.0}) {
            const T qu = fu - cu, qv = fv - cv;
            T norm = abs(qu + qv * 2.0);
            norm = max(norm, abs(qu * 2.0 + qv));
            norm = max(norm, abs(qu - qv));
            const auto nearer = ir::lessThan(norm, least);
            least = ir::select(nearer, norm, least);
            best = {ir::select(nearer, qu, best[0]), ir::select(nearer, qv, best[1])};
        }
    return best;
}

// The hexagons about the square pixel [-1/2, 1/2]^2: (u, v) the generators at the pixel's
// centre, e1 and e2 their steps (the world's offsets that advance u and v by 1) along the
// pixel's sides in pixels, and the shrunk hexagon's bounds. `cx, cy` is the centre of the
// hexagon holding the pixel's centre (back by its offset q from the pixel's centre), `shape`
// the shrunk corners mapped through the steps.
template <class T>
struct HexagonsInSquare {
    T cx, cy, e1u, e1v, e2u, e2v;
    std::array<std::array<T, 2>, 6> shape;
};
template <class T>
HexagonsInSquare<T> hexagonsInSquare(T u, T v, T e1u, T e1v, T e2u, T e2v,
                                     const std::array<T, 3>& bounds) {
    const std::array<T, 2> q = offsetInHexagon(u, v);
    const T cx = ir::literal(u, 0.0) - (q[0] * e1u + q[1] * e2u);
    const T cy = ir::literal(u, 0.0) - (q[0] * e1v + q[1] * e2v);
    const auto corners = insetHexagon(bounds);
    std::array<std::array<T, 2>, 6> shape;
    for (size_t k = 0; k < 6; ++k)
        shape[k] = {corners[k][0] * e1u + corners[k][1] * e2u,
                    corners[k][0] * e1v + corners[k][1] * e2v};
    return {cx, cy, e1u, e1v, e2u, e2v, shape};
}

// `sum` plus the paper that the hexagons kHexRings[from, to) leave within the pixel, added in
// the list's order, each signed alike (the steps' turn decides every polygon's sense).
template <class T>
T paperOfCells(const HexagonsInSquare<T>& h, size_t from, size_t to, T sum) {
    for (size_t cell = from; cell < to; ++cell) {
        const auto [nu, nv] = kHexRings[cell];
        const T ox = h.cx + h.e1u * nu + h.e2u * nv, oy = h.cy + h.e1v * nu + h.e2v * nv;
        std::array<std::array<T, 2>, 6> moved;
        for (size_t k = 0; k < 6; ++k) moved[k] = {h.shape[k][0] + ox, h.shape[k][1] + oy};
        sum = sum + polygonInSquare(moved);
    }
    return sum;
}

// A sum of paperOfCells as the pixel's share of paper, 0 to 1.
template <class T>
T paperShare(T sum) {
    using std::abs;
    using std::min;
    return min(abs(sum), ir::literal(sum, 1.0));
}

// The paper the honeycomb's strokes leave within the square pixel (its share of the pixel, 0
// to 1): the hexagon holding the centre and its six neighbours (kOneRingCells); with
// `rings` 2 the next ring's twelve too. Exact while every point of the pixel lies within them
// (kOneRingRows, kTwoRingsRows). The kernel reads the first ring once and adds the second
// behind a branch (LatticeCrowd.cpp, hexEdgesInPixel).
template <class T>
T honeycombPaperInSquare(T u, T v, T e1u, T e1v, T e2u, T e2v, const std::array<T, 3>& bounds,
                         int rings = 1) {
    const HexagonsInSquare<T> h = hexagonsInSquare(u, v, e1u, e1v, e2u, e2v, bounds);
    return paperShare(
        paperOfCells(h, 0, rings > 1 ? kHexRings.size() : kOneRingCells, ir::literal(u, 0.0)));
}

} // namespace moire::lower
