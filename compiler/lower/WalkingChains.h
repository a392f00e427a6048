// A walking family whose turn has a short period, drawn member by member (docs/filtering.md,
// "Walking families past the budget"): where the turn is 2 pi p / q, member n + q is member n
// turned by whole turns, so the members fall into q chains along which the shape does not
// turn. Each chain is a translated shape, whose residual is convex in its index: the members
// within reach of a pixel are two runs found by bisection, and the union of their strokes over
// the pixel's footprint is exact. The walking solver's crowd estimate uses it where the scan
// strides and the period is short (WalkingFamily.cpp).
#pragma once

#include "compiler/ir/Builder.h"

#include <functional>

namespace moire::lower {

// The period of a turn, found in the kernel: the first convergent denominator q of
// |turn| / 2 pi (p its numerator) whose remainder drift = q turn - 2 pi p turns no chain of the
// capped interval by more than kChainDrift radians; q = 0 where there is none up to
// kMaxChains.
struct TurnPeriod {
    ir::ValueId q, p, drift;
};
constexpr double kMaxChains = 72;
constexpr double kChainDrift = 0.05;
TurnPeriod turnPeriod(ir::Builder& b, ir::ValueId turn);

struct ChainInputs {
    ir::ValueId turn;    // theta
    ir::ValueId stroke;  // the stroke's width as written, in residual units
    ir::ValueId lo, end; // the members [lo, end) are drawn
    ir::ValueId reach;   // past this |residual| a member's stroke misses the footprint
    // h_p(n), given Rot(-n theta) p: the point turned back by member n's own turn.
    std::function<ir::ValueId(ir::ValueId n, ir::ValueId turnedX, ir::ValueId turnedY)> residual;
    // Rot(-angle) p.
    std::function<std::pair<ir::ValueId, ir::ValueId>(ir::ValueId angle)> unturn;
    // The footprint mean of the band of residuals `half` either side of `centre`.
    std::function<ir::ValueId(ir::ValueId centre, ir::ValueId half)> bandMean;
};

// The footprint mean of the union of every member's stroke in [lo, end), for a period found
// (period.q > 0).
ir::ValueId chainInk(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period);

} // namespace moire::lower
