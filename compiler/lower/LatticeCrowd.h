// The mean ink of a lattice whose points or edges are finer than the pixel (docs/filtering.md,
// "Lattices finer than a pixel"). A lattice gives the distance to its nearest point or edge
// alone, so the mean filter's distance form counts one member a pixel: where they crowd that
// is a fraction of the ink. In the limit of many cells a pixel the ink is the share of a cell
// the strokes cover, a closed form of the lattice's geometry: the compose step hands the
// nearest member's mean over to it by members per pixel (a CrowdEstimate), as the walking
// solver hands its strided scan over to its crowd.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LatticeFamily.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

#include <cmath>
#include <numbers>

namespace moire::lower {

struct LatticeCrowdInputs {
    ir::ValueId spacing;   // between neighbouring points (the hexagons' side for hex_lattice)
    ir::ValueId sx, sy;    // the stretch along x and y
    ir::ValueId stroke;    // the stroke's width as written, in world units
    ir::ValueId pixel;     // the pixel's side in world units
    ir::ValueId drawEdges; // a bool: the edges, else the points
    // The generators' index fields and their gradients (LayerFields::genU ...): the square
    // and triangle lattices' edges are whole lines, families of the index u, v (and u + v).
    ir::ValueId genU = ir::kNoValue, genUX = ir::kNoValue, genUY = ir::kNoValue;
    ir::ValueId genV = ir::kNoValue, genVX = ir::kNoValue, genVY = ir::kNoValue;
    ir::ValueId cosTurn = ir::kNoValue, sinTurn = ir::kNoValue; // the camera's turn
    ir::ValueId distance = ir::kNoValue; // to the nearest point or edge, in world units
};

// The mean over the square pixel (in pixel units: side 1, centred at 0) of a disc of radius
// r centred at (cu, cv) along the pixel's sides. Written as the integral over u of the disc's
// chord clipped to the pixel, with u = cu + r sin(theta): the integrand is then smooth in theta
// (an unclipped disc's is 2 r^2 cos^2 theta, which the midpoint rule over the half turn
// integrates exactly), so kDotTaps midpoints in theta over the disc's extent within the pixel
// give the area to well under a percent. A template over IR values here, over double in tests.
constexpr int kDotTaps = 8;
template <class T>
T discInSquare(T cu, T cv, T r) {
    using ir::literal;
    using std::asin;
    using std::cos;
    using std::max;
    using std::min;
    using std::sin;
    const T zero = literal(cu, 0.0), half = literal(cu, 0.5), one = literal(cu, 1.0);
    const T radius = max(r, literal(cu, 1e-9));
    auto angle = [&](T u) { return asin(min(max((u - cu) / radius, -one), one)); };
    const T lo = angle(max(-half, cu - radius)), hi = angle(min(half, cu + radius));
    const T step = max(hi - lo, zero) * (1.0 / kDotTaps);
    T sum = zero;
    for (int k = 0; k < kDotTaps; ++k) {
        const T theta = lo + step * (k + 0.5);
        const T w = radius * cos(theta);
        const T chord = max(min(cv + w, half) - max(cv - w, -half), zero);
        sum = sum + chord * w;
    }
    return min(sum * step, one);
}

// A disc's Fourier transform over its area, 2 J1(z) / z at z = 2 pi r |k| (radius r, frequency
// k in cycles per unit): 1 at z = 0, the disc's share of each harmonic of a dot screen (the
// box filter's ripple about the dots' share, dotRipple in the .cpp). Its power series,
// sum_j (-1)^j (z^2 / 4)^j / (j! (j + 1)!), summed by Horner's rule up to z = 8 (16 terms, to
// 1e-6; its largest term there is 22, which float carries to a few 1e-6), and Hankel's
// asymptotic form beyond, J1(z) ~ sqrt(2 / (pi z)) (P cos w - Q sin w) with w = z - 3 pi / 4,
// P = 1 + 15 / (128 z^2) and Q = 3 / (8 z) - 315 / (3072 z^3) (to 1e-5 from z = 8). A
// template over IR values here, over double in tests.
constexpr int kJincTerms = 16;
constexpr double kJincSeriesUpTo = 8.0;
template <class T>
T discTransform(T z) {
    using ir::literal;
    using std::cos;
    using std::max;
    using std::min;
    using std::sin;
    using std::sqrt;
    const T one = literal(z, 1.0);
    const T near = min(z, literal(z, kJincSeriesUpTo));
    const T x = near * near * 0.25;
    T series = one;
    for (int j = kJincTerms; j >= 1; --j) series = one - x * (1.0 / (j * (j + 1.0))) * series;
    const T far = max(z, literal(z, kJincSeriesUpTo));
    const T w = far - literal(z, 0.75 * std::numbers::pi);
    const T inv = one / far;
    const T p = one + inv * inv * (15.0 / 128.0);
    const T q = inv * (3.0 / 8.0) - inv * inv * inv * (315.0 / 3072.0);
    const T j1 = sqrt(inv * (2.0 / std::numbers::pi)) * (p * cos(w) - q * sin(w));
    return ir::select(ir::lessThan(z, literal(z, kJincSeriesUpTo)), series, j1 * inv * 2.0);
}

// A screen's harmonic of world frequency (kx, ky) from one dot of radius r a cell, `cells` cells
// a unit of area: cells pi r^2 (2 J1(z) / z) at z = 2 pi r |k| (discTransform). Its sites'
// phases are the caller's.
ir::ValueId dotHarmonic(ir::Builder& b, ir::ValueId cells, ir::ValueId r, ir::ValueId kx,
                        ir::ValueId ky);

// The square pixel's mean of a wave of world frequency (kx, ky) (cycles a unit) over the wave's
// value at the pixel's centre: sin(pi f) / (pi f) for each of the pixel's sides, f the wave's
// cycles a pixel along it. Unlike footprintTransfer (FineUnion.h) its side lobes are kept:
// past a cycle a pixel they are all the ripple a lattice leaves.
ir::ValueId boxTransfer(ir::Builder& b, ir::ValueId kx, ir::ValueId ky,
                        const PixelFootprint& pixel);

// The box-filtered mean of a screen of round dots of radius r (world units), one at each whole
// (genU, genV): the dots' share of the plane, |det(grad u, grad v)| pi r^2, and the box filter's
// ripple about it (the harmonics with |m1|, |m2| <= 2, each the dot's transform times the
// pixel's). The dots laid apart (2 r under the nearest two points' distance). Reads the
// generators, their world gradients and the pixel (size and turn) of `in`.
ir::ValueId dotScreenMean(ir::Builder& b, const LatticeCrowdInputs& in, ir::ValueId r);

// `engaged` from 0 where the densest rows of members stand kCrowdFrom pixels apart or more, to
// 1 at kCrowdFull; `mean` the share of the plane the strokes cover; `nearest`, where the
// lattice draws its points, the nearest dot's mean over the pixel (discInSquare) in place of
// the distance form, which takes a dot narrower than the pixel for a band across it. The square and
// triangle lattices' edges are whole lines, two or three phase families of the generators: there
// `engaged` is 1 and `mean` their periodic means over the square pixel laid over one another
// (exact at every scale for one family, and for the square's two over a pixel facing them).
CrowdEstimate latticeCrowd(ir::Builder& b, LatticeKind kind, const LatticeCrowdInputs& in);

} // namespace moire::lower
