// The mean filter's union of fine layers (docs/filtering.md, "Fine layers together"). Each
// layer's footprint mean (Prefilter.h) laid over the others is the union of the means: right
// where the layers' phases are independent across the pixel, wrong where two fine families are
// correlated, as they are wherever their beat D (for a pair swept together, D = f1 - f2, or
// f1 + f2 for a sum beat) runs slowly across the pixel while their members do not. There the
// pixel holds Phi(D), the fringe law's mean ink of the pair at offset D (§4.1, Eq. 7), which
// is the envelope's sweep (Envelope.h, sweptInk): the stack's ink averaged over one period of
// every layer's index advanced together. Its departure from the union of the layers' own
// swept means is the stack's correlation, and it is added to the union of the footprint means
// with the weight the pixel's footprint leaves it (FineUnion.cpp): the moiré of two families
// that neither are resolved shows as the box-filtered field shows it. For a pair (a run of
// two) the correlation is in closed form, the overlap of the two periodic strokes averaged
// over the pixel (sweptOverlap below); a longer run takes the sweep, 24 taps of every layer.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/Envelope.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

#include <optional>
#include <vector>

namespace moire::lower {

// Taps of the sweep (Envelope.h's M) for the union: the envelope view's default.
constexpr double kUnionTaps = 24;

// A family of whole lines within a layer, as the mean filter measures it (its index, gradient
// and first member) with its footprint mean: a phase family is one; a square or triangle
// lattice's edges are two or three (CrowdEstimate::strands), whose union is the layer's ink.
struct Strand {
    Footprint footprint;
    ir::ValueId mean;
};

// One layer of a run of fine layers: as the envelope sweeps it, and as the mean filter
// measures it (its strands; `footprint` a phase family's own). `strandsOn` is where a
// lattice's strands are its ink (it draws its edges), kNoValue for a phase family and the
// honeycomb; `shape` a lattice's (its dots or cells: LatticeUnion.h), `laid` the ink
// the pixel lays of it.
struct FineLayer {
    EnvelopeLayer sweep;
    Footprint footprint;
    std::vector<Strand> strands;
    ir::ValueId strandsOn = ir::kNoValue;
    std::optional<CrowdEstimate::LatticeShape> shape;
    ir::ValueId laid = ir::kNoValue; // the layer's own mean ink over the pixel, as laid
    // A family given by its distance, by the index its crowd runs by (CrowdEstimate::runs):
    // where its members run two ways (`twoWays` > 0, a grid's lines), by its two strands as
    // a lattice's lines are; where they are a screen of dots (`shape`, its `dots`), by
    // that shape as a lattice's dots are; else as a phase family by the first.
    bool byDistance = false;
    ir::ValueId twoWays = ir::kNoValue;
    bool lattice() const { return !byDistance && (strandsOn != ir::kNoValue || shape.has_value()); }
    // Whether the layer joins a run as a pair alone: the sweep of a longer run knows neither
    // a lattice's strands and shape nor a family given by its distance (which has no phase
    // sample), so such a run is closed at two (Compose.cpp).
    bool pairsOnly() const { return lattice() || byDistance; }
};

// Whether a layer can join a run: a phase family with a footprint and a one-index phase
// sample, or a lattice (joinsAsLattice), or a family given by its distance by the index its
// crowd runs by (joinsByDistance); morphs and walking families are laid over on their own. A
// lattice joins by its strands, the whole lines of its edges (CrowdEstimate::strands: the square
// and triangle lattices'), or by its shape, its dots or cells (CrowdEstimate::shape,
// LatticeUnion.h: every lattice whose generators are known).
bool joinsFineUnion(const Footprint& footprint, const PhaseSample& sample);
bool joinsAsStrands(const CrowdEstimate& crowd);
bool joinsAsLattice(const CrowdEstimate& crowd);
bool joinsByDistance(const CrowdEstimate& crowd);

// footprintTransfer (below) of an index whose gradient has components (u, v) along the
// pixel's sides.
ir::ValueId transfer(ir::Builder& b, const PixelSides& g, const PixelFootprint& pixel);

// How far a family's members are past being resolved: smoothstep(kCrowdFrom, kCrowdFull, nu),
// nu = |grad index| x pixel, times the index's trust where it is read from the members
// (Footprint::trust), and 0 where its footprint reaches below a first member (as meanInk,
// which draws such a pixel from its distance).
ir::ValueId unresolved(ir::Builder& b, const Footprint& f, const PixelFootprint& pixel);

// A family that starts at a member has no members below it, which a periodic stroke counts:
// within one member past the first a correlation is faded out, 0 to 1 (1 for a family with no
// first member).
ir::ValueId pastFirst(ir::Builder& b, const Footprint& f);

// A pair's covariance `cov` (of the two layers' inks over the pixel, as units of their
// strokes) as the composite takes it: k1 k2 cov (P - K1) per premultiplied channel, k_i a
// layer's opacity times its alpha (inkCoverage), P the ink beneath the pair and K1 the lower
// layer's colour (pairCorrelation in FineUnion.cpp derives it). Every pair's correlation
// ends here.
Ink pairCorrection(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                   ir::ValueId cov);

// The transfer of a pixel's footprint to the fundamental of a periodic ink whose index spans
// `along` and `across` units over the pixel's two sides: the square pixel's mean of
// cos(2 pi index) is sinc(along) sinc(across) times its value at the centre, sinc(x) =
// sin(pi x) / (pi x). Each factor is held at 0 past its first zero (x >= 1), where a side
// spans a whole period: the remaining lobes are small and of either sign. Written once as a
// template: over IR values in the kernel, over double in the tests.
template <class T>
T footprintTransfer(T along, T across) {
    using ir::literal;
    using std::max;
    using std::min;
    using std::sin;
    auto sinc = [&](T x) {
        T t = min(max(x, literal(x, 1e-4)), literal(x, 1.0));
        return sin(t * 3.14159265358979323846) / (t * 3.14159265358979323846);
    };
    return sinc(along) * sinc(across);
}

// The mean over one period of P_h1(x + D) P_h2(x), P_h the periodic box that is 1 within h
// of a whole number (any h >= 0: a box wider than a period overlaps its neighbours and
// counts twice there): the periodic convolution of two boxes, a trapezoid in D. Written in
// closed form: F(D) = sum_n g(D - n) with g = box_h1 * box_h2, whose second derivative is
//   delta(D + h1 + h2) - delta(D + h1 - h2) - delta(D - h1 + h2) + delta(D - h1 - h2).
// The periodic Q(x) = (t^2 - t + 1/6) / 2, t = fract(x), has Q'' = 1 - sum_n delta(x - n)
// and mean 0, so
//   F(D) = 4 h1 h2 - [Q(D + h1 + h2) - Q(D + h1 - h2) - Q(D - h1 + h2) + Q(D - h1 - h2)]:
// the second derivatives agree (the four signs sum to 0) and so do the means (the integral
// of g is 4 h1 h2). D is first reduced to [-1/2, 1/2), so the fracts stay small numbers.
// This is its value at one offset; the kernel takes its mean over the pixel (below), the
// tests hold the two against each other and this against the strokes themselves.
template <class T>
T periodicBoxOverlap(T offset, T h1, T h2) {
    using ir::literal;
    using std::floor;
    using std::max;
    auto q = [&](T x) {
        T t = x - floor(x);
        return (t * t - t + 1.0 / 6.0) * 0.5;
    };
    const T d = offset - floor(offset + 0.5);
    const T sum = h1 + h2, diff = h1 - h2;
    const T f = h1 * h2 * 4.0 - (q(d + sum) - q(d + diff) - q(d - diff) + q(d - sum));
    return max(f, literal(offset, 0.0)); // rounding leaves a hair below 0 where they miss
}

// periodicBoxOverlap averaged over a square pixel across which the offset steps `along` and
// `across` (|grad D . side| for its two sides): the pixel holds the overlap's mean over the
// offsets it spans, each harmonic of the trapezoid attenuated by the pixel as it is, where a
// single transfer for the fundamental would leave the trapezoid's corners sharp. It is the
// trapezoid footprint's second difference (Prefilter.h, trapezoidMean) of Q's second
// integral, Q2(x) = t^2 (1 - t)^2 / 24 (B4(t) / 24 less its constant, which a second
// difference drops), term by term. With the narrow side held at 1e-3 (Prefilter.h) its
// float rounding stays under about 1e-3 of the overlap.
template <class T>
T periodicBoxOverlapMean(T offset, T h1, T h2, T along, T across) {
    using ir::literal;
    using std::floor;
    using std::max;
    const Trapezoid<T> foot = trapezoid(along, across);
    auto q2 = [&](T x) {
        T t = x - floor(x);
        T u = t * (1.0 - t);
        return u * u * (1.0 / 24.0);
    };
    auto mean = [&](T c) { return trapezoidMean(foot, c, q2); };
    const T d = offset - floor(offset + 0.5);
    const T sum = h1 + h2, diff = h1 - h2;
    const T f = h1 * h2 * 4.0 - (mean(d + sum) - mean(d + diff) - mean(d - diff) + mean(d - sum));
    return max(f, literal(offset, 0.0));
}

// E[AB]: the mean over the sweep u in [0, 1) of A(f1 + p u) B(f2 + q u), A and B the two
// layers' strokes in their index (members at the integers, half-widths w1, w2 in index units,
// held within [0, 1/2], where the strokes touch), advanced p and q periods over the sweep (p,
// q whole and coprime, neither 0: sweepDirection's w). In harmonics, A = sum alpha_m e(m x),
// B = sum beta_n e(n x) (both even), the sweep keeps the pairs p m + q n = 0, m = q j,
// n = -p j, so E = sum_j alpha_(qj) beta_(pj) e(j D), D = q f1 - p f2. The harmonics
// alpha_(qj) are those of A decimated by q, (1/q) sum_r A((y + r) / q), which is a box of
// half-width q w1 at every whole number, 1/q high; so
//   E = periodicBoxOverlap(D, |q| w1, |p| w2) / |p q|,
// on the diagonal (p = q = 1) the overlap of the strokes at the beat's offset f1 - f2, and
// for the sum beat (1, -1) at f1 + f2 (the strokes are even). Averaged over the pixel, whose
// sides D steps `along` and `across` (periodicBoxOverlapMean).
template <class T>
T sweptOverlap(T f1, T f2, T p, T q, T w1, T w2, T along, T across) {
    using ir::literal;
    using std::abs;
    using std::max;
    using std::min;
    const T zero = literal(f1, 0.0), half = literal(f1, 0.5), one = literal(f1, 1.0);
    const T h1 = min(max(w1, zero), half), h2 = min(max(w2, zero), half);
    const T ap = max(abs(p), one), aq = max(abs(q), one);
    return periodicBoxOverlapMean(q * f1 - p * f2, aq * h1, ap * h2, along, across) / (ap * aq);
}

// The run's pixel: `under` is the ink beneath the run (premultiplied), `independent` the run's
// layers' inks laid over it one by one (the union of their means). Returns the pixel with the
// run's correlation added where the footprint leaves it (a run of one layer: `independent`),
// a pair's in closed form, a longer run's by the sweep (chosen by the run's length here, not
// per pixel). A run with a lattice is a pair (the compose step closes it at two), whose
// correlation is its strands' (FineUnion.cpp, strandCorrelation: each line of the first layer
// beats with the second's line whose beat is slowest at the pixel, in closed form), or its
// shape's (LatticeUnion.h): two dot screens, a screen with the other layer's lines, two
// lattices of edges of one kind by their cells; which, by branches on the lattices' `edges`.
// Computed behind a branch: a pixel where fewer than two of the run's layers are past the
// unresolved threshold (kCrowdFrom) pays a handful of instructions.
Ink fineUnion(ir::Builder& b, const Ink& under, const Ink& independent,
              const std::vector<FineLayer>& run, const PixelFootprint& pixel);

} // namespace moire::lower
