// The walking solver's crowd density, where the members past the budget are estimated rather
// than drawn: few turns' crossings (drawn in WalkingTurns.cpp), many turns' arcsine average
// with its near field counted or phase-averaged, and the members a period of the turn apart
// that fall on one another (WalkingCrowd.cpp hands over to it).
#include "compiler/ir/Plane.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/ChainSelection.h"
#include "compiler/lower/Convergents.h"
#include "compiler/lower/WalkingSolver.h"

#include <numbers>

namespace moire::lower::walking {

// Why members per unit of residual is what the ink needs: member n inks the points where
// |h_p(n)| < h. Over a footprint, a member crossing it with |grad_p h| = g covers a band
// 2h / g wide, and members cross at g / |dh/dn| per unit of length (the implicit function
// n(p) of h_p(n) = 0 has |grad n| = |grad_p h| / |dh/dn|). g cancels: the ink is
// 2h sum_i 1 / |dh/dn(n_i)| over the zeros n_i of h_p, and sum_i 1 / |dh/dn(n_i)| is the
// measure of {n : |h_p(n)| < e} / 2e as e -> 0 (the coarea formula in one variable).
//
// That sum is read two ways, mixed by how many full turns the interval's members make
// (|theta| x span / 2 pi):
//  - Few turns: every zero of h over the interval, found by sampling and bisection
//    (turnsDrawn, WalkingTurns.cpp), each with its 1 / |dh/dn| read by a difference of h
//    across it, exact where h is linear over one member; the members about each are drawn.
//  - Many turns: far out (n ||delta|| >> r) the pulled-back point is -n delta plus a point
//    circling at radius r, so rho(q_n) = n m + u . Rot(-n theta) p to first order (u the
//    unit normal of the shape at -delta, m = rho(-delta)), and
//        h_p(n) = c(n) + r cos(n theta - beta),   c(n) = n (m - s) - phase.
//    Over a turn the cosine's phase runs evenly, so its values have the arcsine density
//    1 / (pi sqrt(r^2 - c^2)) at -c, and the measure of members with |h| < e, per 2e, is
//        density = (1 / pi) integral over [n_lo, n_hi + 1] of dn / sqrt(r^2 - c(n)^2)
//                = (n_hi + 1 - n_lo) / (pi r) x (asin x_b - asin x_a) / (x_b - x_a),
//    x = c(n) / r at the interval's ends (asin clamps: members whose c is out of reach
//    of the cosine cross nowhere). As m -> s the quotient tends to 1 / sqrt(1 - x^2):
//    every member of the (capped) interval crosses, each with 1 / (pi sqrt(r^2 - phase^2)).
//    With m far from s it tends to 1 / |m - s|: one member a |m - s| of residual.
//    The first order holds where n ||delta|| >> r. Nearer (n ||delta|| < 2 r) the first
//    kNearCounted members are counted one by one (countedCrossings), the rest averaged over
//    the phase with the whole residual (phaseAveraged); beyond, members a period of the turn
//    apart that fall on one another are counted once (crowdCoincidence): the ink is their
//    union, not their sum (branchesInk).
//
// The crowd's density and its mean ink.
Vals Solver::crowdDensity(ValueId span) {
    ValueId rr = b_.max(r_, b_.mul(s_, c(1e-6)));
    ValueId k = b_.sub(drift_, s_);
    ValueId end = b_.add(crowdLo_, span);
    // Many turns: the arcsine average, its near field (n ||delta|| < 2 r, where the first
    // order above is rough but every member is its own) and its far field, where members
    // a period of the turn apart fall on one another (crowdCoincidence). The near field's
    // first kNearCounted members are counted one by one, the rest of it averaged over the
    // phase (nearDensity). The filter's evaluations are not the search's: the tally (the
    // solver's cost in the experiments) leaves them out.
    ValueId far = b_.clamp(b_.div(b_.mul(rr, c(2.0)), b_.max(len_, c(1e-9))), crowdLo_, end);
    ValueId width = b_.max(in_.stroke, c(1e-9));
    counting_ = false;
    ValueId counted = b_.min(far, b_.add(crowdLo_, c(kNearCounted)));
    ValueId nearPart = nearDensity(crowdLo_, counted, far);
    counting_ = true;
    ValueId farArcsine = b_.add(arcsineDensity(far, end, k, rr), vertexChange(far, end, k, rr));
    ValueId farShare = crowdCoincidence(far, end, k, rr, 2.0);
    ValueId averaged = b_.add(nearPart, b_.mul(farArcsine, farShare));
    // The mirror: where the far members' line offsets c(n) = n (m - s) - phase all stay
    // within the stroke of 0 (the marginal drift at a zero phase), each far member is a
    // line through the origin, and member n + j with j theta = pi (mod 2 pi) draws member
    // n's line again, seen from the other side (h changes sign, |h| does not). The two
    // branches are then one set of lines, at angles n theta (mod pi): one comb, not two
    // independent ones. Its distinct lines are counted by the coincidence of the turn
    // modulo a half turn, each line crossing once: ink min(1, width x density_pi). The
    // near members (n ||delta|| < 2 r) stay two independent combs, laid over it.
    ValueId cFar = b_.max(b_.abs(b_.sub(b_.mul(far, k), in_.phase)),
                          b_.abs(b_.sub(b_.mul(end, k), in_.phase)));
    ValueId mirror =
        b_.sub(c(1.0), b_.smoothstep(b_.mul(width, c(0.5)), width, b_.mul(cFar, c(2.0))));
    // Polygons only: a circle's member and its mirror bend to opposite sides of their
    // common tangent at the origin, and counting them as one stroke drew the circles of
    // walking_mean's strided band further from their exact ink (measured), not nearer.
    mirror = b_.select(round_, c(0.0), mirror);
    // Few turns: the crossings of h_p(n) = 0 in n, sampled and drawn (turnsDrawn), the
    // arcsine taking over from kFewTurns to twice as many. No turn at all is a period of one
    // member, drawn as one chain (chains()), not here.
    ValueId turns = b_.div(b_.mul(b_.abs(in_.turn), span), c(2.0 * std::numbers::pi));
    ValueId many = b_.smoothstep(c(kFewTurns), c(2.0 * kFewTurns), turns);
    // Drawn, the passages of successive turns that fall on one another (members a full turn
    // apart, q = 2 pi / |theta| of them, within the stroke: q |m - s| + r |q theta - 2 pi|
    // under its width), or a far line and its mirror half a turn on, would each be laid over
    // the other: the estimate counts them once, so it takes over where the interval holds
    // both (a square at the marginal drift turning 0.05 degrees a member, nine turns over its
    // interval, drew 0.98 ink where the exact field has 0.71).
    ValueId turnMembers = b_.div(c(2.0 * std::numbers::pi), b_.max(b_.abs(in_.turn), c(1e-9)));
    ValueId fullTurn = b_.round(turnMembers);
    ValueId returned = b_.add(
        b_.abs(b_.mul(fullTurn, k)),
        b_.mul(rr, b_.abs(b_.sub(b_.mul(fullTurn, b_.abs(in_.turn)), c(2.0 * std::numbers::pi)))));
    ValueId passagesApart = b_.select(
        b_.gt(span, fullTurn), b_.smoothstep(b_.mul(width, c(0.5)), width, returned), c(1.0));
    ValueId mirrorApart =
        b_.select(b_.gt(span, b_.mul(turnMembers, c(0.5))), b_.sub(c(1.0), mirror), c(1.0));
    ValueId distinct = b_.mul(passagesApart, mirrorApart);
    many = b_.sub(c(1.0), b_.mul(b_.sub(c(1.0), many), distinct));
    counting_ = false;
    // A polygon's residual wiggles once a facet over a turn, on top of the turn's cosine, and
    // each wiggle's turns want a few samples (nonagons two a pixel at a degree a member drew
    // 2% light at 24 samples a turn, their exact ink at six a facet).
    ValueId perTurn =
        b_.max(c(kCrossingSamplesPerTurn), b_.mul(in_.facets, c(kCrossingSamplesPerFacet)));
    ValueId samples = b_.max(c(kCrossingSamples), b_.floor(b_.mul(turns, perTurn)));
    const Vals few = b_.ifThenElse(
        b_.lt(many, c(1.0)),
        [&] { return turnsDrawn(crowdLo_, b_.sub(end, c(1.0)), width, samples); },
        [&] {
            return Vals{c(0.0), c(0.0)};
        });
    counting_ = true;
    ValueId density = b_.denan(b_.mix(few[0], averaged, many), c(0.0));
    ValueId twice = branchesInk(width, averaged, farShare, rr);
    Vals mirrored = b_.ifThenElse(
        b_.gt(mirror, c(0.0)),
        [&] {
            // Every member passes through the origin, on the facet that faces it, whose
            // half-length is n s tan(pi / N): a member past n = r / (||delta|| tan(pi / N))
            // crosses p on that facet, which lies on one of the far lines, so it is counted
            // with the lines, not as a near member of its own (counted apart, the two drew
            // a square of spacing 3 at a 3 degree turn at 0.46 ink against the exact 0.36).
            ValueId tanHalf =
                b_.div(b_.sqrt(b_.max(b_.sub(c(1.0), b_.mul(kappa_, kappa_)), c(0.0))), kappa_);
            ValueId onFacet =
                b_.clamp(b_.div(rr, b_.max(b_.mul(len_, tanHalf), c(1e-9))), crowdLo_, far);
            counting_ = false;
            ValueId ownCounted = b_.min(onFacet, b_.add(crowdLo_, c(kNearCounted)));
            ValueId own = nearDensity(crowdLo_, ownCounted, onFacet);
            counting_ = true;
            ValueId nearComb = b_.min(c(1.0), b_.mul(b_.mul(width, c(0.5)), own));
            ValueId lineDensity = b_.add(arcsineDensity(onFacet, far, k, rr), farArcsine);
            ValueId lines = b_.min(
                c(1.0),
                b_.mul(width, b_.mul(lineDensity, crowdCoincidence(onFacet, end, k, rr, 1.0))));
            ValueId blank = b_.mul(b_.mul(b_.sub(c(1.0), nearComb), b_.sub(c(1.0), nearComb)),
                                   b_.sub(c(1.0), lines));
            return Vals{b_.mix(twice, b_.sub(c(1.0), blank), mirror)};
        },
        [&] { return Vals{twice}; });
    return {density, b_.denan(b_.mix(few[1], mirrored[0], many), c(0.0))};
}

ValueId Solver::changesSign(ValueId h0, ValueId h1) {
    return b_.emit(Op::Ne, {negative(h0), negative(h1)});
}

// 1 / |dh|, the members (or turns) per unit of residual across a crossing; held finite
// where h is flat.
ValueId Solver::perResidual(ValueId dh) {
    return b_.div(c(1.0), b_.max(b_.abs(dh), b_.mul(s_, c(1e-6))));
}

// The near field past the members counted one by one: the coarea sum of [a, b] with each
// member's phase n theta taken as evenly spread over a turn (the run makes many turns) but
// its residual taken whole, not to first order: at kPhaseNodes members n of the run, the
// crossings of h(n, phi) = rho(Rot(-phi) p - n delta) - (n s + phase) = 0 over a turn of
// phi, sampled at kPhaseAngles angles, each sign change contributing 1 / (M |dh|) (the
// density (1 / 2 pi) sum 1 / |dh/dphi| of its zeros), times the run's length. Near the
// origin of the walk every facet of the shape takes part, which the first order's one
// cosine leaves out (it drew a hexagon at the marginal drift 15% light).
ValueId Solver::phaseAveraged(ValueId a, ValueId b) {
    ValueId count = b_.max(b_.sub(b, a), c(0.0));
    ValueId dn = b_.div(count, c(kPhaseNodes));
    const double angle = 2.0 * std::numbers::pi / kPhaseAngles;
    Vals res = b_.loop(
        {c(0.0), c(0.0)},
        [&](std::span<const ValueId> v) {
            return Vals{both(b_.lt(v[0], c(kPhaseNodes)), b_.gt(count, c(0.0)))};
        },
        [&](std::span<const ValueId> v) {
            ValueId n = b_.add(a, b_.mul(b_.add(v[0], c(0.5)), dn));
            auto at = [&](ValueId phi) {
                auto [qx, qy] = unturn(phi);
                return residualAt(n, qx, qy);
            };
            ValueId first = at(c(0.0));
            Vals turn = b_.loop(
                {c(1.0), first, c(0.0)},
                [&](std::span<const ValueId> u) { return Vals{b_.le(u[0], c(kPhaseAngles))}; },
                [&](std::span<const ValueId> u) {
                    ValueId h = at(b_.mul(u[0], c(angle)));
                    ValueId add =
                        b_.select(changesSign(u[1], h),
                                  b_.div(perResidual(b_.sub(h, u[1])), c(kPhaseAngles)), c(0.0));
                    return Vals{b_.add(u[0], c(1.0)), h, b_.add(u[2], add)};
                });
            return Vals{b_.add(v[0], c(1.0)), b_.add(v[1], b_.mul(turn[2], dn))};
        });
    return res[1];
}

// The coarea sum over members one by one: sum of 1 / |h(n + 1) - h(n)| over the n in
// [lo, hi) where h changes sign (each a crossing between two members, exact where h is
// linear over one member), for the near field, where the first order is rough.
// `fade` > 0: crossings within `fade` members of hi count less, linearly to none at hi.
ValueId Solver::countedCrossings(ValueId lo, ValueId hi, ValueId fade) {
    Vals res = b_.loop(
        {lo, residual(lo), c(0.0)},
        [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], hi)}; },
        [&](std::span<const ValueId> v) {
            ValueId next = b_.add(v[0], c(1.0));
            ValueId h = residual(next);
            ValueId weight = b_.select(
                b_.gt(fade, c(0.0)),
                b_.clamp(b_.div(b_.sub(hi, next), b_.max(fade, c(1.0))), c(0.0), c(1.0)), c(1.0));
            ValueId add = b_.select(changesSign(v[1], h),
                                    b_.mul(weight, perResidual(b_.sub(h, v[1]))), c(0.0));
            return Vals{next, h, b_.add(v[2], add)};
        });
    return res[2];
}

