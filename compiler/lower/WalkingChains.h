// A walking family whose turn has a short period, drawn member by member (docs/filtering.md,
// "Walking families past the budget"): where the turn is 2 pi p / q, member n + q is member n
// turned by whole turns, so the members fall into q chains along which the shape does not
// turn. Each chain is a translated shape, whose residual is convex in its index: the members
// within reach of a pixel are two runs found by bisection, and the union of their strokes over
// the pixel's footprint is exact. The walking solver's crowd estimate uses it where the scan
// strides and the period is short (WalkingCrowd.cpp).
#pragma once

#include "compiler/ir/Builder.h"

#include <functional>

namespace moire::lower {

// The period of a turn, found in the kernel: the first convergent denominator q of
// |turn| / 2 pi (p its numerator) whose remainder drift = q turn - 2 pi p turns no chain of the
// capped interval by more than kChainDrift radians; q = 0 where there is none up to
// kMaxSelected; `inverse` is p's inverse modulo q (the chain j whose members stand at turn
// 2 pi k / q is k inverse mod q).
struct TurnPeriod {
    ir::ValueId q, p, drift, inverse;
};
// Chains drawn one by one, every chain of the period.
constexpr double kMaxChains = 72;
// Past kMaxChains, the period for which the chains that reach the pixel are picked
// (ChainSelection.h): k inverse stays a whole number a float holds (q^2 < 2^24).
constexpr double kMaxSelected = 2048;
constexpr double kChainDrift = 0.05;
TurnPeriod turnPeriod(ir::Builder& b, ir::ValueId turn);

struct ChainInputs {
    ir::ValueId turn;    // theta
    ir::ValueId stroke;  // the stroke's width as written, in residual units
    ir::ValueId lo, end; // the members [lo, end) are drawn
    // Where the chains are picked: the near members [lo, split) are drawn one by one and the
    // chains from split on; split = lo otherwise.
    ir::ValueId split;
    ir::ValueId reach; // past this |residual| a member's stroke misses the footprint
    // h_p(n), given Rot(-n theta) p: the point turned back by member n's own turn.
    std::function<ir::ValueId(ir::ValueId n, ir::ValueId turnedX, ir::ValueId turnedY)> residual;
    // Rot(-angle) p.
    std::function<std::pair<ir::ValueId, ir::ValueId>(ir::ValueId angle)> unturn;
    // The footprint mean of the band of residuals `half` either side of `centre`, the pixel's
    // extents across the band's normal being (along, across) (distanceMeanInk).
    std::function<ir::ValueId(ir::ValueId centre, ir::ValueId half, ir::ValueId along,
                              ir::ValueId across)>
        bandMean;
    // The footprint every chain is drawn with, but for picked windows (ChainWindows).
    ir::ValueId along, across;
};

struct ChainWindows;

// The footprint mean of the union of strokes of width `stroke` centred at residuals h(i),
// i in [from, to), sorted along their common normal, by inclusion and exclusion: each stroke's
// mean less that of its overlap with the one before, exact for strokes of one width (none
// overlaps past its neighbour what the neighbour does not). bandMean(centre, half) is the
// footprint mean of the band of residuals `half` either side of `centre`.
ir::ValueId sortedStrokesMean(ir::Builder& b, ir::ValueId stroke, ir::ValueId from, ir::ValueId to,
                              const std::function<ir::ValueId(ir::ValueId)>& h,
                              const std::function<ir::ValueId(ir::ValueId, ir::ValueId)>& bandMean);

// The normal at the pixel of member n turned by psi, grad_p h_p(n), in the frame of the point
// the residual is read at: grad_p h = Rot(psi) grad_q h, the gradient with respect to the
// turned point q = Rot(-psi) p, by central differences of step e (in.residual, in.unturn).
std::pair<ir::ValueId, ir::ValueId> memberNormal(ir::Builder& b, const ChainInputs& in,
                                                 ir::ValueId n, ir::ValueId psi, ir::ValueId e);

// The footprint mean of the union of every member's stroke in [lo, end), for a period found
// (period.q > 0): every chain of it, or where `picked` (a bool), the near members [lo, split)
// one by one and the chains of `windows` alone (ChainSelection.h).
ir::ValueId chainInk(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period,
                     ir::ValueId picked, const ChainWindows& windows);

} // namespace moire::lower
