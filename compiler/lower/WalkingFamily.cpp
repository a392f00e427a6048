#include "compiler/lower/WalkingFamily.h"

#include "compiler/ir/Plane.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/WalkingSolver.h"

#include <limits>
#include <numbers>
#include <tuple>

namespace moire::lower::walking {

LayerFields Solver::run() {
    setUp();
    // The cheapest method that is exact for these parameters (§7.5). The conditions
    // depend on layer parameters only, so each pixel of a layer takes the same branch.
    // Sweep, the baseline without a certificate, has no such dispatch.
    // Under the mean filter every method also gives the ink of the members beside the
    // nearest (CrowdEstimate::others, a third value): the scan gathers it, a closed form
    // gives none.
    auto closed = [&](Vals v) {
        if (resolving()) v.push_back(c(0.0));
        return v;
    };
    auto polygonOrScan = [&] {
        if (!variant().polygonClosedForm) return scan();
        return b_.ifThenElse(
            closedPolygon_, [&] { return closed(translatedPolygon()); }, [&] { return scan(); });
    };
    Vals found =
        variant().solver == WalkingVariant::Solver::Sweep
            ? sweep()
            : b_.ifThenElse(
                  still_, [&] { return closed(concentric()); },
                  [&] {
                      return b_.ifThenElse(
                          quadratic_, [&] { return closed(translatedCircle()); }, polygonOrScan);
                  });
    LayerFields out;
    // min(G, d) with the guard first: the IR's min keeps its first operand when the
    // second is NaN, so a radius that is NaN everywhere (a shape with no sides, say) draws
    // nothing at a finite distance instead of writing NaN.
    out.distance = b_.min(guard_, found[0]);
    out.index = found[1];
    if (in_.wantIndex) searchedIndex(found[1], out);
    out.aux0 = nLo_;
    out.aux1 = nHiRaw_;
    if (in_.flankGuard) out.sample = phaseSample(found[0], found[1]);
    if (resolving()) {
        out.crowd = crowd(found[0], found[1], out.gradX, out.gradY);
        out.crowd.others = found[2];
    }
    return out;
}

// The mean filter is drawn by a solver that estimates its crowd (not the sweep baseline).
bool Solver::resolving() const {
    return in_.crowd && variant().solver != WalkingVariant::Solver::Sweep;
}

ValueId Solver::radius(ValueId qx, ValueId qy) {
    countEvaluations(1);
    if (!variant().supportFastPaths) return facetRadius(qx, qy);
    return rho_(b_, qx, qy);
}

// Table 6's "support fast paths" removed: a polygon's radius as the definition writes it
// (Eq. 16), the largest <q, u_k> over its N unit facet normals, the first facing +x, in a
// loop with u_k carried by a turn of 2 pi / N, in place of the family's folded form. A
// circle, or a side count that is no whole polygon's (a morph), keeps the family's own.
ValueId Solver::facetRadius(ValueId qx, ValueId qy) {
    return b_.ifThenElse(
        wholePolygon_, [&] { return Vals{facetLoop(qx, qy)}; },
        [&] { return Vals{rho_(b_, qx, qy)}; })[0];
}

ValueId Solver::facetLoop(ValueId qx, ValueId qy) {
    // Carried: facet k, u_k, the largest <q, u_k> so far.
    Vals res = b_.loop(
        {c(0.0), c(1.0), c(0.0), c(-kFar)},
        [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], in_.facets)}; },
        [&](std::span<const ValueId> v) {
            ValueId dot = b_.add(b_.mul(qx, v[1]), b_.mul(qy, v[2]));
            ir::Vec2T<BuiltValue> u =
                ir::rotate({BuiltValue(b_, v[1]), BuiltValue(b_, v[2])}, BuiltValue(b_, facetCos_),
                           BuiltValue(b_, facetSin_));
            return Vals{b_.add(v[0], c(1.0)), u.x.id, u.y.id, b_.max(v[3], dot)};
        });
    return res[3];
}

// Counts evaluations of the residual (of rho, or of its closed form) in the tally.
void Solver::countEvaluations(int count) {
    if (in_.tally && counting_)
        for (int i = 0; i < count; ++i) b_.emitSink(Op::Tally, {}, kRadiusTally);
}

// Rot(-angle) p: the point in the frame of a member turned by `angle`.
std::pair<ValueId, ValueId> Solver::unturn(ValueId angle) {
    BuiltValue cs(b_, b_.cos(angle)), sn(b_, b_.sin(angle));
    return unturn(cs, sn, in_.px, in_.py);
}

// Rot(-angle) (x, y), given the angle's cosine and sine.
std::pair<ValueId, ValueId> Solver::unturn(BuiltValue cs, BuiltValue sn, ValueId x, ValueId y) {
    ir::Vec2T<BuiltValue> q = ir::unrotate({BuiltValue(b_, x), BuiltValue(b_, y)}, cs, sn);
    return {q.x.id, q.y.id};
}

// The signed residual h_p(n) = rho(Rot(-n theta) p - n delta) - (n s + phase) (Eq. 24).
ValueId Solver::residual(ValueId n) {
    auto [qx, qy] = unturn(b_.mul(n, in_.turn));
    return residualAt(n, qx, qy);
}

// The same, with the turned point Rot(-n theta) p given.
ValueId Solver::residualAt(ValueId n, ValueId turnedX, ValueId turnedY) {
    ValueId qx = b_.sub(turnedX, b_.mul(n, in_.offsetX));
    ValueId qy = b_.sub(turnedY, b_.mul(n, in_.offsetY));
    return b_.sub(radius(qx, qy), b_.add(b_.mul(n, s_), in_.phase));
}