// The near field [lo, b): counted one by one up to hi, phase-averaged beyond. Where the
// two meet, the counted crossings fade out over kSeamFade members and the average starts
// half as many members early, so that a crossing moving across the seam as p moves
// changes the estimate smoothly (a hard seam drew sawtooth edges along it).
ValueId Solver::nearDensity(ValueId lo, ValueId hi, ValueId b) {
    ValueId seam = b_.lt(hi, b);
    ValueId fade = b_.select(seam, c(kSeamFade), c(0.0));
    ValueId from = b_.select(seam, b_.max(lo, b_.sub(hi, c(0.5 * kSeamFade))), b);
    return b_.add(countedCrossings(lo, hi, fade), phaseAveraged(from, b));
}

// The ink of many turns' members, `density` of them per unit of residual. The cosine
// crosses the member's level twice a turn, so the members form two branches, and each
// branch crosses a pixel in passages, one a turn. Within a passage consecutive members
// step about |theta| r apart in residual, nearly evenly (the phases n theta of a run of
// members are nearly evenly spread: the three-gap theorem), so a passage is a comb inking
// x_p = min(1, width / (|theta| r)) of what it crosses. Passages a turn apart land wherever
// the drift has moved them, as if independently: with E = width x density the summed
// coverage and E / x_p passages, the union inks 1 - (1 - x_p)^(E / x_p) (1 - exp(-E) for
// thin combs). Where a period of the turn brings the passages back onto one another (the
// far run's share of distinct members, `share`, under 1), they are one comb a branch
// instead, the two laid over one another: 1 - (1 - x)^2, x = min(1, E / 2); weighted by
// the share of coincident members. With two passages or fewer the two forms agree.
ValueId Solver::branchesInk(ValueId width, ValueId density, ValueId share, ValueId r) {
    ValueId coverage = b_.mul(width, density);
    ValueId comb = b_.min(c(1.0), b_.mul(coverage, c(0.5)));
    ValueId twice = b_.mul(comb, b_.sub(c(2.0), comb));
    ValueId perPassage =
        b_.min(c(1.0), b_.div(width, b_.max(b_.mul(b_.abs(in_.turn), r), c(1e-9))));
    ValueId passages = b_.div(coverage, b_.max(perPassage, c(1e-9)));
    ValueId left = b_.max(b_.sub(c(1.0), perPassage), c(1e-9));
    ValueId scattered =
        b_.sub(c(1.0), b_.emit(Op::Exp, {b_.mul(passages, b_.emit(Op::Log, {left}))}));
    return b_.select(b_.gt(passages, c(2.0)), b_.mix(scattered, twice, b_.sub(c(1.0), share)),
                     twice);
}

