// The few chains of a long period that can reach a pixel (docs/filtering.md, "A long period:
// the chains that reach the pixel"). Where a walking family's turn is 2 pi p / q with q past
// the chains drawn one by one (kMaxChains), member n's turn is sign 2 pi k / q + n e / q, with
// k = n p mod q its chain's place around the turn and e the period's remainder (TurnPeriod).
// A polygon's far member is its facet's line (or a vertex's two), whose residual at the pixel
// depends on the turn alone but for a level moving evenly with n: so the members that reach
// the pixel lie at two turns, where the residual over a full turn crosses zero, and their
// chains are two short windows of consecutive k. Those windows are found here, from the
// residual over a turn at the first and the last far member; the chains within them are
// drawn by WalkingChains, and the near members before the first far one one by one.
#pragma once

#include "compiler/lower/WalkingChains.h"

namespace moire::lower {

// Chains drawn a window, at most: past it the estimate takes over.
constexpr double kSelectSlots = 8;

// Two windows of chains, k in [from, from + count) (mod q) each, and how far they hold:
// 1 where the residual over a turn crosses zero twice at both ends, nowhere else within
// reach, and each window spans under kSelectSlots - 2 chains; 0 where any of that fails
// (falling smoothly as the wider window grows to kSelectSlots - 1).
// Each window's members are nearly one line at the pixel: `normalX`, `normalY` is its normal
// in the frame of the point the residual is read at, and `along`, `across` the pixel's
// extents across it (set by the caller, which knows the pixel's frame).
struct ChainWindows {
    ir::ValueId weight;
    ir::ValueId from[2], count[2];
    ir::ValueId normalX[2], normalY[2];
    ir::ValueId along[2], across[2];
};

// The windows of the members [in.split, in.end) at the pixel, for a period found (q > 0).
ChainWindows selectChains(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period);

// v mod q for whole v and q, exact in single precision where |v| < 2^24.
ir::ValueId wholeMod(ir::Builder& b, ir::ValueId v, ir::ValueId q);

} // namespace moire::lower