// Folds |h_p(n)| at one more index into (best, argmin). NaN candidates never win.
void Solver::consider(ValueId& best, ValueId& argmin, ValueId n, ValueId value) {
    ValueId v = b_.abs(value);
    ValueId better = b_.lt(v, best);
    best = b_.select(better, v, best);
    argmin = b_.select(better, n, argmin);
}

// The turn Rot(a) Rot(b), given both as a cosine and a sine.
std::pair<ValueId, ValueId> Solver::compose(std::pair<ValueId, ValueId> a,
                                            std::pair<ValueId, ValueId> b) {
    ir::Vec2T<BuiltValue> r = ir::rotate({BuiltValue(b_, b.first), BuiltValue(b_, b.second)},
                                         BuiltValue(b_, a.first), BuiltValue(b_, a.second));
    return {r.x.id, r.y.id};
}

void Solver::setUp() {
    s_ = b_.max(in_.spacing, c(1e-6));
    // The guard (Eq. 26): any distance past it draws nothing, so the search may stop there.
    StrokeBandT<BuiltValue> band{BuiltValue(b_, in_.band.h), BuiltValue(b_, in_.band.a)};
    guard_ = walkGuard(band, BuiltValue(b_, s_), in_.flankGuard ? 1.0 : kWalkGuardPitches).id;
    accept_ = b_.sub(in_.band.h, in_.band.a); // fully inked below this: stop early
    r_ = b_.hypot(in_.px, in_.py);
    len_ = b_.hypot(in_.offsetX, in_.offsetY);
    round_ = eq(in_.facets, c(0.0));
    ValueId whole = both(eq(in_.facets, b_.floor(in_.facets)),
                         both(b_.emit(Op::Ge, {in_.facets, c(3.0)}),
                              b_.emit(Op::Le, {in_.facets, c(kWalkMaxFacets)})));
    wholePolygon_ = whole;
    if (!variant().supportFastPaths) {
        ValueId step = b_.div(c(2.0 * std::numbers::pi), b_.max(in_.facets, c(1.0)));
        facetCos_ = b_.cos(step);
        facetSin_ = b_.sin(step);
    }
    // The drift constant m = rho(-delta) (Eq. 29): how fast member n outruns its radius.
    drift_ = rho_(b_, b_.neg(in_.offsetX), b_.neg(in_.offsetY));
    // kappa = cos(pi / N), the inradius of the shape's normals (Eq. 21); 1 for a circle.
    ValueId sides = b_.max(in_.facets, c(2.0));
    kappa_ = b_.select(round_, c(1.0), b_.cos(b_.div(c(std::numbers::pi), sides)));
    // Rot(2^j theta), j = 0 .. kCarriedPowers - 1: the scan's turns by 1 to 7 members at
    // stride 1. They depend on the turn alone, so they are computed once per frame (in
    // double) rather than as a cosine and a sine per pixel and per member.
    for (int j = 0; j < kCarriedPowers; ++j) {
        ValueId angle = b_.mul(in_.turn, c(double(1 << j)));
        turnPowers_[j] = {b_.cos(angle), b_.sin(angle)};
    }

    ValueId noOffset = eq(len_, c(0.0));
    ValueId noTurn = eq(in_.turn, c(0.0));
    still_ = both(noOffset, b_.emit(Op::Or, {noTurn, round_}));
    quadratic_ = both(round_, noTurn);
    closedPolygon_ = both(both(b_.emit(Op::Not, {round_}), noTurn),
                          both(whole, b_.emit(Op::Le, {drift_, b_.add(s_, c(kWalkMarginal))})));

    std::tie(nLo_, nHiRaw_) = interval(guard_);
    // The crowd (below) is estimated over the interval of the pattern's own guard, so that
    // a view that widens the guard to read the flanking members (the split's left half)
    // draws the pattern the pattern view draws.
    std::tie(crowdLo_, crowdHiRaw_) =
        in_.flankGuard ? interval(walkGuard(band, BuiltValue(b_, s_), kWalkGuardPitches).id)
                       : std::pair{nLo_, nHiRaw_};
}

// Theorem 4's interval [n_lo, n_hi] for a guard distance, with the per-branch upper bounds
// of §7.6 (n_hi uncapped).
std::pair<ValueId, ValueId> Solver::interval(ValueId guard) {
    ValueId kr = b_.mul(kappa_, r_);
    ValueId lo = member(
        b_.floor(b_.div(b_.sub(b_.sub(kr, in_.phase), guard), b_.add(s_, b_.mul(kappa_, len_)))));
    // Loose (§9.1, Table 6's "exact drift" removed): the obvious bound ||delta|| >= m in
    // place of m. It widens the interval, and where m < s < ||delta|| it even takes the
    // wrong branch, so it can lose ink; it never invents any (a minimum over members).
    ValueId intervalDrift = variant().solver == WalkingVariant::Solver::Loose ? len_ : drift_;
    ValueId gap = b_.sub(s_, intervalDrift);
    ValueId slower = b_.div(b_.add(b_.sub(r_, in_.phase), guard), gap);         // m < s
    ValueId faster = b_.div(b_.add(b_.add(r_, in_.phase), guard), b_.neg(gap)); // m > s
    ValueId hi =
        ceil(b_.select(b_.gt(gap, c(0.0)), slower, b_.select(b_.lt(gap, c(0.0)), faster, c(kFar))));
    return {lo, hi};
}