// (1 / pi) integral over [na, nb] of dn / sqrt(r^2 - c(n)^2), c(n) = n k - phase, as
// (nb - na) / (pi r) x (asin x_b - asin x_a) / (x_b - x_a), x = c / r; the quotient's limit
// 1 / sqrt(1 - x^2) where x_b - x_a is too small to divide by (k -> 0). 0 where nb <= na.
ValueId Solver::arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r) {
    return arcsineDensity(na, nb, k, r, c(-1.0), c(1.0));
}

// The same, counting only the members whose x lies in [lo, hi] (within [-1, 1]).
ValueId Solver::arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r, ValueId lo,
                               ValueId hi) {
    ValueId xa = b_.div(b_.sub(b_.mul(na, k), in_.phase), r);
    ValueId xb = b_.div(b_.sub(b_.mul(nb, k), in_.phase), r);
    ValueId dx = b_.sub(xb, xa);
    ValueId mid = b_.mul(b_.add(xa, xb), c(0.5));
    ValueId limit = b_.select(
        both(both(b_.lt(b_.abs(mid), c(1.0)), b_.emit(Op::Ge, {mid, lo})), b_.le(mid, hi)),
        b_.div(c(1.0), b_.sqrt(b_.max(b_.sub(c(1.0), b_.mul(mid, mid)), c(1e-12)))), c(0.0));
    auto asinIn = [&](ValueId x) { return b_.emit(Op::Asin, {b_.clamp(x, lo, hi)}); };
    ValueId quotient =
        b_.div(b_.sub(asinIn(xb), asinIn(xa)), b_.select(eq(dx, c(0.0)), c(1.0), dx));
    ValueId arcsine = b_.select(b_.lt(b_.abs(dx), c(1e-4)), limit, quotient);
    ValueId count = b_.max(b_.sub(nb, na), c(0.0));
    return b_.div(b_.mul(count, arcsine), b_.mul(c(std::numbers::pi), r));
}

