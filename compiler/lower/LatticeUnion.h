// The union of two fine layers of which one or both are lattices, by the lattice's shape
// (docs/filtering.md, "Two dot screens", "Two honeycombs"). Two lattices whose rows run nearly
// together beat: where one's dots (or cells) fall on the other's the pair covers less paper
// than where they fall between, and a pixel that holds many members of each shows that beat
// as the box-filtered field does, where their means laid over one another show an even grey.
// A dot is not a union of lines, nor a honeycomb's edges, so the strands cannot pair them
// (FineUnion.h). The pair is read instead as one lattice moved on the other: each of the
// first lattice's generating rows is matched with the second's shortest row vector nearest
// to it, which makes the second, about the pixel, the first moved by an offset (in the
// first's cells) that the beat carries slowly across the plane. The mean of the two layers'
// product at that offset is then a closed form of the shapes: the overlap of a dot of each
// (lensArea), a dot's share within the strokes of lines (discInStrip), or the paper that the
// two lattices' edges both leave, the overlap of their cells shrunk by the strokes
// (cellArea); sampled over the pixel (LatticeUnion.cpp). A screen whose members are rings
// (rings given by their distance, LatticeShape::inner) is read as the screen of the discs
// within their outer edges less that of the discs within their inner edges: every closed form
// here is linear in the screen's member.
#pragma once

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/FineUnion.h"

#include <array>
#include <cmath>
#include <optional>

namespace moire::lower {

// The area two discs of radii r1 and r2 share with their centres d apart: the lens, the two
// circular segments r^2 acos(c) on either side of the chord, less the triangle pair the
// segments' sectors count twice (half the square root of Heron's product, twice the area of
// the triangle of d, r1 and r2). The cosines held to [-1, 1] make the formula whole: a disc
// within the other gives its own area (acos(-1) = pi for it, 0 for the other, Heron's product
// below 0), apart discs none. acos(x) is taken as pi / 2 - asin(x). A template over IR values
// in the kernel, over double in the tests.
template <class T>
T lensArea(T d, T r1, T r2) {
    using ir::literal;
    using std::asin;
    using std::max;
    using std::min;
    using std::sqrt;
    const T zero = literal(d, 0.0), one = literal(d, 1.0);
    const T a = max(r1, zero), c = max(r2, zero);
    const T dist = max(d, literal(d, 1e-9));
    auto acos = [&](T x) { return 1.5707963267948966 - asin(min(max(x, -one), one)); };
    const T cos1 = (dist * dist + a * a - c * c) / (dist * a * 2.0 + 1e-30);
    const T cos2 = (dist * dist + c * c - a * a) / (dist * c * 2.0 + 1e-30);
    const T heron = (a + c - dist) * (dist + a - c) * (dist - a + c) * (dist + a + c);
    const T area = a * a * acos(cos1) + c * c * acos(cos2) - sqrt(max(heron, zero)) * 0.5;
    return max(area, zero);
}

// The area of a disc of radius r within the strip |z| < h, its centre c from the strip's
// centre line: S(h - c) - S(-h - c), S(z) the disc's area below the chord at z, which with
// t = z / r held to [-1, 1] is r^2 (pi / 2 + asin t + t sqrt(1 - t^2)) (0 at t = -1, the
// half disc at 0, the whole at 1). A template over IR values in the kernel, over double in
// the tests.
template <class T>
T discInStrip(T c, T h, T r) {
    using ir::literal;
    using std::asin;
    using std::max;
    using std::min;
    using std::sqrt;
    const T zero = literal(c, 0.0), one = literal(c, 1.0);
    const T radius = max(r, literal(c, 1e-9));
    auto below = [&](T z) {
        const T t = min(max(z / radius, -one), one);
        return radius * radius * (asin(t) + t * sqrt(max(one - t * t, zero)) + 1.5707963267948966);
    };
    return max(below(h - c) - below(zero - h - c), zero);
}

// The area of the region {x : -lower_i <= m_i . x <= upper_i, i = 1, 2, 3}, three directions
// of normals that sum to 0 (m_1 + m_2 + m_3 = 0: the sides of a triangle, weighted by their
// lengths), `lower` absent where the region is bounded on one side alone. With the normals
// summing to 0 the half-planes m_i . x <= b_i bound a triangle of one shape whatever the b,
// scaled by their sum: of area kappa (b_1 + b_2 + b_3)^2, none where the sum is below 0. The
// region is the triangle of `upper` less the corners the lower bounds cut off; each corner
// cut (m_i . x < -lower_i within the other two upper bounds) is such a triangle too, as is
// where two corners' cuts overlap, and where all three do. By inclusion and exclusion, with
// (x)+ = max(x, 0):
//   area / kappa = (sum U)+^2 - sum_i (U_j + U_k - L_i)+^2 + sum_{i<j} (U_k - L_i - L_j)+^2
//                  - (-sum L)+^2,
// which holds while every lower bound is at or below its upper one (-L_i <= U_i), the cuts
// within the triangle; past that the region is empty.
// A lattice's cells are such regions: the triangle lattice's two triangles (one bounded
// above, the other below) and the honeycomb's hexagon (both), and so is the overlap of two of
// them moved on each other (the least bound of each side). A template over IR values in the
// kernel, over double in the tests.
template <class T>
T cellArea(const std::array<T, 3>& upper, const std::optional<std::array<T, 3>>& lower,
           double kappa) {
    using ir::literal;
    using std::max;
    const T zero = literal(upper[0], 0.0);
    auto square = [&](T x) {
        const T y = max(x, zero);
        return y * y;
    };
    T area = square(upper[0] + upper[1] + upper[2]);
    if (lower) {
        const std::array<T, 3>& l = *lower;
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            area = area - square(upper[j] + upper[k] - l[i]);
            area = area + square(upper[i] - l[j] - l[k]);
        }
        area = area - square(zero - l[0] - l[1] - l[2]);
        // A lower bound above its upper one leaves nothing, where the cut corners above
        // would reach past the triangle.
        for (int i = 0; i < 3; ++i)
            area = ir::select(ir::lessThan(upper[i] + l[i], zero), zero, area);
    }
    return max(area, zero) * kappa;
}