// delta = 0, and no turn (or a circle, which turning leaves alone): h_p is affine in n,
// one evaluation and a rounding.
Vals Solver::concentric() {
    ValueId v = b_.sub(radius(in_.px, in_.py), in_.phase);
    ValueId n = member(b_.round(b_.div(v, s_)));
    return {b_.abs(b_.sub(v, b_.mul(n, s_))), n};
}

// A translated circle (turn 0): |p - n delta| = n s + phase is a quadratic in n, and h_p
// is convex, so |h_p| is least next to one of its zeros, at n = 0, or (when it has no
// zero) next to its vertex; at the marginal drift it tends to a constant.
Vals Solver::translatedCircle() {
    // A = L^2 - s^2 and C = r^2 - phase^2, as products of a difference and a sum: near
    // the marginal drift L - s is exact in any precision where L^2 - s^2 would keep
    // only the rounding of the squares (A is then small, and every index below is
    // divided by it).
    ValueId a = b_.mul(b_.sub(len_, s_), b_.add(len_, s_));
    ValueId pd = b_.add(b_.mul(in_.px, in_.offsetX), b_.mul(in_.py, in_.offsetY)); // p . delta
    ValueId half = b_.add(pd, b_.mul(s_, in_.phase)); // A n^2 - 2 half n + C
    ValueId cc = b_.mul(b_.sub(r_, in_.phase), b_.add(r_, in_.phase));
    ValueId disc = b_.sub(b_.mul(half, half), b_.mul(a, cc));
    // Roots in the cancellation-free form: q = half + sign(half) sqrt(disc), t = q / A, C / q.
    ValueId sgn = b_.select(b_.lt(half, c(0.0)), c(-1.0), c(1.0));
    ValueId q = b_.add(half, b_.mul(sgn, b_.sqrt(disc)));
    ValueId nan = c(std::numeric_limits<double>::quiet_NaN());
    ValueId real = b_.emit(Op::Ge, {disc, c(0.0)});
    ValueId t1 = b_.select(real, b_.div(q, a), nan);
    ValueId t2 = b_.select(real, b_.div(cc, q), nan);
    // The vertex of h_p, where it has a minimum (only when L > s). Fix: the distance of p
    // from the line of the walk is written as the cross product |p x delta| / L rather
    // than sqrt(r^2 L^2 - (p . delta)^2), which cancels for p near that line.
    ValueId w = b_.abs(b_.sub(b_.mul(in_.px, in_.offsetY), b_.mul(in_.py, in_.offsetX)));
    ValueId l2 = b_.mul(len_, len_);
    ValueId tv = b_.add(b_.div(pd, l2), b_.div(b_.mul(s_, w), b_.mul(l2, b_.sqrt(a))));
    ValueId vertex = b_.select(b_.gt(a, c(0.0)), tv, nan);

    // A candidate's residual. Fix: the direct form |p - n delta| - (n s + phase) cancels
    // catastrophically in single precision at large n (two lengths of order n s whose
    // difference is a pixel), and near the marginal drift the roots and the vertex do sit
    // at n ~ 1e4-1e7: the JIT drew white stripes across a band the interpreter inks solid.
    // Through the quadratic Q(n) = A n^2 - 2 half n + C = |p - n delta|^2 - (n s + phase)^2,
    // h(n) = Q(n) / (|p - n delta| + n s + phase) has no such cancellation, with Q written
    // from the numbers the candidates were solved from: factored through its roots,
    // (A n - q)(n - C / q), when it has real ones (this holds at A = 0 too), and as the
    // completed square A (n - half / A)^2 - disc / A when it has none. The division needs
    // a positive level n s + phase, so n = 0 and a negative phase's first members keep
    // the direct form.
    ValueId factored = both(real, b_.emit(Op::Ne, {q, c(0.0)}));
    ValueId squared = both(b_.emit(Op::Not, {factored}), b_.emit(Op::Ne, {a, c(0.0)}));
    ValueId centre = b_.div(half, a); // where Q is least
    auto value = [&](ValueId n) {
        ValueId dist =
            radius(b_.sub(in_.px, b_.mul(n, in_.offsetX)), b_.sub(in_.py, b_.mul(n, in_.offsetY)));
        ValueId level = b_.add(b_.mul(n, s_), in_.phase);
        ValueId off = b_.sub(n, centre);
        ValueId quad = b_.select(factored, b_.mul(b_.sub(b_.mul(a, n), q), b_.sub(n, t2)),
                                 b_.sub(b_.mul(a, b_.mul(off, off)), b_.div(disc, a)));
        ValueId useQ =
            both(b_.emit(Op::Or, {factored, squared}),
                 both(b_.emit(Op::Ge, {n, c(1.0)}), b_.emit(Op::Ge, {level, b_.mul(s_, c(0.5))})));
        return b_.select(useQ, b_.div(quad, b_.add(dist, level)), b_.sub(dist, level));
    };

    ValueId best = c(kFar), argmin = c(0.0);
    consider(best, argmin, c(0.0), residualAt(c(0.0), in_.px, in_.py));
    for (ValueId t : {t1, t2, vertex}) {
        ValueId lo = member(b_.floor(t));
        consider(best, argmin, lo, value(lo));
        ValueId hi = b_.add(lo, c(1.0));
        consider(best, argmin, hi, value(hi));
    }
    // Marginal drift: h_p tends to -(p . delta) / L - phase along the far members.
    ValueId marginal = b_.le(b_.abs(b_.sub(len_, s_)), c(kWalkMarginal));
    ValueId flat = b_.select(marginal, b_.sub(b_.neg(b_.div(pd, len_)), in_.phase), nan);
    consider(best, argmin, c(kFarIndex), flat);
    return {best, argmin};
}