// A polygon whose drift points at a vertex: far out, rho(-n delta + v) takes the larger of
// the two facets' projections, so h_p(n) = c(n) + r cos(||phi| - beta|), beta = pi / N the
// half angle between their normals, not c(n) + r cos(phi). As phi runs over a turn, a level
// L of that is crossed 4 times where L > r cos beta (two peaks), twice down to -r cos beta,
// and never below: against the one cosine's 2 crossings of every level in (-r, r), the
// arcsine average gains the band x = c / r < -cos beta once more and loses x > cos beta.
// Off the vertex the second facet's peak stands n Delta lower (Delta = m minus its
// projection of -delta), and once n Delta passes the peak's height above the valley
// between them, r (1 - cos beta), the one cosine holds again: the change is tapered by
// that at the run's first member. Circles: none.
ValueId Solver::vertexChange(ValueId na, ValueId nb, ValueId k, ValueId r) {
    ValueId beta = b_.emit(Op::Acos, {kappa_});
    ValueId len = b_.max(len_, c(1e-9));
    ValueId off = b_.emit(Op::Acos, {b_.clamp(b_.div(drift_, len), c(-1.0), c(1.0))});
    ValueId second = b_.mul(len, b_.cos(b_.sub(b_.mul(beta, c(2.0)), off)));
    ValueId delta = b_.max(b_.sub(drift_, second), c(0.0));
    ValueId height = b_.max(b_.mul(r, b_.sub(c(1.0), kappa_)), c(1e-9));
    ValueId taper =
        b_.clamp(b_.sub(c(1.0), b_.div(b_.mul(b_.max(na, c(0.0)), delta), height)), c(0.0), c(1.0));
    ValueId gained = arcsineDensity(na, nb, k, r, c(-1.0), b_.neg(kappa_));
    ValueId lost = arcsineDensity(na, nb, k, r, kappa_, c(1.0));
    return b_.select(round_, c(0.0), b_.mul(taper, b_.sub(gained, lost)));
}