// Taps a side of the pixel at which the pair's overlap is sampled: the beat is resolved
// wherever the correlation is given weight, so a few taps give its mean over the pixel.
constexpr int kDotPairTaps = 2;

// How far a screen's dots are past resolved for the pair: smoothstep(kCrowdFrom, kCrowdFull)
// of its rows per pixel along its sparser generator, as the union of phase families reads
// members per pixel (FineUnion.cpp). Not the dots' own hand-over to their share of the plane
// (LatticeCrowd.cpp), which counts each dot over the pixel exactly while the next ring of
// neighbours is out of reach: counted so, each screen's mean is right, but not their overlap.
ir::ValueId dotsCrowded(ir::Builder& b, const CrowdEstimate::LatticeShape& p,
                        const PixelFootprint& pixel);

// The correlation of two consecutive layers that both draw dots (FineLayer::points), in the
// form the union of fine layers adds it (FineUnion.cpp, pairCorrelation): k1 k2 (E - a1 a2)
// (P - K1), E the mean of the two screens' product over the pixel, a_i their shares, with the
// weight of the least engaged screen and of the beat's resolution. Zero wherever either does
// not draw its points.
Ink dotCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                   const PixelFootprint& pixel);

// The correlation of a dot screen with a layer of lines, consecutive (the screen first where
// `dotsFirst`): a phase family, or a lattice that draws its edges, by its strands. Each line
// beats with the screen's row nearest its direction, whose dots it covers by the share of a
// disc within its strokes at the offset the beat carries (discInStrip), the lines taken as
// independent of one another as strandCorrelation takes them (FineUnion.cpp). In the same
// form as dotCorrelation; zero where the screen does not draw its points or the lattice of
// lines does not draw its edges.
Ink dotLineCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                       bool dotsFirst, const PixelFootprint& pixel);

// Whether two lattices' cells can be laid on one another: both of the same kind (the same
// normals and cells), and one that has them (not the square lattice).
bool sameCells(const CrowdEstimate::LatticeShape& a, const CrowdEstimate::LatticeShape& b);

// The correlation of two consecutive lattices of the same kind that both draw their edges,
// by the paper their edges leave (cellArea), in the form of dotCorrelation; zero where either
// draws its points.
Ink cellCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                    const PixelFootprint& pixel);

// Whether a lattice's cells are the honeycomb's hexagon (bounded on both sides of each
// direction), whose paper hexLineCorrelation lays on lines.
bool honeycombCells(const CrowdEstimate::LatticeShape& p);

// The correlation of a honeycomb that draws its edges with a layer of lines, consecutive (the
// honeycomb first where `cellsFirst`): a phase family, or a lattice that draws its edges, by
// its strands. Each line beats with the honeycomb's row nearest its direction (a row of its
// centres, or of the lines its sides lie on), which carries the lines' offset from each
// hexagon's centre; the paper both leave is the shrunk hexagon less the lines' strokes across
// it (polygonInBand, HoneycombInPixel.h). In the same form as dotLineCorrelation; zero where
// the honeycomb draws its points or the lattice of lines does not draw its edges.
Ink hexLineCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                       bool cellsFirst, const PixelFootprint& pixel);

// The correlation of a honeycomb that draws its edges with a dot screen, consecutive (the
// honeycomb first where `cellsFirst`). The screen is matched with the honeycomb's rows of
// centres as one screen is with another (dotCorrelation), which makes it, about the pixel, a
// screen at the honeycomb's period moved by the beat's offset; the paper both leave is the
// shrunk hexagon less the dots within it (discInPolygon, HoneycombInPixel.h). In the same form
// as dotCorrelation; zero where the honeycomb draws its points or the screen its edges.
Ink hexDotCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                      bool cellsFirst, const PixelFootprint& pixel);

} // namespace moire::lower