// A translated polygon with a whole number of facets and drift m <= s (Proposition 6):
// h_p is convex and piecewise linear, one piece per facet, so its zero is one of the N
// facet solves; at the marginal drift the leading facet's piece is flat.
//
// Fix: the candidates' residuals used to be evaluated as rho(p - n delta) - (n s + phase),
// which in single precision loses everything once n is large (rho and n s are both of
// order n s and differ by a pixel), and near the marginal drift the zero does sit at
// n ~ (a_k - phase) / (s + b_k) ~ 1e7: the JIT drew white stripes across a band the
// interpreter inks solid. Here h_p is evaluated in its piecewise form (Eq. 34),
// max_k (a_k - phase - n (s + b_k)), from the same a_k and slopes the zero was solved
// from, which is consistent with that solve in any precision. Since h_p is a maximum of
// decreasing lines (every slope s + b_k > 0 off the flat facets), its zero is where the
// last of them crosses zero: the largest facet solve. So one pass finds that zero, a
// second evaluates Eq. 34 at the two members beside it: 2 evaluations of h_p and 2N dot
// products, where testing both neighbours of every facet's solve took 2N evaluations.
Vals Solver::translatedPolygon() {
    ValueId rp = radius(in_.px, in_.py);
    ValueId inside = b_.lt(rp, in_.phase);
    return b_.ifThenElse(
        inside,
        [&] {
            return Vals{b_.sub(in_.phase, rp), c(0.0)};
        },
        [&] {
            ValueId step = b_.div(c(2.0 * std::numbers::pi), in_.facets);
            ValueId cs = b_.cos(step), sn = b_.sin(step);
            // Facet k's a_k - phase and slope s + b_k (the negated slope of its piece),
            // with its normal u_k carried by a rotation of 2 pi / N per facet.
            auto facet = [&](ValueId ux, ValueId uy) {
                ValueId ak = b_.add(b_.mul(in_.px, ux), b_.mul(in_.py, uy));
                ValueId bk = b_.add(b_.mul(in_.offsetX, ux), b_.mul(in_.offsetY, uy));
                return std::pair{b_.sub(ak, in_.phase), b_.add(s_, bk)};
            };
            auto turnNormal = [&](ValueId ux, ValueId uy) {
                ir::Vec2T<BuiltValue> u = ir::rotate({BuiltValue(b_, ux), BuiltValue(b_, uy)},
                                                     BuiltValue(b_, cs), BuiltValue(b_, sn));
                return std::pair{u.x.id, u.y.id};
            };
            auto more = [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], in_.facets)}; };
            // Pass 1. Carried: facet k, u_k, the largest solve, and the largest
            // a_k - phase among facets whose slope vanishes (within kWalkMarginal).
            Vals found = b_.loop({c(0.0), c(1.0), c(0.0), c(-kFar), c(-kFar)}, more,
                                 [&](std::span<const ValueId> v) {
                                     auto [level, slope] = facet(v[1], v[2]);
                                     ValueId solves = b_.gt(slope, c(kWalkMarginal));
                                     ValueId root = b_.select(
                                         solves, b_.max(v[3], b_.div(level, slope)), v[3]);
                                     ValueId flatA = b_.select(solves, v[4], b_.max(v[4], level));
                                     auto [ux, uy] = turnNormal(v[1], v[2]);
                                     return Vals{b_.add(v[0], c(1.0)), ux, uy, root, flatA};
                                 });
            ValueId lo = member(b_.floor(found[3]));
            ValueId hi = b_.add(lo, c(1.0));
            // Pass 2: h_p(lo) and h_p(hi) by Eq. 34, over every facet.
            Vals at = b_.loop({c(0.0), c(1.0), c(0.0), c(-kFar), c(-kFar)}, more,
                              [&](std::span<const ValueId> v) {
                                  auto [level, slope] = facet(v[1], v[2]);
                                  ValueId hLo = b_.max(v[3], b_.sub(level, b_.mul(lo, slope)));
                                  ValueId hHi = b_.max(v[4], b_.sub(level, b_.mul(hi, slope)));
                                  auto [ux, uy] = turnNormal(v[1], v[2]);
                                  return Vals{b_.add(v[0], c(1.0)), ux, uy, hLo, hHi};
                              });
            countEvaluations(2);
            ValueId best = c(kFar), argmin = c(0.0);
            consider(best, argmin, lo, at[3]);
            consider(best, argmin, hi, at[4]);
            // The flat tail: every far member sits at exactly a_k* - phase (case 2).
            ValueId flat = b_.select(b_.gt(found[4], c(-kFar)), found[4],
                                     c(std::numeric_limits<double>::quiet_NaN()));
            consider(best, argmin, c(kFarIndex), flat);
            return Vals{best, argmin};
        });
}