// The share of `count` far members that are distinct strokes. Member n + q lies within
// dev(q) = |q k| + r |q theta - 2 pi p| of member n (the cosine moves by at most r times
// the angle it is turned by, the line by q k), for any whole p. The first q that brings
// dev under the stroke's width is a convergent denominator of theta / 2 pi (the best
// approximations), found by the continued fraction's recurrence. Then the far members fall
// into q chains, each of count / q members stepping dev apart, whose union is one stroke
// plus (count / q - 1) steps: q + (count - q) dev / width strokes of the count. A turn by a
// rational share of a full turn at the marginal drift (dev = 0) leaves exactly q distinct
// members however long the interval; no q within the count: all distinct.
//
// A circle bends where a polygon's facet is straight: far out the circles' members step
// apart by the curvature's r^2 / (2 n ||delta||) besides (the second order of |x - n delta|),
// so chain members a period q apart differ by dev + C / n^2, C = r^2 q / (2 ||delta||), and
// they are distinct up to n_c = sqrt(C / (width - dev)). Over the far run [a, b] the distinct
// strokes are then (n_c - a) + (dev / width)(b - n_c) + (C / width)(1 / n_c - 1 / b).
//
// `turns`: the period of the turn, in half turns: 2 (a member's stroke comes back after a
// full turn), or 1 (the mirror, a line through the origin comes back after half a turn).
ValueId Solver::crowdCoincidence(ValueId a, ValueId b, ValueId k, ValueId r, double turns) {
    ValueId count = b_.sub(b, a);
    ValueId width = b_.max(in_.stroke, c(1e-9));
    const double period = turns * std::numbers::pi;
    ValueId x = b_.div(b_.abs(in_.turn), c(period));
    if (turns < 2) { // fold into [0, 1/2]: x and 1 - x have the same denominators
        x = b_.sub(x, b_.floor(x));
        x = b_.min(x, b_.sub(c(1.0), x));
    }
    auto deviation = [&](ValueId p, ValueId q) {
        return b_.add(b_.abs(b_.mul(q, k)),
                      b_.mul(b_.mul(r, c(period)), b_.abs(b_.sub(b_.mul(q, x), p))));
    };
    auto fits = [&](ValueId p, ValueId q) {
        return both(b_.le(q, count), b_.lt(deviation(p, q), width));
    };
    const Convergent found = firstConvergent(b_, x, kCrowdConvergents, 1e-7, count, fits);
    ValueId q = found.q, dev = deviation(found.p, q);
    ValueId safe = b_.max(count, c(1.0));
    ValueId bend = b_.select(
        round_, b_.div(b_.mul(b_.mul(r, r), q), b_.mul(b_.max(len_, c(1e-9)), c(2.0))), c(0.0));
    ValueId from = b_.max(a, c(1.0)), to = b_.max(b, c(1.0));
    ValueId nc = b_.clamp(b_.sqrt(b_.div(bend, b_.max(b_.sub(width, dev), c(1e-9)))), from, to);
    ValueId distinct =
        b_.add(b_.add(b_.sub(nc, from), b_.mul(b_.div(dev, width), b_.sub(to, nc))),
               b_.mul(b_.div(bend, width), b_.sub(b_.div(c(1.0), nc), b_.div(c(1.0), to))));
    ValueId share = b_.div(b_.add(q, distinct), safe);
    return b_.select(b_.gt(q, c(0.0)), b_.min(share, c(1.0)), c(1.0));
}

} // namespace moire::lower::walking
