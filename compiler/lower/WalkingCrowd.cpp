// The walking solver's crowd under the mean filter (docs/filtering.md "Walking families past
// the budget"): how far the compose step hands the searched member over to the crowd, the
// windows of the closed forms, and the chains drawn member by member (WalkingChains.h,
// ChainSelection.h); the estimate's density is WalkingDensity.cpp's.
#include "compiler/ir/Plane.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/ChainSelection.h"
#include "compiler/lower/WalkingSolver.h"

#include <numbers>

namespace moire::lower::walking {

// The crowd estimate for the mean filter (LayerFields::crowd, docs/filtering.md "Walking
// families past the budget"): where the interval is wider than the budget the scan strides
// and misses members, so the ink it draws is too light; the compose step then hands it over
// to the crowd's mean ink (`mean`, from `density`, members per unit of residual across the
// stroke, crowdDensity in WalkingDensity.cpp), by `engaged`. Where the turn has a short
// period (no turn included), the crowd is not estimated but drawn, member by member, chain by
// chain (chains(), WalkingChains.h); the estimate serves every other turn.
//
// `engaged` is smoothstep(B / 2, B, span): 0 where the interval is well inside the budget,
// 1 from where the scan strides. Where the answer is a closed form (§7.5), which finds the
// nearest member alone, it is how near the nearest's neighbours come (closedCrowding), and
// the members are drawn as one chain: those closed forms do not turn the shape (or turn a
// circle, which is the same), so the family is a translated shape, a period of one member.
// `nearest` and `argmin` are the solver's answer (|h_p| and the member), (gradX, gradY) its
// index gradient (the nearest member's normal; kNoValue where the index is not computed).
CrowdEstimate Solver::crowd(ValueId nearest, ValueId argmin, ValueId gradX, ValueId gradY) {
    ValueId nHi = b_.min(crowdHiRaw_, b_.add(crowdLo_, c(kWalkSpanCap - 1.0)));
    ValueId span = b_.add(b_.sub(nHi, crowdLo_), c(1.0));
    ValueId end = b_.add(crowdLo_, span);
    const double budget = variant().budget;
    ValueId exact = b_.emit(Op::Or, {still_, quadratic_});
    if (variant().polygonClosedForm) exact = b_.emit(Op::Or, {exact, closedPolygon_});
    const Across foot = across(gradX, gradY);
    ValueId engaged = b_.ifThenElse(
        exact, [&] { return Vals{closedCrowding(argmin, foot)}; },
        [&] { return Vals{b_.smoothstep(c(0.5 * budget), c(budget), span)}; })[0];
    Vals got = b_.ifThenElse(
        b_.gt(engaged, c(0.0)),
        [&] {
            // One chain drawing serves both (each instance is a large piece of every
            // backend's code): a closed form's window about its answer, with a period of
            // one member and the footprint across its normal, or the interval's first
            // members with the turn's period, each facing its own box.
            TurnPeriod turned = turnPeriod(b_, in_.turn);
            auto [from, to] = closedWindow(nearest, argmin, foot);
            auto pick = [&](ValueId closed, ValueId strided) {
                return b_.select(exact, closed, strided);
            };
            TurnPeriod period{pick(c(1.0), turned.q), pick(c(0.0), turned.p),
                              pick(c(0.0), turned.drift), pick(c(0.0), turned.inverse)};
            const Across box = facing();
            Across footprint{pick(foot.along, box.along), pick(foot.across, box.across)};
            // Every chain where the period is short; past it, a polygon's chains that
            // reach the pixel (ChainSelection.h), where its near members are few.
            ValueId all = both(b_.gt(period.q, c(0.0)), b_.le(period.q, c(kMaxChains)));
            // Picked only at the marginal drift with a turn that returns (its members a
            // period apart within a quarter of a pixel over the interval): there every far
            // member of a chain is one stroke, so each chain is drawn up to two periods
            // past `split` (later members add nothing), which keeps its residuals where
            // single precision still tells them apart (at n = 2^16 their ulp is a tenth of
            // a thin stroke). A quarter of a pixel, not less: a float's remainder of a
            // turn that returns exactly is about 1e-6 (q ulps of the turn), which moves the
            // members of the span cap 9e-5 r pixels at q = 720, and the JIT must pick where
            // the interpreter does out to the corners of a 4K frame.
            ValueId split = farMembersFrom(end);
            ValueId marginal = b_.le(b_.abs(b_.sub(drift_, s_)), c(kWalkMarginal));
            ValueId turnsBack = b_.le(
                b_.mul(b_.abs(b_.div(period.drift, b_.max(period.q, c(1.0)))), b_.mul(span, r_)),
                b_.mul(memberPixel(), c(0.25)));
            ValueId picked = both(both(b_.emit(Op::Not, {exact}), b_.emit(Op::Not, {round_})),
                                  both(b_.gt(period.q, c(kMaxChains)),
                                       b_.le(b_.sub(split, crowdLo_), c(kNearDrawn))));
            picked = both(picked, both(marginal, turnsBack));
            ValueId pickedEnd = b_.min(end, b_.add(split, b_.mul(period.q, c(2.0))));
            Vals drawn = b_.ifThenElse(
                b_.emit(Op::Or, {all, picked}),
                [&] {
                    ValueId lo = pick(from, crowdLo_);
                    return chains(period, lo, b_.select(all, pick(to, end), pickedEnd), footprint,
                                  b_.emit(Op::Not, {all}), b_.select(all, lo, split));
                },
                [&] {
                    return Vals{c(0.0), c(0.0)};
                });
            ValueId weight = b_.select(all, c(1.0), drawn[1]);
            return b_.ifThenElse(
                b_.lt(weight, c(1.0)),
                [&] {
                    Vals estimate = crowdDensity(span);
                    return Vals{estimate[0], b_.mix(estimate[1], drawn[0], weight)};
                },
                [&] {
                    return Vals{c(0.0), drawn[0]};
                });
        },
        [&] {
            return Vals{c(0.0), c(0.0)};
        });
    CrowdEstimate out; // got[0], the density, is what the mean is made of
    out.engaged = engaged;
    out.mean = got[1];
    return out;
}

// The members [from, to) a closed form's chain draws: those about the nearest member n
// that can reach the footprint. Where the drift m is under the spacing, h_p falls by at
// least s - m a member (dh/dn = grad rho . (-delta) - s <= rho(-delta) - s, rho a support
// function), so a member k from n is at least |k| (s - m) - |h_p(n)| from the pixel, and
// none past (reach + |h_p(n)|) / (s - m) members reaches it: the bisections then take a few
// steps. Elsewhere (a circle faster than its spacing, whose second zero can lie anywhere
// along the interval; the marginal drift) the window of the span cap centred on n, within
// Theorem 4's interval.
std::pair<ValueId, ValueId> Solver::closedWindow(ValueId nearest, ValueId argmin,
                                                 const Across& foot) {
    ValueId n = answerIndex(argmin);
    ValueId gap = b_.sub(s_, drift_);
    ValueId far = b_.denan(b_.add(memberReach(foot), b_.min(nearest, c(kFar))), c(kFar));
    ValueId within = b_.add(b_.floor(b_.div(far, b_.max(gap, c(1e-30)))), c(1.0));
    ValueId half = b_.select(b_.gt(gap, c(kWalkMarginal)), b_.min(within, c(0.5 * kWalkSpanCap)),
                             c(0.5 * kWalkSpanCap));
    // n - half .. n + half, moved within the interval where it reaches past an end.
    ValueId size = b_.add(b_.mul(half, c(2.0)), c(1.0));
    ValueId from = b_.clamp(b_.sub(n, half), crowdLo_,
                            b_.max(crowdLo_, b_.sub(b_.add(crowdHiRaw_, c(1.0)), size)));
    ValueId to = b_.min(b_.add(from, size), b_.add(crowdHiRaw_, c(1.0)));
    return {from, to};
}

// How far a closed form's answer (the nearest member, whose stroke the compose step draws
// across its own normal) is to be handed over to the chain's union of every member within
// reach: 1 where a neighbour of the nearest member, n - 1 or n + 1, comes within reach of
// the footprint, 0 from half a pixel beyond, smoothly between. Where no neighbour reaches,
// the nearest member's stroke is all the ink there is but where the residual has a second
// zero far in index (a translated circle faster than its spacing crosses itself): members
// crossing within one pixel there count once, as they do where the members are resolved.
// The two answers agree where the hand-over starts, to the footprint's shape.
// Not handed over where single precision cannot place the members: on the marginal drift's
// flat tail (the far members stand at one residual, at indices past any window) and where
// the residual's terms, about n (s + ||delta||), pass kFloatReach pixels: next to the
// marginal drift members are packed 2e-4 apart, and a float residual's differences between
// them break the convexity the chain's bisection reads (at 2^16 pixels the JIT's picture
// was 0.5 of ink off the interpreter's at 0.5% of the pixels). There the nearest member's
// stroke is drawn alone, as the point rule's search finds it.
ValueId Solver::closedCrowding(ValueId argmin, const Across& foot) {
    counting_ = false;
    ValueId n = answerIndex(argmin);
    ValueId after = b_.abs(residual(b_.add(n, c(1.0))));
    ValueId before = b_.abs(residual(member(b_.sub(n, c(1.0)))));
    counting_ = true;
    ValueId first = eq(n, c(0.0));
    ValueId tail = b_.emit(Op::Ge, {n, c(kFarIndex)});
    ValueId next = b_.select(first, after, b_.min(before, after));
    next = b_.denan(b_.select(tail, c(kFar), next), c(kFar));
    ValueId pixel = memberPixel();
    ValueId from = b_.add(memberReach(foot), b_.mul(pixel, c(0.25)));
    ValueId near = b_.sub(c(1.0), b_.smoothstep(from, b_.add(from, b_.mul(pixel, c(0.5))), next));
    ValueId size = b_.mul(b_.add(n, c(1.0)), b_.add(s_, len_));
    ValueId resolved = b_.sub(c(1.0), b_.smoothstep(b_.mul(pixel, c(kFloatReach)),
                                                    b_.mul(pixel, c(2.0 * kFloatReach)), size));
    return b_.mul(near, resolved);
}

// A turn of a short period (no turn included), drawn member by member, chain by chain
// (WalkingChains.h), over the members [lo, end). Not counted in the tally.
// `foot` is the footprint across the members' normal (a box facing each, `facing()`, where
// they turn). Where `picked`, a long period: the chains that reach the pixel alone, from
// `split` on, and the near members before it one by one (ChainSelection.h).
// Returns the ink and how far the picked chains hold (1 where every chain is drawn).
Vals Solver::chains(const TurnPeriod& period, ValueId lo, ValueId end, const Across& foot,
                    ValueId picked, ValueId split) {
    ChainInputs in = pointAccess();
    in.turn = in_.turn;
    in.stroke = in_.stroke;
    in.lo = lo;
    in.end = end;
    in.split = split;
    // Picked windows are drawn across their own normal: the reach of a square pixel's
    // diagonal bounds every footprint's.
    in.reach = b_.select(picked, b_.add(memberHalf(), b_.mul(memberPixel(), c(kHalfDiagonal))),
                         memberReach(foot));
    in.bandMean = [&](ValueId centre, ValueId half, ValueId along, ValueId across) {
        return bandMean(centre, half, Across{along, across});
    };
    in.along = foot.along;
    in.across = foot.across;
    counting_ = false;
    Vals windows = b_.ifThenElse(
        picked,
        [&] {
            ChainWindows w = selectChains(b_, in, period);
            Vals out{w.weight, w.from[0], w.count[0], w.from[1], w.count[1]};
            for (int k = 0; k < 2; ++k) {
                // The normal in the point's frame, taken to the pixel's (the chain rule
                // through the layer's frame), then across the pixel's sides.
                auto [gx, gy] = toPixelFrame(w.normalX[k], w.normalY[k]);
                Across a = across(gx, gy);
                out.push_back(a.along);
                out.push_back(a.across);
            }
            return out;
        },
        [&] {
            return Vals{c(1.0),     c(0.0),      c(0.0),     c(0.0),     c(0.0),
                        foot.along, foot.across, foot.along, foot.across};
        });
    ChainWindows win;
    win.weight = windows[0];
    win.from[0] = windows[1], win.count[0] = windows[2];
    win.from[1] = windows[3], win.count[1] = windows[4];
    win.along[0] = windows[5], win.across[0] = windows[6];
    win.along[1] = windows[7], win.across[1] = windows[8];
    ValueId ink = b_.ifThenElse(
        b_.gt(win.weight, c(0.0)), [&] { return Vals{chainInk(b_, in, period, picked, win)}; },
        [&] { return Vals{c(0.0)}; })[0];
    counting_ = true;
    // A NaN radius (see run()) draws nothing here either.
    return {b_.denan(ink, c(0.0)), win.weight};
}

// The residual at a turned point and the point turned, for WalkingChains' helpers.
ChainInputs Solver::pointAccess() {
    ChainInputs in;
    in.residual = [this](ValueId n, ValueId x, ValueId y) { return residualAt(n, x, y); };
    in.unturn = [this](ValueId angle) { return unturn(angle); };
    return in;
}

// A gradient in the frame of the point p, (x, y), as one in the pixel's (the independent
// variables'): J^T (x, y), J the Jacobian of p, so that a layer's own turn is kept.
std::pair<ValueId, ValueId> Solver::toPixelFrame(ValueId x, ValueId y) {
    ValueId gx =
        b_.add(b_.mul(x, b_.emit(Op::DerivX, {in_.px})), b_.mul(y, b_.emit(Op::DerivX, {in_.py})));
    ValueId gy =
        b_.add(b_.mul(x, b_.emit(Op::DerivY, {in_.px})), b_.mul(y, b_.emit(Op::DerivY, {in_.py})));
    return {gx, gy};
}

// The first member whose residual at the pixel is its far form (ChainSelection.h): past
// n ||delta|| sin(pi / N) = r, the pulled-back point stays within the facet (or the two at
// a vertex) that faces -delta, and the residual over a turn is that facet's line moved by
// n (m - s) alone; kFarForm times that, within [crowdLo_, end].
ValueId Solver::farMembersFrom(ValueId end) {
    ValueId sinHalf = b_.sqrt(b_.sub(c(1.0), b_.mul(kappa_, kappa_)));
    ValueId n = b_.div(b_.mul(r_, c(kFarForm)), b_.max(b_.mul(len_, sinHalf), c(1e-9)));
    n = b_.neg(b_.floor(b_.neg(b_.min(n, c(kFar)))));
    return b_.clamp(b_.denan(n, end), crowdLo_, end);
}

} // namespace moire::lower::walking