// Algorithm 1: walk the certified interval, skipping by the Lipschitz bound, with a
// power-of-two stride anchored to the global index lattice when the interval is wider
// than the budget.
Vals Solver::scan() {
    ValueId nHi = b_.min(nHiRaw_, b_.add(nLo_, c(kWalkSpanCap - 1.0)));
    ValueId span = b_.add(b_.sub(nHi, nLo_), c(1.0));
    // Lipschitz constant of h_p in n (Lemma 5).
    ValueId lambda = b_.add(b_.add(s_, len_), b_.mul(b_.abs(in_.turn), r_));
    // The loop multiplies by reciprocals: divisions would sit on its critical path.
    ValueId invLambda = b_.div(c(1.0), lambda);
    // The stride: the least power of two that fits the interval into the budget.
    ValueId stride = b_.loop(
        {c(1.0)},
        [&](std::span<const ValueId> v) {
            return Vals{b_.lt(b_.mul(v[0], c(in_.variant.budget)), span)};
        },
        [&](std::span<const ValueId> v) { return Vals{b_.mul(v[0], c(2.0))}; })[0];
    // Anchored to multiples of the stride, not to n_lo: neighbouring pixels then sample
    // the same members (§9.6). (WalkingVariant::latticeAnchored false: at n_lo, Fig. 17.)
    ValueId invStride = b_.div(c(1.0), stride); // exact: a power of two
    // Strides per unit of (value - min(best, G)): an exact rescaling of 1 / Lambda.
    ValueId invLambdaStride = b_.mul(invLambda, invStride);
    ValueId start =
        in_.variant.latticeAnchored ? b_.mul(stride, ceil(b_.mul(nLo_, invStride))) : nLo_;
    auto [p0x, p0y] = unturn(b_.mul(start, in_.turn));
    // Rot(2^j sigma theta), j = 0 .. kCarriedPowers - 1, for the carried rotation: the
    // frame's powers at stride 1, else a cosine and a sine and repeated squaring.
    const bool carried = variant().carriedRotation;
    Vals powers;
    if (carried)
        powers = b_.ifThenElse(
            eq(stride, c(1.0)),
            [&] {
                Vals out;
                for (auto [cj, sj] : turnPowers_) {
                    out.push_back(cj);
                    out.push_back(sj);
                }
                return out;
            },
            [&] {
                ValueId strideTurn = b_.mul(stride, in_.turn);
                std::pair<ValueId, ValueId> r{b_.cos(strideTurn), b_.sin(strideTurn)};
                Vals out{r.first, r.second};
                for (int j = 1; j < kCarriedPowers; ++j) {
                    r = compose(r, r);
                    out.push_back(r.first);
                    out.push_back(r.second);
                }
                return out;
            });
    auto power = [&](int j) { return std::pair{powers[2 * j], powers[2 * j + 1]}; };

    // Under the mean filter, where the scan visits every member (stride 1), it also gathers
    // the footprint mean of the union of the members' strokes (memberMean, overlapMean),
    // so that members closer than a pixel all count (docs/filtering.md): the skip's bar is
    // then raised to the reach of a member's mean, so that no member within it is skipped,
    // and the early exit (the nearest member found fully inked) waits for the union to
    // fill the pixel, as the members beside it still count. Strided, the crowd estimate
    // draws the pixel, and the scan is as it was.
    const bool summing = resolving();
    ValueId exhaustive = summing ? eq(stride, c(1.0)) : ir::kNoValue;
    ValueId reach = summing ? b_.select(exhaustive, memberReach(), c(0.0)) : ir::kNoValue;

    // Carried: iteration, n, best, argmin, Rot(-n theta) p, steps since the last anchor;
    // summing, the paper the closed runs leave (paperLeft), the best member's mean, the last
    // member within reach and its signed residual (none yet: member -2), and the open
    // run's mean.
    Vals init = {c(0.0), start, c(kFar), start, p0x, p0y, c(0.0)};
    if (summing) init.insert(init.end(), {c(1.0), c(0.0), c(-2.0), c(0.0), c(0.0)});
    Vals res = b_.loop(
        init,
        [&](std::span<const ValueId> v) {
            ValueId going = both(b_.lt(v[0], c(in_.variant.budget)), b_.le(v[1], nHi));
            if (!variant().acceptEarlyExit) return Vals{going};
            // Summing, the nearest member fully inked ends the scan only once the union's
            // mean fills the pixel too.
            ValueId open = b_.gt(v[2], accept_);
            if (summing)
                open = b_.emit(Op::Or,
                               {open, both(exhaustive, b_.gt(paperLeft(v[7], v[11]), c(0.0)))});
            return Vals{both(going, open)};
        },
        [&](std::span<const ValueId> v) {
            ValueId iter = v[0], n = v[1], best = v[2], argmin = v[3], tx = v[4], ty = v[5],
                    steps = v[6];
            ValueId signedValue = residualAt(n, tx, ty);
            ValueId value = b_.abs(signedValue);
            // min(best, G) before this member: ready before rho is, off the critical path.
            ValueId bar = b_.min(best, guard_);
            if (summing) bar = b_.max(bar, reach);
            ValueId better = b_.lt(value, best);
            // Summing, a member within h - a settles the nearest as the early exit would
            // have (the first met, as the point rule draws it): the scan goes on for the
            // union alone, and the index does not move between members whose residuals
            // tie to rounding (as the JIT's single precision and the interpreter's double
            // would break the tie apart).
            if (summing) better = both(better, b_.gt(best, accept_));
            Vals sums;
            if (summing) {
                // Past the reach a member's mean and its overlap's are exactly 0: only the
                // few members within it pay for them.
                ValueId within = b_.lt(value, reach);
                ValueId after = eq(n, b_.add(v[9], c(1.0)));
                Vals got = b_.ifThenElse(
                    within,
                    [&] {
                        ValueId overlap = b_.select(after, overlapMean(v[10], signedValue), c(0.0));
                        return Vals{memberMean(value), overlap};
                    },
                    [&] {
                        return Vals{c(0.0), c(0.0)};
                    });
                // A member within reach but not next to the last closes the open run.
                ValueId opens = both(within, b_.emit(Op::Not, {after}));
                ValueId run = b_.select(after, b_.sub(b_.add(v[11], got[0]), got[1]), got[0]);
                sums = {b_.select(opens, paperLeft(v[7], v[11]), v[7]),
                        b_.select(better, got[0], v[8]), b_.select(within, n, v[9]),
                        b_.select(within, signedValue, v[10]), b_.select(within, run, v[11])};
            }
            best = b_.select(better, value, best);
            argmin = b_.select(better, n, argmin);
            // No index within (value - min(best, G)) / Lambda of n can come under the guard
            // or beat the best: skip them, in whole strides. With best updated by this
            // value, value - min(best, G) is max(value - bar, 0) (the same subtraction, or
            // 0 when this value is the new best under the guard; NaN stays NaN). In
            // strides that is ceil((floor(x) + 1) / sigma) for x = that / Lambda, which for
            // x >= 0 and sigma a power of two is floor(x / sigma) + 1: one rounding on the
            // loop's critical path instead of two. A NaN x takes one stride.
            ValueId excess = b_.max(b_.sub(value, bar), c(0.0));
            ValueId strides =
                variant().lipschitzSkip
                    ? b_.max(c(1.0), b_.add(b_.floor(b_.mul(excess, invLambdaStride)), c(1.0)))
                    : c(1.0); // Table 6: every stride of the interval visited
            ValueId next = b_.add(n, b_.mul(stride, strides));
            // A jump of up to 2^kCarriedPowers - 1 strides advances the carried rotation by
            // angle addition (one stride by Rot(sigma theta), more by the product of the
            // powers of two in it); a longer jump, or every kWalkReanchor steps, takes a
            // fresh cosine and sine instead. Skips of a few strides are the common case
            // away from a member, so this keeps most cosines and sines out of the loop.
            auto fresh = [&] {
                auto [ax, ay] = unturn(b_.mul(next, in_.turn));
                return Vals{ax, ay, c(0.0)};
            };
            if (!carried) {
                Vals turned = fresh();
                Vals out{b_.add(iter, c(1.0)), next, best, argmin, turned[0], turned[1], steps};
                out.insert(out.end(), sums.begin(), sums.end());
                return out;
            }
            ValueId carry = both(b_.le(strides, c(double((1 << kCarriedPowers) - 1))),
                                 b_.lt(steps, c(kWalkReanchor)));
            Vals turned = b_.ifThenElse(
                carry,
                [&] {
                    Vals by = b_.ifThenElse(
                        eq(strides, c(1.0)),
                        [&] {
                            return Vals{power(0).first, power(0).second};
                        },
                        [&] {
                            auto [rc, rs] = stridesTurn(strides, power);
                            return Vals{rc, rs};
                        });
                    auto [ax, ay] = unturn(BuiltValue(b_, by[0]), BuiltValue(b_, by[1]), tx, ty);
                    return Vals{ax, ay, b_.add(steps, c(1.0))};
                },
                fresh);
            Vals out{b_.add(iter, c(1.0)), next, best, argmin, turned[0], turned[1], turned[2]};
            out.insert(out.end(), sums.begin(), sums.end());
            return out;
        });
    if (!summing) return {res[2], res[3]};
    // The members beside the nearest: the union's mean less the nearest's own (which the
    // compose step draws across its own normal). Strided, none (the crowd's estimate).
    ValueId all = b_.sub(c(1.0), paperLeft(res[7], res[11]));
    ValueId others = b_.max(b_.sub(all, res[8]), c(0.0));
    return {res[2], res[3], b_.select(exhaustive, others, c(0.0))};
}

