// The envelope view (§4.4): the stack's ink averaged over one period of every layer's index,
// advanced together (Eq. 13), written once as IR so that every backend draws it. Each layer
// hands over its phase sample (Eq. 14, LayerFields::sample), found once per pixel; each of
// the M taps then reads every layer's distance from it by Eq. 15, inks the stack as the
// pattern does (inkOver) with each stroke at its true width, and the taps are averaged.
// The mean is then graded about a per-pixel pivot: the composite of the layers' own means,
// the ink the stack would have if its phases were independent, so that the gain amplifies
// exactly the beat between the layers (a sole layer is graded about its nominal ink).
// The stroke's edge keeps the pattern's antialias band (0.7 px), widened where the taps could
// not resolve it to kTapBand taps' worth of index, and held within the half-width: a band
// symmetric about the edge leaves each layer's mean ink exactly its hard edge's, 2h / gap,
// and the widening keeps M taps from aliasing on edges sharper than their spacing (at a
// high zoom). Wherever the taps' band is the wider (two taps wider than 0.7 px, so at every
// zoom above that), nothing in the view depends on the pixel's size: the same world point
// gives the same value at every zoom (tests/envelope_test.cpp).
constexpr double kTapBand = 2.0;
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/Characters.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/sema/Views.h"

#include <vector>

namespace moire::lower {

// A stack with a lattice sweeps the pair (u, v) of every lattice's generators over their
// unit cell (§4.4's rank-two case): F_k taps of a Fibonacci lattice rule, F_k nearest
// M^2 / 8 (Envelope.cpp), k at most this (F_18 = 2584 taps).
constexpr double kLatticeRuleOrder = 18;

// What the envelope is given of one layer.
struct EnvelopeLayer {
    PhaseSample sample;
    ir::ValueId halfWidth; // the stroke's true half-width (no hairline floor)
    ir::ValueId antialias; // the pattern's antialias band (Eq. 35)
    Vals color;            // r, g, b, a
    ir::ValueId opacity;
    ir::ValueId spacing; // the nominal pitch: a sole layer is graded about its ink at it
    ir::ValueId gradX = ir::kNoValue, gradY = ir::kNoValue; // its index gradient
    // In a rank-two sweep (a stack with a lattice), how far a one-index layer's index
    // advances per advance (s, t) of the lattices' generators: rideU s + rideV t. Unset, it
    // rides the first generator, (1, 0). See rankTwoRides.
    ir::ValueId rideU = ir::kNoValue, rideV = ir::kNoValue;
};

struct EnvelopeSettings {
    ir::ValueId gain; // contrast about the pivot
    ir::ValueId taps; // M, rounded and held within [1, sema::kMaxEnvelopeTaps]
};

// The local period of a layer at the pixel: the gap between the two members that bracket
// it (z - down when the nearest member is ahead of the pixel, up - z otherwise). Eq. 15 takes
// |up - z|; the two agree for the phase families, and where a walking family bunches the
// bracketing gap is the one a member crosses the pixel in, once per period.
ir::ValueId sampleGap(ir::Builder& b, const PhaseSample& s);

// The distance to the nearest member after advancing the layer's index by `advance` (in
// (-1, 1)): Eq. 15, max(min over z, up, down of |k - advance * gap|, floor).
ir::ValueId tapDistance(ir::Builder& b, const PhaseSample& s, ir::ValueId gap, ir::ValueId advance);

// The sweep direction w: how fast each layer's index advances as the tap u goes over [0, 1).
// The one place it is chosen. The diagonal (1, ..., 1) keeps every zero-sum character (every
// difference beat, and for three layers the zero-sum ternaries such as (1, 1, -2)); a pair
// whose first-order sum beat is the slower one (Eq. 11: its index gradients point more
// against each other than along, g1 . g2 < 0) has its second layer swept backwards,
// w = (1, -1), which keeps the sum instead. Per pixel, as §4.4 allows for first-order sum
// beats.
// Any other deviation is licensed once per stack, never per pixel (§4.4): the pair's nominal
// pitch ratio (the two spacings alone, as parallel carriers) is run through the character
// search, and when the character it certifies is a fringe (mu <= 1/4) that is not zero-sum,
// the sweep keeps it, w = (|k2|, -k1 sgn k2), wherever it is also the pixel's own winner:
// w = (1, 3) for the (3, -1) beat of pitches 15 and 5 (Fig. 7). Elsewhere the diagonal.
std::vector<ir::ValueId> sweepDirection(ir::Builder& b, const std::vector<EnvelopeLayer>& layers);

// The hand-over between a pair's first-order difference and sum beats is a fade, not a
// switch (§4.4: the sum beat's per-pixel freedom is one fade): with
// q = 2 g1.g2 / (|g1|^2 + |g2|^2), which is 0 where the two beats are equally slow, the sweep
// w = (1, -1) takes the weight smoothstep(kSumFade, -kSumFade, q) and w = (1, 1) the rest.
// Inside the band (the beats' rates within about 10% of each other) both sweeps run and their
// envelopes are mixed; outside it, one sweep, the one sweepDirection picks. kNoValue where
// there is no such pair, and 0 where a licensed deviation holds the pixel (w is not (1, +-1)).
constexpr double kSumFade = 0.1;
ir::ValueId sumFade(ir::Builder& b, const std::vector<EnvelopeLayer>& layers,
                    const std::vector<ir::ValueId>& w);

// Sets the rides of the one-index layers of a stack with a lattice, per pixel, from the
// stack's winning character `c` over `layers` (Characters.h): a layer the character pairs
// with a lattice's row, with a coefficient of +-1, rides that row, so that the character is
// kept (a line family beating with a lattice's second generator rides it, where riding the
// first would average that fringe away: §4.4, the combination of the generators that rides
// the sweep is the character choice again). Any other layer rides the first generator.
void rankTwoRides(ir::Builder& b, const Character& c, std::vector<EnvelopeLayer>& layers);

// The stack's ink over `paper` (premultiplied) averaged over one period of every layer's index
// advanced together along `w` (sweepDirection), the sum beat's fade mixed in where sumFade
// gives one, and not graded: `mean`; and `pivot`, the layers' own mean coverages composited
// in order (a sole one-index layer's nominal ink), the ink the stack would hold were its
// phases independent. The envelope grades the one about the other; the mean filter's union of
// fine layers (FineUnion.h) adds their difference, the stack's correlation, to the union of
// the layers' footprint means. settings.gain is not read.
struct SweptInk {
    Ink mean, pivot;
};
SweptInk sweptInk(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                  const EnvelopeSettings& settings, const std::vector<ir::ValueId>& w);

// The envelope over `paper` (premultiplied), graded by the settings: premultiplied RGBA.
Ink envelopeInk(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                const EnvelopeSettings& settings);

} // namespace moire::lower
