#include "compiler/lower/WalkingFamily.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Plane.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/ChainSelection.h"
#include "compiler/lower/Prefilter.h"
#include "compiler/lower/WalkingChains.h"

#include <array>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>

namespace moire::lower {

using ir::BuiltValue;
using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

// A distance no member reaches: larger than any guard, finite in single precision.
constexpr double kFar = 1e30;
// The argmin recorded for the flat tail of a marginal drift, which no finite index attains.
constexpr double kFarIndex = 1e7;

class Solver {
  public:
    Solver(ir::Builder& b, const WalkingInputs& in, const RadiusFn& rho)
        : b_(b), in_(in), rho_(rho) {}

    LayerFields run() {
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
                closedPolygon_, [&] { return closed(translatedPolygon()); },
                [&] { return scan(); });
        };
        Vals found = variant().solver == WalkingVariant::Solver::Sweep
                         ? sweep()
                         : b_.ifThenElse(
                               still_, [&] { return closed(concentric()); },
                               [&] {
                                   return b_.ifThenElse(
                                       quadratic_, [&] { return closed(translatedCircle()); },
                                       polygonOrScan);
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

  private:
    ValueId c(double v) { return b_.constF(v); }
    ValueId both(ValueId a, ValueId b) { return b_.emit(Op::And, {a, b}); }
    ValueId eq(ValueId a, ValueId b) { return b_.emit(Op::Eq, {a, b}); }
    ValueId ceil(ValueId v) { return b_.neg(b_.floor(b_.neg(v))); }

    const WalkingVariant& variant() const { return in_.variant; }
    // The mean filter is drawn by a solver that estimates its crowd (not the sweep baseline).
    bool resolving() const {
        return in_.crowd && variant().solver != WalkingVariant::Solver::Sweep;
    }

    ValueId radius(ValueId qx, ValueId qy) {
        countEvaluations(1);
        if (!variant().supportFastPaths) return facetRadius(qx, qy);
        return rho_(b_, qx, qy);
    }
    // Table 6's "support fast paths" removed: a polygon's radius as the definition writes it
    // (Eq. 16), the largest <q, u_k> over its N unit facet normals, the first facing +x, in a
    // loop with u_k carried by a turn of 2 pi / N, in place of the family's folded form. A
    // circle, or a side count that is no whole polygon's (a morph), keeps the family's own.
    ValueId facetRadius(ValueId qx, ValueId qy) {
        return b_.ifThenElse(
            wholePolygon_, [&] { return Vals{facetLoop(qx, qy)}; },
            [&] { return Vals{rho_(b_, qx, qy)}; })[0];
    }
    ValueId facetLoop(ValueId qx, ValueId qy) {
        // Carried: facet k, u_k, the largest <q, u_k> so far.
        Vals res = b_.loop(
            {c(0.0), c(1.0), c(0.0), c(-kFar)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], in_.facets)}; },
            [&](std::span<const ValueId> v) {
                ValueId dot = b_.add(b_.mul(qx, v[1]), b_.mul(qy, v[2]));
                ir::Vec2T<BuiltValue> u =
                    ir::rotate({BuiltValue(b_, v[1]), BuiltValue(b_, v[2])},
                               BuiltValue(b_, facetCos_), BuiltValue(b_, facetSin_));
                return Vals{b_.add(v[0], c(1.0)), u.x.id, u.y.id, b_.max(v[3], dot)};
            });
        return res[3];
    }
    // Counts evaluations of the residual (of rho, or of its closed form) in the tally.
    void countEvaluations(int count) {
        if (in_.tally && counting_)
            for (int i = 0; i < count; ++i) b_.emitSink(Op::Tally, {}, kRadiusTally);
    }
    // Rot(-angle) p: the point in the frame of a member turned by `angle`.
    std::pair<ValueId, ValueId> unturn(ValueId angle) {
        BuiltValue cs(b_, b_.cos(angle)), sn(b_, b_.sin(angle));
        return unturn(cs, sn, in_.px, in_.py);
    }
    // Rot(-angle) (x, y), given the angle's cosine and sine.
    std::pair<ValueId, ValueId> unturn(BuiltValue cs, BuiltValue sn, ValueId x, ValueId y) {
        ir::Vec2T<BuiltValue> q = ir::unrotate({BuiltValue(b_, x), BuiltValue(b_, y)}, cs, sn);
        return {q.x.id, q.y.id};
    }
    // The signed residual h_p(n) = rho(Rot(-n theta) p - n delta) - (n s + phase) (Eq. 24).
    ValueId residual(ValueId n) {
        auto [qx, qy] = unturn(b_.mul(n, in_.turn));
        return residualAt(n, qx, qy);
    }
    // The same, with the turned point Rot(-n theta) p given.
    ValueId residualAt(ValueId n, ValueId turnedX, ValueId turnedY) {
        ValueId qx = b_.sub(turnedX, b_.mul(n, in_.offsetX));
        ValueId qy = b_.sub(turnedY, b_.mul(n, in_.offsetY));
        return b_.sub(radius(qx, qy), b_.add(b_.mul(n, s_), in_.phase));
    }
    // Folds |h_p(n)| at one more index into (best, argmin). NaN candidates never win.
    void consider(ValueId& best, ValueId& argmin, ValueId n, ValueId value) {
        ValueId v = b_.abs(value);
        ValueId better = b_.lt(v, best);
        best = b_.select(better, v, best);
        argmin = b_.select(better, n, argmin);
    }
    ValueId member(ValueId n) { return b_.max(n, c(0.0)); } // members start at n = 0
    // The solver's argmin as a member's index: at most the flat tail's kFarIndex, 0 for NaN.
    ValueId answerIndex(ValueId argmin) { return b_.denan(b_.min(argmin, c(kFarIndex)), c(0.0)); }
    // The turn Rot(a) Rot(b), given both as a cosine and a sine.
    std::pair<ValueId, ValueId> compose(std::pair<ValueId, ValueId> a,
                                        std::pair<ValueId, ValueId> b) {
        ir::Vec2T<BuiltValue> r = ir::rotate({BuiltValue(b_, b.first), BuiltValue(b_, b.second)},
                                             BuiltValue(b_, a.first), BuiltValue(b_, a.second));
        return {r.x.id, r.y.id};
    }

    void setUp() {
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
    std::pair<ValueId, ValueId> interval(ValueId guard) {
        ValueId kr = b_.mul(kappa_, r_);
        ValueId lo = member(b_.floor(
            b_.div(b_.sub(b_.sub(kr, in_.phase), guard), b_.add(s_, b_.mul(kappa_, len_)))));
        // Loose (§9.1, Table 6's "exact drift" removed): the obvious bound ||delta|| >= m in
        // place of m. It widens the interval, and where m < s < ||delta|| it even takes the
        // wrong branch, so it can lose ink; it never invents any (a minimum over members).
        ValueId intervalDrift = variant().solver == WalkingVariant::Solver::Loose ? len_ : drift_;
        ValueId gap = b_.sub(s_, intervalDrift);
        ValueId slower = b_.div(b_.add(b_.sub(r_, in_.phase), guard), gap);         // m < s
        ValueId faster = b_.div(b_.add(b_.add(r_, in_.phase), guard), b_.neg(gap)); // m > s
        ValueId hi = ceil(
            b_.select(b_.gt(gap, c(0.0)), slower, b_.select(b_.lt(gap, c(0.0)), faster, c(kFar))));
        return {lo, hi};
    }

    // delta = 0, and no turn (or a circle, which turning leaves alone): h_p is affine in n,
    // one evaluation and a rounding.
    Vals concentric() {
        ValueId v = b_.sub(radius(in_.px, in_.py), in_.phase);
        ValueId n = member(b_.round(b_.div(v, s_)));
        return {b_.abs(b_.sub(v, b_.mul(n, s_))), n};
    }

    // A translated circle (turn 0): |p - n delta| = n s + phase is a quadratic in n, and h_p
    // is convex, so |h_p| is least next to one of its zeros, at n = 0, or (when it has no
    // zero) next to its vertex; at the marginal drift it tends to a constant.
    Vals translatedCircle() {
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
            ValueId dist = radius(b_.sub(in_.px, b_.mul(n, in_.offsetX)),
                                  b_.sub(in_.py, b_.mul(n, in_.offsetY)));
            ValueId level = b_.add(b_.mul(n, s_), in_.phase);
            ValueId off = b_.sub(n, centre);
            ValueId quad = b_.select(factored, b_.mul(b_.sub(b_.mul(a, n), q), b_.sub(n, t2)),
                                     b_.sub(b_.mul(a, b_.mul(off, off)), b_.div(disc, a)));
            ValueId useQ = both(
                b_.emit(Op::Or, {factored, squared}),
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
    Vals translatedPolygon() {
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
                auto more = [&](std::span<const ValueId> v) {
                    return Vals{b_.lt(v[0], in_.facets)};
                };
                // Pass 1. Carried: facet k, u_k, the largest solve, and the largest
                // a_k - phase among facets whose slope vanishes (within kWalkMarginal).
                Vals found =
                    b_.loop({c(0.0), c(1.0), c(0.0), c(-kFar), c(-kFar)}, more,
                            [&](std::span<const ValueId> v) {
                                auto [level, slope] = facet(v[1], v[2]);
                                ValueId solves = b_.gt(slope, c(kWalkMarginal));
                                ValueId root =
                                    b_.select(solves, b_.max(v[3], b_.div(level, slope)), v[3]);
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
    Vals scan() {
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
                            ValueId overlap =
                                b_.select(after, overlapMean(v[10], signedValue), c(0.0));
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
                        auto [ax, ay] =
                            unturn(BuiltValue(b_, by[0]), BuiltValue(b_, by[1]), tx, ty);
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

    // The footprint mean of one member's stroke as written (half-width t / 2, no floor) at
    // residual `value` from the pixel's centre, for scan()'s union: distanceMeanInk over a box of
    // the pixel's side (the member's own normal is not known inside the scan; the nearest
    // member's is, and the compose step draws that one across it). In residual units, as
    // the solver works: the band's antialias half-width is 0.7 pixel in them (strokeBand), so
    // the pixel is a / 0.7, and the ratio of the stroke, the distance and the footprint is
    // what the mean reads.
    ValueId memberPixel() { return b_.div(in_.band.a, c(kAntialiasPixels)); }
    ValueId memberHalf() { return b_.mul(in_.stroke, c(0.5)); }
    ValueId memberMean(ValueId value) { return bandMean(value, memberHalf()); }
    // The square pixel's extents across a member's normal, in residual units: the spans of its
    // two sides along the normal (distanceMeanInk's `along` and `across`).
    struct Across {
        ValueId along, across;
    };
    // A box of the pixel's side facing the member, where its normal is not known.
    Across facing() { return {memberPixel(), c(0.0)}; }
    // Across the normal the index gradient (gradX, gradY) gives, turned into the pixel's sides
    // as the compose step turns it (onPixelSides); the box where it is not given or vanishes.
    Across across(ValueId gradX, ValueId gradY) {
        if (gradX == ir::kNoValue || gradY == ir::kNoValue) return facing();
        PixelSides g =
            onPixelSides(b_, gradX, gradY, PixelFootprint{ir::kNoValue, in_.cosTurn, in_.sinTurn});
        NormalExtents e = extentsAcross(b_, g.u, g.v, memberPixel());
        return {e.along, e.across};
    }
    // The footprint mean of a band of residuals `half` either side of `centre`.
    ValueId bandMean(ValueId centre, ValueId half) { return bandMean(centre, half, facing()); }
    ValueId bandMean(ValueId centre, ValueId half, const Across& foot) {
        return distanceMeanInk(BuiltValue(b_, centre), BuiltValue(b_, half),
                               BuiltValue(b_, foot.along), BuiltValue(b_, foot.across))
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
    ValueId paperLeft(ValueId paper, ValueId run) {
        return b_.mul(paper, b_.sub(c(1.0), b_.min(run, c(1.0))));
    }
    // The footprint mean of the overlap of two members' strokes centred at residuals a and b
    // (signed, along a common normal), for the union in scan(): [a - t/2, a + t/2] and
    // [b - t/2, b + t/2] share the stroke of half-width max(t - |a - b|, 0) / 2 centred on
    // (a + b) / 2. Strokes of one width sorted along the normal overlap only the next one's
    // beyond what an earlier one's does, so their union's mean is the sum of their means less
    // those of each one's overlap with the next (inclusion and exclusion, exact for parallel
    // members; consecutive members within reach are taken as the next along the normal).
    ValueId overlapMean(ValueId a, ValueId bv) {
        ValueId overlap = b_.max(b_.sub(in_.stroke, b_.abs(b_.sub(a, bv))), c(0.0));
        ValueId centre = b_.mul(b_.add(a, bv), c(0.5));
        return distanceMeanInk(BuiltValue(b_, centre), BuiltValue(b_, b_.mul(overlap, c(0.5))),
                               BuiltValue(b_, memberPixel()), BuiltValue(b_, c(0.0)))
            .id;
    }
    // Past t / 2 + s1 a member's mean is 0 (distanceMeanInk), s1 the footprint's half-span
    // (about 0.52 pixel for the box, 0.71 at most for the square across a diagonal). That is
    // below the guard (h + a, with h >= max(t / 2, 1.15 pixel) and a = 0.7 pixel), so Theorem
    // 4's interval holds every member within it.
    ValueId memberReach() { return memberReach(facing()); }
    ValueId memberReach(const Across& foot) {
        return b_.add(memberHalf(),
                      trapezoid(BuiltValue(b_, foot.along), BuiltValue(b_, foot.across)).s1.id);
    }

    // Sweep (§9.1), the baseline without a certificate: seed at the member whose radius
    // matches rho(p), look at a fixed neighbourhood of sweepNeighbours members either side,
    // then refine the best with Newton steps on the index (a central-difference slope). A
    // fixed-trip loop pays for every slot, members that do not exist (n < 0, read as member
    // 0) included. tests/reference/WalkingSweep.cpp is the same method in double.
    Vals sweep() {
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
    std::pair<ValueId, ValueId> stridesTurn(ValueId k, const PowerFn& power) {
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
    PhaseSample phaseSample(ValueId distance, ValueId argmin) {
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

    // The crowd estimate for the mean filter (LayerFields::crowd, docs/filtering.md "Walking
    // families past the budget"): where the interval is wider than the budget the scan strides
    // and misses members, so the ink it draws is too light; the compose step then hands it over
    // to the crowd's mean ink (`mean`, from `density`, members per unit of residual across the
    // stroke, below), by `engaged`. Where the turn has a short period (no turn included), the
    // crowd is not estimated but drawn, member by member, chain by chain (chains(),
    // WalkingChains.h); what follows is the estimate for every other turn.
    //
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
    //    (sampledCrossings), each with its 1 / |dh/dn| read by a difference of h across it,
    //    exact where h is linear over one member.
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
    // `engaged` is smoothstep(B / 2, B, span): 0 where the interval is well inside the budget,
    // 1 from where the scan strides. Where the answer is a closed form (§7.5), which finds the
    // nearest member alone, it is how near the nearest's neighbours come (closedCrowding), and
    // the members are drawn as one chain: those closed forms do not turn the shape (or turn a
    // circle, which is the same), so the family is a translated shape, a period of one member.
    // `nearest` and `argmin` are the solver's answer (|h_p| and the member), (gradX, gradY) its
    // index gradient (the nearest member's normal; kNoValue where the index is not computed).
    CrowdEstimate crowd(ValueId nearest, ValueId argmin, ValueId gradX, ValueId gradY) {
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
                ValueId turnsBack =
                    b_.le(b_.mul(b_.abs(b_.div(period.drift, b_.max(period.q, c(1.0)))),
                                 b_.mul(span, r_)),
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
                        return chains(period, lo, b_.select(all, pick(to, end), pickedEnd),
                                      footprint, b_.emit(Op::Not, {all}),
                                      b_.select(all, lo, split));
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
    std::pair<ValueId, ValueId> closedWindow(ValueId nearest, ValueId argmin, const Across& foot) {
        ValueId n = answerIndex(argmin);
        ValueId gap = b_.sub(s_, drift_);
        ValueId far = b_.denan(b_.add(memberReach(foot), b_.min(nearest, c(kFar))), c(kFar));
        ValueId within = b_.add(b_.floor(b_.div(far, b_.max(gap, c(1e-30)))), c(1.0));
        ValueId half = b_.select(b_.gt(gap, c(kWalkMarginal)),
                                 b_.min(within, c(0.5 * kWalkSpanCap)), c(0.5 * kWalkSpanCap));
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
    ValueId closedCrowding(ValueId argmin, const Across& foot) {
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
        ValueId near =
            b_.sub(c(1.0), b_.smoothstep(from, b_.add(from, b_.mul(pixel, c(0.5))), next));
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
    Vals chains(const TurnPeriod& period, ValueId lo, ValueId end, const Across& foot,
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
    ChainInputs pointAccess() {
        ChainInputs in;
        in.residual = [this](ValueId n, ValueId x, ValueId y) { return residualAt(n, x, y); };
        in.unturn = [this](ValueId angle) { return unturn(angle); };
        return in;
    }
    // A gradient in the frame of the point p, (x, y), as one in the pixel's (the independent
    // variables'): J^T (x, y), J the Jacobian of p, so that a layer's own turn is kept.
    std::pair<ValueId, ValueId> toPixelFrame(ValueId x, ValueId y) {
        ValueId gx = b_.add(b_.mul(x, b_.emit(Op::DerivX, {in_.px})),
                            b_.mul(y, b_.emit(Op::DerivX, {in_.py})));
        ValueId gy = b_.add(b_.mul(x, b_.emit(Op::DerivY, {in_.px})),
                            b_.mul(y, b_.emit(Op::DerivY, {in_.py})));
        return {gx, gy};
    }
    // The first member whose residual at the pixel is its far form (ChainSelection.h): past
    // n ||delta|| sin(pi / N) = r, the pulled-back point stays within the facet (or the two at
    // a vertex) that faces -delta, and the residual over a turn is that facet's line moved by
    // n (m - s) alone; kFarForm times that, within [crowdLo_, end].
    ValueId farMembersFrom(ValueId end) {
        ValueId sinHalf = b_.sqrt(b_.sub(c(1.0), b_.mul(kappa_, kappa_)));
        ValueId n = b_.div(b_.mul(r_, c(kFarForm)), b_.max(b_.mul(len_, sinHalf), c(1e-9)));
        n = b_.neg(b_.floor(b_.neg(b_.min(n, c(kFar)))));
        return b_.clamp(b_.denan(n, end), crowdLo_, end);
    }
    // The crowd's density and its mean ink.
    Vals crowdDensity(ValueId span) {
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
        // Few turns: the crossings of h_p(n) = 0 in n, sampled and drawn (sampledCrossings).
        // No turn at all is a period of one member, drawn as one chain (chains()), not here.
        ValueId turns = b_.div(b_.mul(b_.abs(in_.turn), span), c(2.0 * std::numbers::pi));
        ValueId many = b_.smoothstep(c(kFewTurns), c(2.0 * kFewTurns), turns);
        counting_ = false;
        const Vals few = b_.ifThenElse(
            b_.lt(many, c(1.0)),
            [&] { return sampledCrossings(crowdLo_, b_.sub(end, c(1.0)), width); },
            [&] {
                return Vals{c(0.0), c(0.0)};
            });
        counting_ = true;
        ValueId density = b_.denan(b_.mix(few[0], averaged, many), c(0.0));
        ValueId twice = branchesInk(width, averaged, farShare, rr);
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
    // 1 where h < 0, else 0: a sign read with 0 among the positives, so that a residual of
    // exactly 0 (a point on a facet) still makes a sign change with a negative neighbour (a
    // zero product missed that crossing and drew a light line along the facet).
    ValueId negative(ValueId h) { return b_.select(b_.lt(h, c(0.0)), c(1.0), c(0.0)); }
    ValueId changesSign(ValueId h0, ValueId h1) {
        return b_.emit(Op::Ne, {negative(h0), negative(h1)});
    }
    // 1 / |dh|, the members (or turns) per unit of residual across a crossing; held finite
    // where h is flat.
    ValueId perResidual(ValueId dh) {
        return b_.div(c(1.0), b_.max(b_.abs(dh), b_.mul(s_, c(1e-6))));
    }
    // The ink of the crossing between members z - 1 and z, whose members step 1 / d apart in
    // residual there. Where they stand apart (at most kCrossingRun - 1 of them within reach of
    // the footprint) the members about the crossing are drawn, each at its own residual: h is
    // monotone across a crossing, so kCrossingRun members either side of it are a run sorted
    // along their common normal, nearly parallel (consecutive members differ by one turn), and
    // their union is exact by inclusion and exclusion, each stroke less its overlap with the
    // one before. The footprint is the square pixel across member z's own normal (memberNormal,
    // taken to the pixel's frame). Where they crowd, the comb: an even spread of strokes
    // 1 / d apart inks min(1, width d), which the drawn run hands over to smoothly as the
    // members within reach pass kCrossingRun (drawn as an even comb, a crossing of members two
    // pixels apart drew grey where one member's stroke or paper lies: a triangle of spacing 5
    // walking at 0.05 degrees a member, 0.083 from the exact box mean a pixel on average,
    // drawn 0.001). Not counted in the tally.
    ValueId crossingInk(ValueId z, ValueId d, ValueId width) {
        ValueId comb = b_.min(c(1.0), b_.mul(width, d));
        ValueId psi = b_.mul(z, in_.turn);
        auto [nx, ny] = memberNormal(b_, pointAccess(), z, psi, b_.max(memberPixel(), c(1e-6)));
        auto [gx, gy] = toPixelFrame(nx, ny);
        const Across foot = across(gx, gy);
        ValueId within = b_.mul(b_.mul(memberReach(foot), c(2.0)), d);
        ValueId drawn =
            b_.sub(c(1.0), b_.smoothstep(c(kCrossingRun - 1.0), c(kCrossingRun + 1.0), within));
        ValueId run = b_.ifThenElse(
            b_.gt(drawn, c(0.0)),
            [&] {
                // Members start at n = 0: none before it reaches the pixel.
                auto h = [&](ValueId n) {
                    return b_.select(b_.lt(n, c(0.0)), c(kFar), residual(member(n)));
                };
                return Vals{b_.min(sortedStrokesMean(b_, in_.stroke, b_.sub(z, c(kCrossingRun)),
                                                     b_.add(z, c(kCrossingRun)), h,
                                                     [&](ValueId centre, ValueId half) {
                                                         return bandMean(centre, half, foot);
                                                     }),
                                   c(1.0))};
            },
            [&] { return Vals{c(0.0)}; })[0];
        return b_.mix(comb, run, drawn);
    }
    // Few turns: where the members turn, h_p(n) is not convex in n (with no turn it is, and
    // chains() draws it), but over a few turns it crosses zero a few times, twice a turn at
    // most for the far members. Sampled at kCrossingSamples members evenly over [lo, hi], each
    // sign change between two samples is refined by bisection to the two members it falls between,
    // and each crossing's members are drawn, or where they crowd taken as a comb of members 1 /
    // |dh/dn| apart in residual (crossingInk). The crossings are laid over one another
    // independently (they cross the pixel at the angles their turns make). A dip below zero
    // narrower than the samples' spacing is missed. Returns {density, ink}.
    Vals sampledCrossings(ValueId lo, ValueId hi, ValueId width) {
        ValueId step = b_.div(b_.sub(hi, lo), c(kCrossingSamples));
        Vals res = b_.loop(
            {c(1.0), lo, residual(lo), c(0.0), c(1.0)},
            [&](std::span<const ValueId> v) {
                return Vals{both(b_.le(v[0], c(kCrossingSamples)), b_.lt(v[1], hi))};
            },
            [&](std::span<const ValueId> v) {
                ValueId n = b_.min(hi, b_.floor(b_.add(lo, b_.mul(v[0], step))));
                n = b_.max(n, b_.add(v[1], c(1.0)));
                ValueId h = residual(n);
                ValueId side = negative(h);
                ValueId cross = changesSign(v[2], h);
                Vals got = b_.ifThenElse(
                    cross,
                    [&] {
                        ValueId z = firstWhere(b_, b_.add(v[1], c(1.0)), n, [&](ValueId m) {
                            return eq(negative(residual(m)), side);
                        });
                        ValueId d = perResidual(b_.sub(residual(z), residual(b_.sub(z, c(1.0)))));
                        return Vals{d, b_.sub(c(1.0), crossingInk(z, d, width))};
                    },
                    [&] {
                        return Vals{c(0.0), c(1.0)};
                    });
                return Vals{b_.add(v[0], c(1.0)), n, h, b_.add(v[3], got[0]), b_.mul(v[4], got[1])};
            });
        return Vals{res[3], b_.sub(c(1.0), res[4])};
    }
    // The near field past the members counted one by one: the coarea sum of [a, b] with each
    // member's phase n theta taken as evenly spread over a turn (the run makes many turns) but
    // its residual taken whole, not to first order: at kPhaseNodes members n of the run, the
    // crossings of h(n, phi) = rho(Rot(-phi) p - n delta) - (n s + phase) = 0 over a turn of
    // phi, sampled at kPhaseAngles angles, each sign change contributing 1 / (M |dh|) (the
    // density (1 / 2 pi) sum 1 / |dh/dphi| of its zeros), times the run's length. Near the
    // origin of the walk every facet of the shape takes part, which the first order's one
    // cosine leaves out (it drew a hexagon at the marginal drift 15% light).
    ValueId phaseAveraged(ValueId a, ValueId b) {
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
                        ValueId add = b_.select(
                            changesSign(u[1], h),
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
    ValueId countedCrossings(ValueId lo, ValueId hi, ValueId fade) {
        Vals res = b_.loop(
            {lo, residual(lo), c(0.0)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], hi)}; },
            [&](std::span<const ValueId> v) {
                ValueId next = b_.add(v[0], c(1.0));
                ValueId h = residual(next);
                ValueId weight = b_.select(
                    b_.gt(fade, c(0.0)),
                    b_.clamp(b_.div(b_.sub(hi, next), b_.max(fade, c(1.0))), c(0.0), c(1.0)),
                    c(1.0));
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
    ValueId nearDensity(ValueId lo, ValueId hi, ValueId b) {
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
    ValueId branchesInk(ValueId width, ValueId density, ValueId share, ValueId r) {
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
    ValueId arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r) {
        return arcsineDensity(na, nb, k, r, c(-1.0), c(1.0));
    }
    // The same, counting only the members whose x lies in [lo, hi] (within [-1, 1]).
    ValueId arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r, ValueId lo, ValueId hi) {
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
    ValueId vertexChange(ValueId na, ValueId nb, ValueId k, ValueId r) {
        ValueId beta = b_.emit(Op::Acos, {kappa_});
        ValueId len = b_.max(len_, c(1e-9));
        ValueId off = b_.emit(Op::Acos, {b_.clamp(b_.div(drift_, len), c(-1.0), c(1.0))});
        ValueId second = b_.mul(len, b_.cos(b_.sub(b_.mul(beta, c(2.0)), off)));
        ValueId delta = b_.max(b_.sub(drift_, second), c(0.0));
        ValueId height = b_.max(b_.mul(r, b_.sub(c(1.0), kappa_)), c(1e-9));
        ValueId taper = b_.clamp(b_.sub(c(1.0), b_.div(b_.mul(b_.max(na, c(0.0)), delta), height)),
                                 c(0.0), c(1.0));
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
    ValueId crowdCoincidence(ValueId a, ValueId b, ValueId k, ValueId r, double turns) {
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
        auto found = [&](ValueId q, ValueId dev) {
            return both(b_.le(q, count), b_.lt(dev, width));
        };
        // q = 1, p = 0 first (x < 1/2: its nearest whole number is 0).
        ValueId dev1 = deviation(c(0.0), c(1.0));
        ValueId first = found(c(1.0), dev1);
        // Carried: step, fract, p, q, the previous p and q, found q (0: none), its dev.
        Vals init = {c(0.0),
                     x,
                     c(0.0),
                     c(1.0),
                     c(1.0),
                     c(0.0),
                     b_.select(first, c(1.0), c(0.0)),
                     b_.select(first, dev1, c(0.0))};
        Vals res = b_.loop(
            init,
            [&](std::span<const ValueId> v) {
                return Vals{both(both(b_.lt(v[0], c(kCrowdConvergents)), b_.gt(v[1], c(1e-7))),
                                 eq(v[6], c(0.0)))};
            },
            [&](std::span<const ValueId> v) {
                ValueId y = b_.div(c(1.0), v[1]);
                ValueId a = b_.floor(y);
                ValueId p = b_.add(b_.mul(a, v[2]), v[4]);
                ValueId q = b_.add(b_.mul(a, v[3]), v[5]);
                ValueId dev = deviation(p, q);
                ValueId hit = found(q, dev);
                return Vals{b_.add(v[0], c(1.0)),
                            b_.sub(y, a),
                            p,
                            q,
                            v[2],
                            v[3],
                            b_.select(hit, q, c(0.0)),
                            b_.select(hit, dev, c(0.0))};
            });
        ValueId q = res[6], dev = res[7];
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
    void searchedIndex(ValueId argmin, LayerFields& out) {
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
        ValueId frac =
            b_.select(usable, toward,
                      b_.select(eq(n, c(0.0)), alone, b_.max(c(-1.0), b_.min(c(1.0), alone))));
        // A NaN radius (see run()) leaves the index at the searched member (or at 0).
        out.index = b_.denan(b_.add(n, frac), n);
        out.gradX = b_.emit(Op::DerivX, {out.index});
        out.gradY = b_.emit(Op::DerivY, {out.index});
    }

    ir::Builder& b_;
    const WalkingInputs& in_;
    const RadiusFn& rho_;
    ValueId s_, guard_, accept_, r_, len_, round_, drift_, kappa_;
    ValueId still_, quadratic_, closedPolygon_, wholePolygon_;
    ValueId facetCos_ = ir::kNoValue, facetSin_ = ir::kNoValue; // Rot(2 pi / N), no fast paths
    ValueId nLo_, nHiRaw_;
    ValueId crowdLo_, crowdHiRaw_; // the interval of the pattern's own guard (setUp)
    bool counting_ = true;         // the radius's evaluations go to the tally (countEvaluations)
    // Jumps of up to 2^kCarriedPowers - 1 strides keep the rotation. Most skips are short:
    // on the walking examples 7 and 15 measured alike, 63 slower (a deeper product).
    static constexpr int kCarriedPowers = 3;
    // Convergents of theta / 2 pi the crowd estimate looks through for a period of the turn:
    // their denominators at least double every two steps, so 24 reach past the span cap.
    static constexpr double kCrowdConvergents = 24;
    // Near members counted one by one (countedCrossings); beyond, the phase average.
    static constexpr double kNearCounted = 256;
    // Picked chains (ChainSelection.h): the near members drawn one by one, at most, and how
    // far past n ||delta|| sin(pi / N) = r the far members are taken to start.
    static constexpr double kNearDrawn = 256;
    static constexpr double kFarForm = 1.5;
    // Half a square's diagonal over its side: the farthest its footprint reaches.
    static constexpr double kHalfDiagonal = 0.7072;
    // The rest of the near field: members and angles of its phase average (phaseAveraged).
    static constexpr double kPhaseNodes = 12;
    static constexpr double kPhaseAngles = 24;
    // Members over which the counted crossings hand over to the phase average (nearDensity).
    static constexpr double kSeamFade = 16;
    // The size of a closed form's residual terms, in pixels, up to which its crowd is drawn
    // (closedCrowding): 2^12.
    static constexpr double kFloatReach = 4096;
    // Few turns: h sampled at this many members over the interval (sampledCrossings), and the
    // arcsine average taking over from kFewTurns to twice as many turns.
    static constexpr double kCrossingSamples = 64;
    static constexpr double kFewTurns = 2;
    // A crossing's members drawn either side of it, and up to how many within reach they are
    // drawn rather than taken as a comb (crossingInk).
    static constexpr double kCrossingRun = 4;
    std::array<std::pair<ValueId, ValueId>, kCarriedPowers> turnPowers_;
};

} // namespace

LayerFields walkingFamilyFields(ir::Builder& b, const WalkingInputs& in, const RadiusFn& rho) {
    return Solver(b, in, rho).run();
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