// Across the normal the index gradient (gradX, gradY) gives, turned into the pixel's sides
// as the compose step turns it (onPixelSides); the box where it is not given or vanishes.
Solver::Across Solver::across(ValueId gradX, ValueId gradY) {
    if (gradX == ir::kNoValue || gradY == ir::kNoValue) return facing();
    PixelSides g =
        onPixelSides(b_, gradX, gradY, PixelFootprint{ir::kNoValue, in_.cosTurn, in_.sinTurn});
    NormalExtents e = extentsAcross(b_, g.u, g.v, memberPixel());
    return {e.along, e.across};
}

ValueId Solver::bandMean(ValueId centre, ValueId half, const Across& foot) {
    return distanceMeanInk(BuiltValue(b_, centre), BuiltValue(b_, half), BuiltValue(b_, foot.along),
                           BuiltValue(b_, foot.across))
        .id;
}

// The union of the members within reach, gathered in runs. Consecutive members (n, n + 1)
// lie side by side, nearly parallel (each is the last moved by one offset and turned by one
// turn): a run of them is one set of parallel strokes, whose union's mean is exact by
// inclusion and exclusion (overlapMean). Members far apart in index that both reach the
// pixel cross there at whatever angle the turns between them make, and their runs are
// laid over one another as independent inks: the paper left is the product of each
// run's 1 - mean, and the union 1 - that. `paper` is what the closed runs leave, `run`
// the open run's mean.
ValueId Solver::paperLeft(ValueId paper, ValueId run) {
    return b_.mul(paper, b_.sub(c(1.0), b_.min(run, c(1.0))));
}

// The footprint mean of the overlap of two members' strokes centred at residuals a and b
// (signed, along a common normal), for the union in scan(): [a - t/2, a + t/2] and
// [b - t/2, b + t/2] share the stroke of half-width max(t - |a - b|, 0) / 2 centred on
// (a + b) / 2. Strokes of one width sorted along the normal overlap only the next one's
// beyond what an earlier one's does, so their union's mean is the sum of their means less
// those of each one's overlap with the next (inclusion and exclusion, exact for parallel
// members; consecutive members within reach are taken as the next along the normal).
ValueId Solver::overlapMean(ValueId a, ValueId bv) {
    ValueId overlap = b_.max(b_.sub(in_.stroke, b_.abs(b_.sub(a, bv))), c(0.0));
    ValueId centre = b_.mul(b_.add(a, bv), c(0.5));
    return distanceMeanInk(BuiltValue(b_, centre), BuiltValue(b_, b_.mul(overlap, c(0.5))),
                           BuiltValue(b_, memberPixel()), BuiltValue(b_, c(0.0)))
        .id;
}

ValueId Solver::memberReach(const Across& foot) {
    return b_.add(memberHalf(),
                  trapezoid(BuiltValue(b_, foot.along), BuiltValue(b_, foot.across)).s1.id);
}

// Sweep (§9.1), the baseline without a certificate: seed at the member whose radius
// matches rho(p), look at a fixed neighbourhood of sweepNeighbours members either side,
// then refine the best with Newton steps on the index (a central-difference slope). A
// fixed-trip loop pays for every slot, members that do not exist (n < 0, read as member
// 0) included. tests/reference/WalkingSweep.cpp is the same method in double.
Vals Solver::sweep() {
    const int k = variant().sweepNeighbours;
    ValueId seed = b_.round(b_.div(b_.sub(radius(in_.px, in_.py), in_.phase), s_));
    ValueId first = b_.sub(seed, c(double(k)));
    Vals found = b_.loop(
        {c(0.0), guard_, member(seed)}, // no member past the guard is recorded
        [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], c(2.0 * k + 1.0))}; },
        [&](std::span<const ValueId> v) {
            ValueId n = member(b_.add(first, v[0]));
            ValueId best = v[1], argmin = v[2];
            consider(best, argmin, n, residual(n));
            return Vals{b_.add(v[0], c(1.0)), best, argmin};
        });
    ValueId best = found[1], argmin = found[2];
    ValueId n = argmin;
    for (int step = 0; step < kSweepNewtonSteps; ++step) {
        ValueId at = b_.round(n);
        ValueId h0 = residual(at);
        ValueId slope = b_.mul(
            c(0.5), b_.sub(residual(b_.add(at, c(1.0))), residual(member(b_.sub(at, c(1.0))))));
        // A flat slope ends the refinement (it stays where it is: the same member again).
        ValueId moves = b_.emit(Op::Ne, {slope, c(0.0)});
        n = b_.select(moves, member(b_.sub(n, b_.div(h0, slope))), n);
        ValueId refined = b_.round(n);
        consider(best, argmin, refined, residual(refined));
    }
    return {best, argmin};
}

// Rot(k sigma theta) for a whole k in [1, 2^kCarriedPowers), as the product of the powers
// Rot(2^j sigma theta) of k's binary digits (an absent digit contributes Rot(0) exactly).
// The binary digits are found independently (the fractional part of k / 2^(j+1) is at
// least a half) and the factors multiplied as a tree, to keep this short on the loop's
// critical path; selects rather than branches, as the jump varies from step to step.
template <class PowerFn>
std::pair<ValueId, ValueId> Solver::stridesTurn(ValueId k, const PowerFn& power) {
    std::vector<std::pair<ValueId, ValueId>> factors;
    for (int j = 0; j < kCarriedPowers; ++j) {
        ValueId half = b_.mul(k, c(1.0 / double(2 << j))); // exact: a power of two
        ValueId digit = b_.emit(Op::Ge, {b_.sub(half, b_.floor(half)), c(0.5)});
        auto [cj, sj] = power(j);
        factors.push_back({b_.select(digit, cj, c(1.0)), b_.select(digit, sj, c(0.0))});
    }
    while (factors.size() > 1) {
        std::vector<std::pair<ValueId, ValueId>> next;
        for (size_t i = 0; i + 1 < factors.size(); i += 2)
            next.push_back(compose(factors[i], factors[i + 1]));
        if (factors.size() % 2) next.push_back(factors.back());
        factors = std::move(next);
    }
    return factors[0];
}

// The phase sample (Eq. 14) for the views that sweep the index: the searched member n*
// and its two neighbours, each read once by its residual h_p(n) (Eq. 24), which is
// positive outside the member, so the member lies -h_p(n) away along the index's
// increase. Member -1 does not exist. A solve saturated at the guard found no member
// within a pitch: its floor keeps the taps from inventing ink where nothing can slide in.
PhaseSample Solver::phaseSample(ValueId distance, ValueId argmin) {
    ValueId n = answerIndex(argmin);
    PhaseSample out;
    out.z = b_.neg(residual(n));
    out.up = b_.neg(residual(b_.add(n, c(1.0))));
    out.down = b_.select(b_.lt(n, c(1.0)), c(kNoMember), b_.neg(residual(b_.sub(n, c(1.0)))));
    out.floor = b_.select(b_.lt(distance, guard_), c(0.0), guard_);
    // A NaN radius draws nothing (see run()): nothing slides either.
    out.z = b_.denan(out.z, c(kNoMember));
    out.up = b_.denan(out.up, c(kNoMember));
    out.down = b_.denan(out.down, c(kNoMember));
    return out;
}

// The searched index field of §4.1: the nearest index plus the fractional residual
// h(n*) / (h(n*) - h(n* + 1)) (or towards n* - 1 inside member n*), and its gradient.
//
// The gradient is exact, by forward-mode AD through the solver's result rather than by
// differences across pixels: n* is piecewise constant in p (it changes only where another
// member becomes the nearest), so it is held fixed, and the fraction is differentiated
// through h(n*) and h(neighbour) as functions of p. Taking n* through a floor (exact: it
// is a whole number) is what holds it: a floor's derivative is zero without reading its
// argument's tangent, so AD carries no tangent into the search loops that found n*. Where
// the fraction falls back (no crossing towards the neighbour, or clamped to one member),
// the gradient is that fallback's own, as AD of the selects gives it.
void Solver::searchedIndex(ValueId argmin, LayerFields& out) {
    ValueId n = b_.floor(answerIndex(argmin));
    ValueId h0 = residual(n);
    ValueId outside = b_.emit(Op::Ge, {h0, c(0.0)});
    ValueId neighbour = member(b_.select(outside, b_.add(n, c(1.0)), b_.sub(n, c(1.0))));
    ValueId h1 = residual(neighbour);
    // Fix: the interpolation is only meaningful where it brackets a crossing; on a flat
    // tail (h1 = h0: the marginal drift's far members, or p on the line of the walk) it
    // divided by zero and wrote an infinite or NaN index. A crossing towards the
    // neighbour has a positive denominator and a fraction within [-1, 1]; anything else
    // falls back to the residual in spacings, as inside member 0, held to one member.
    ValueId denom = b_.select(outside, b_.sub(h0, h1), b_.sub(h1, h0));
    ValueId usable = both(b_.emit(Op::Ne, {neighbour, n}), b_.gt(denom, c(0.0)));
    ValueId toward = b_.max(c(-1.0), b_.min(c(1.0), b_.div(h0, denom)));
    ValueId alone = b_.div(h0, s_);
    ValueId frac = b_.select(
        usable, toward, b_.select(eq(n, c(0.0)), alone, b_.max(c(-1.0), b_.min(c(1.0), alone))));
    // A NaN radius (see run()) leaves the index at the searched member (or at 0).
    out.index = b_.denan(b_.add(n, frac), n);
    out.gradX = b_.emit(Op::DerivX, {out.index});
    out.gradY = b_.emit(Op::DerivY, {out.index});
}

} // namespace moire::lower::walking

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

LayerFields walkingFamilyFields(ir::Builder& b, const WalkingInputs& in, const RadiusFn& rho) {
    return walking::Solver(b, in, rho).run();
}

LayerFields walkingLayerFields(ir::Builder& b, const FamilyInputs& fam) {
    const LayerFrame& at = fam.at;
    WalkingInputs in;
    in.px = at.qx;
    in.py = at.qy;
    in.spacing = at.spacing;
    in.phase = at.phase;
    // Encoding shifts every member's residual by -gain s f(p): the same as moving the
    // phase by +gain s f. The residual is then divided by the carrier gradient, taken as
    // radial from the layer's origin (a first-order convenience, §10.1), minus
    // gain s grad f; the solver works in residual units, so its stroke band is scaled by
    // that length and its distance divided by it.
    ValueId slope = ir::kNoValue;
    if (fam.enc.field != ir::kNoValue) {
        ValueId shift = b.mul(b.mul(fam.enc.gain, at.spacing), fam.enc.field);
        in.phase = b.add(at.phase, shift);
        ValueId rr = b.max(b.hypot(at.dx, at.dy), b.constF(ir::kTiny));
        ValueId gx = b.sub(b.div(at.dx, rr), b.emit(Op::DerivX, {shift}));
        ValueId gy = b.sub(b.div(at.dy, rr), b.emit(Op::DerivY, {shift}));
        slope = b.max(b.hypot(gx, gy), b.constF(ir::kTiny));
    }
    Vals offset = fam.layerProp("offset");
    in.offsetX = offset[0];
    in.offsetY = offset[1];
    // Member n is turned by n * turn with n whole, so a turn is the same taken modulo a full
    // turn; reduced to (-pi, pi] here (per frame, in double, when it does not depend on
    // the pixel) so that n * turn stays small enough for the float renderers to resolve.
    ValueId turn = fam.layerProp("turn")[0];
    ValueId turns = b.round(b.div(turn, b.constF(2.0 * std::numbers::pi)));
    ValueId reduced = b.sub(turn, b.mul(turns, b.constF(2.0 * std::numbers::pi)));
    in.turn = b.select(b.le(b.abs(turn), b.constF(std::numbers::pi)), turn, reduced);
    in.facets = fam.facets;
    in.band = fam.band;
    if (slope != ir::kNoValue) in.band = {b.mul(fam.band.h, slope), b.mul(fam.band.a, slope)};
    in.wantIndex = fam.wantIndex;
    in.tally = fam.tally;
    in.crowd = fam.crowd;
    if (fam.crowd) {
        in.stroke = fam.layerProp("stroke")[0];
        if (slope != ir::kNoValue) in.stroke = b.mul(in.stroke, slope);
        in.cosTurn = fam.cosTurn;
        in.sinTurn = fam.sinTurn;
    }
    in.variant = fam.walking;
    in.flankGuard = fam.sweeps;
    LayerFields out = walkingFamilyFields(b, in, fam.phaseAt);
    if (slope != ir::kNoValue) {
        out.distance = b.div(out.distance, slope);
        if (out.sample.z != ir::kNoValue)
            for (ValueId* v : {&out.sample.z, &out.sample.up, &out.sample.down, &out.sample.floor})
                *v = b.div(*v, slope);
    }
    return out;
}

} // namespace moire::lower
