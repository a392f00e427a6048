#include "compiler/lower/WalkingChains.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Plane.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/WalkingFamily.h"

#include <numbers>
#include <span>
#include <utility>
#include <vector>

namespace moire::lower {

using ir::BuiltValue;
using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

// A residual no member reaches: larger than any reach, finite in single precision.
constexpr double kFar = 1e30;
// Convergents of theta / 2 pi looked through for the period: their denominators at least
// double every two steps, so 24 reach far past kMaxChains.
constexpr double kPeriodConvergents = 24;
// A run of up to this many members within reach is summed member by member (runUnion).
constexpr double kChainRun = 12;

// A turn by a whole share of a full turn, theta = 2 pi p / q: member n + q is member n
// turned by p whole turns, so the members fall into q chains n = j + q i, and along a
// chain the shape no longer turns. Its residual is then a translated shape's,
//     h_j(i) = rho(Rot(-j theta) p - n delta) - (n s + phase),   n = j + q i,
// convex in i (rho is convex, its argument affine in i), as with no turn at all: it
// falls, then rises, and the chain's members within reach of the pixel are two runs,
// one on either side of its lowest member, each found by two bisections. Each run is
// one set of strokes sorted along their common normal, whose union over the footprint is
// exact by inclusion and exclusion (runUnion). So where the turn's period is short, the
// crowd is not estimated but drawn: every member's stroke counts, at its own residual.
// The period is the first convergent denominator q of |theta| / 2 pi whose remainder
// e = q theta - 2 pi p (a turn of the chain a member) turns no chain of the capped
// interval by more than kChainDrift: each member is read at its own angle j theta + i e,
// and over so small a turn h_j stays convex to first order. 0 where no such q <= kMaxChains.
class Chains {
  public:
    Chains(ir::Builder& b, const ChainInputs* in) : b_(b), in_(in) {}

    TurnPeriod period(ValueId turnAngle) {
        const double turn = 2.0 * std::numbers::pi;
        ValueId x = b_.div(b_.abs(turnAngle), c(turn));
        auto fits = [&](ValueId p, ValueId q) {
            ValueId within = b_.mul(q, c(kChainDrift / (turn * kWalkSpanCap)));
            return both(b_.le(q, c(kMaxChains)), b_.le(b_.abs(b_.sub(b_.mul(q, x), p)), within));
        };
        ValueId nearest = b_.round(x); // q = 1: p whole turns
        ValueId whole = b_.floor(x);
        ValueId first = fits(nearest, c(1.0));
        // Carried: step, fract, p, q, the previous p and q, found q (0: none), its p.
        Vals res = b_.loop(
            {c(0.0), b_.sub(x, whole), whole, c(1.0), c(1.0), c(0.0),
             b_.select(first, c(1.0), c(0.0)), nearest},
            [&](std::span<const ValueId> v) {
                return Vals{both(both(b_.lt(v[0], c(kPeriodConvergents)), b_.gt(v[1], c(1e-12))),
                                 both(eq(v[6], c(0.0)), b_.le(v[3], c(kMaxChains))))};
            },
            [&](std::span<const ValueId> v) {
                ValueId y = b_.div(c(1.0), v[1]);
                ValueId a = b_.floor(y);
                ValueId p = b_.add(b_.mul(a, v[2]), v[4]);
                ValueId q = b_.add(b_.mul(a, v[3]), v[5]);
                ValueId hit = fits(p, q);
                return Vals{b_.add(v[0], c(1.0)),      b_.sub(y, a),           p, q, v[2], v[3],
                            b_.select(hit, q, c(0.0)), b_.select(hit, p, v[7])};
            });
        ValueId sign = b_.select(b_.lt(turnAngle, c(0.0)), c(-1.0), c(1.0));
        ValueId drift = b_.sub(b_.mul(res[6], turnAngle), b_.mul(sign, b_.mul(res[7], c(turn))));
        return {res[6], res[7], drift};
    }

    // The crowd drawn chain by chain (above): the chains laid over one another as independent
    // inks, but for a chain and its mirror. Where q is even and p odd, chain j + q / 2 is chain
    // j turned by a half turn; at the marginal drift (every member passing through the origin)
    // the far members of both lie along the same line through the origin, from its two sides,
    // so their last members' strokes overlap (exactly, for a polygon's flat facet; by what the
    // curvature leaves, for circles), and that overlap is ink both chains hold: laid
    // independently it would be counted twice. With that shared stroke m, the pair's union is
    // 1 - (1 - A)(1 - B) / (1 - m). The chains are visited in the order 0, q/2, 1, 1 + q/2, ...
    // so that a pair is met in two consecutive steps. Returns the ink.
    ValueId draw(const TurnPeriod& per) {
        ValueId q = per.q;
        ValueId halfQ = b_.mul(q, c(0.5));
        ValueId halfP = b_.mul(per.p, c(0.5));
        ValueId mirror =
            both(eq(halfQ, b_.floor(halfQ)), b_.emit(Op::Ne, {halfP, b_.floor(halfP)}));
        // Carried: step, the paper left, the pending chain's ink and its last member's residual.
        Vals res = b_.loop(
            {c(0.0), c(1.0), c(0.0), c(kFar)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], q)}; },
            [&](std::span<const ValueId> v) {
                ValueId t = v[0];
                ValueId pairStep = b_.floor(b_.mul(t, c(0.5)));
                ValueId second = b_.emit(Op::Ne, {pairStep, b_.mul(t, c(0.5))});
                ValueId j =
                    b_.select(mirror, b_.add(pairStep, b_.select(second, halfQ, c(0.0))), t);
                auto [ink, tail] = chain(j, q, per.drift);
                ValueId shared = overlapMean(v[3], b_.neg(tail));
                ValueId kept = b_.max(b_.sub(c(1.0), shared), c(1e-6));
                ValueId pairBlank = b_.div(b_.mul(b_.sub(c(1.0), v[2]), b_.sub(c(1.0), ink)), kept);
                pairBlank = b_.clamp(pairBlank, c(0.0), b_.sub(c(1.0), b_.max(v[2], ink)));
                ValueId closes = both(mirror, second);
                ValueId opens = both(mirror, b_.emit(Op::Not, {second}));
                ValueId paper = b_.select(
                    opens, v[1], b_.mul(v[1], b_.select(closes, pairBlank, b_.sub(c(1.0), ink))));
                return Vals{b_.add(t, c(1.0)), paper, ink, tail};
            });
        return b_.sub(c(1.0), res[1]);
    }
    // Chain j's ink over the footprint, and its last member's signed residual.
    std::pair<ValueId, ValueId> chain(ValueId j, ValueId q, ValueId drift) {
        ValueId first = b_.max(ceil(b_.div(b_.sub(in_->lo, j), q)), c(0.0));
        ValueId after = b_.add(b_.floor(b_.div(b_.sub(b_.sub(in_->end, c(1.0)), j), q)), c(1.0));
        // The chain's first member turned by j theta + first e, with a cosine and a sine; the
        // others by that and the small (i - first) e, at most kChainDrift, by its series.
        auto [bx, by] = in_->unturn(b_.add(b_.mul(j, in_->turn), b_.mul(first, drift)));
        auto h = [&](ValueId i) {
            auto [cs, sn] = smallTurn(b_.mul(b_.sub(i, first), drift));
            ir::Vec2T<BuiltValue> turned = ir::unrotate({BuiltValue(b_, bx), BuiltValue(b_, by)},
                                                        BuiltValue(b_, cs), BuiltValue(b_, sn));
            return in_->residual(b_.add(j, b_.mul(q, i)), turned.x.id, turned.y.id);
        };
        Vals got = b_.ifThenElse(
            b_.lt(first, after),
            [&] {
                ValueId last = b_.sub(after, c(1.0));
                ValueId reach = in_->reach;
                // A convex h lies above its tangents at the chain's two ends: where even their
                // meeting point stays out of reach, so does every member, and the chain is left
                // without a search.
                ValueId hFirst = h(first), hLast = h(last);
                ValueId g0 = b_.sub(h(b_.add(first, c(1.0))), hFirst);
                ValueId g1 = b_.sub(hLast, h(b_.sub(last, c(1.0))));
                ValueId meet = b_.div(
                    b_.sub(b_.sub(hLast, hFirst), b_.sub(b_.mul(g1, last), b_.mul(g0, first))),
                    b_.sub(g0, g1));
                ValueId below =
                    b_.select(b_.emit(Op::Ge, {g0, c(0.0)}), hFirst,
                              b_.select(b_.le(g1, c(0.0)), hLast,
                                        b_.add(hFirst, b_.mul(g0, b_.sub(meet, first)))));
                below = b_.select(b_.lt(b_.sub(last, first), c(2.0)), c(-kFar), below);
                ValueId ink = b_.ifThenElse(
                    b_.lt(below, reach), [&] { return Vals{runs(first, last, h)}; },
                    [&] { return Vals{c(0.0)}; })[0];
                return Vals{ink, hLast};
            },
            [&] {
                return Vals{c(0.0), c(kFar)};
            });
        return {got[0], got[1]};
    }
    // The ink of chain [first, last] (residuals h(i), convex in i) where some member may be
    // within reach: the runs of members within reach on either side of the lowest member.
    template <class H>
    ValueId runs(ValueId first, ValueId last, H h) {
        ValueId reach = in_->reach;
        ValueId after = b_.add(last, c(1.0));
        ValueId low = firstWhere(b_, first, last, [&](ValueId i) {
            return b_.emit(Op::Ge, {h(b_.add(i, c(1.0))), h(i)});
        });
        ValueId hLow = h(low);
        return b_.ifThenElse(
            b_.lt(hLow, reach),
            [&] {
                // Falling: from the first member down to the lowest.
                ValueId past = b_.add(low, c(1.0));
                ValueId fa =
                    firstWhere(b_, first, past, [&](ValueId i) { return b_.lt(h(i), reach); });
                ValueId fb = firstWhere(b_, first, past,
                                        [&](ValueId i) { return b_.lt(h(i), b_.neg(reach)); });
                ValueId falling = runUnion(fa, fb, h, false);
                // Rising: past the lowest, taken from the lowest where the run starts next to
                // it (the two runs share its stroke, counted once).
                ValueId ra = firstWhere(b_, past, after,
                                        [&](ValueId i) { return b_.gt(h(i), b_.neg(reach)); });
                ValueId rb = firstWhere(b_, past, after, [&](ValueId i) {
                    return b_.emit(Op::Ge, {h(i), reach});
                });
                ValueId fromLow = eq(ra, past);
                ValueId rising =
                    b_.max(b_.sub(runUnion(b_.select(fromLow, low, ra), rb, h, true),
                                  b_.select(fromLow, memberMean(b_.abs(hLow)), c(0.0))),
                           c(0.0));
                return Vals{
                    b_.sub(c(1.0), b_.mul(b_.sub(c(1.0), falling), b_.sub(c(1.0), rising)))};
            },
            [&] { return Vals{c(0.0)}; })[0];
    }
    // cos a and sin a for |a| <= kChainDrift, by their Taylor series to a^6 and a^7: within
    // 1e-13 there, where a cosine and a sine would be two calls per member.
    std::pair<ValueId, ValueId> smallTurn(ValueId a) {
        ValueId a2 = b_.mul(a, a);
        auto term = [&](ValueId rest, double over) {
            return b_.sub(c(1.0), b_.mul(b_.mul(a2, c(1.0 / over)), rest));
        };
        ValueId sn = b_.mul(a, term(term(term(c(1.0), 42.0), 20.0), 6.0));
        ValueId cs = term(term(term(c(1.0), 30.0), 12.0), 2.0);
        return {cs, sn};
    }
    // The footprint mean of the union of the strokes of members [a, b) of a run sorted along
    // their normal (residuals hOf(i), monotone in i), by inclusion and exclusion: each
    // stroke's mean less that of its overlap with the next, exact for strokes of one width
    // sorted along a line (sumStrokes). A run of more than kChainRun members is split where
    // its steps fall under the stroke's width: on a convex h the steps shrink monotonically
    // towards the chain's lowest member (towards b on the falling run, towards a on the
    // rising one, `fromEnd`), so past that member every stroke overlaps the next and their
    // union is one band, from the first of them to the last widened by half a stroke; the
    // members before it stand a stroke or more apart and are summed one by one (or, past
    // kChainRun of them, taken as an even comb). A pile of hundreds of members on a flat facet
    // after a few far apart is then exact, where reading the run at evenly spread members
    // laid the few and the pile as one comb, solid across the gap.
    template <class HOf>
    ValueId runUnion(ValueId a, ValueId b, HOf hOf, bool fromEnd) {
        ValueId count = b_.sub(b, a);
        // The member `o` steps from the end where the steps are widest.
        ValueId last = b_.sub(b, c(1.0));
        auto at = [&](ValueId o) { return fromEnd ? b_.sub(last, o) : b_.add(a, o); };
        return b_.ifThenElse(
            b_.le(count, c(kChainRun)), [&] { return Vals{sumStrokes(c(0.0), count, at, hOf)}; },
            [&] {
                ValueId width = b_.max(in_->stroke, c(1e-9));
                ValueId half = b_.mul(width, c(0.5));
                ValueId solid = firstWhere(b_, c(0.0), b_.sub(count, c(1.0)), [&](ValueId o) {
                    ValueId next = hOf(at(b_.add(o, c(1.0))));
                    return b_.lt(b_.abs(b_.sub(next, hOf(at(o)))), width);
                });
                ValueId spread = b_.ifThenElse(
                    b_.le(solid, c(kChainRun)),
                    [&] { return Vals{sumStrokes(c(0.0), solid, at, hOf)}; },
                    [&] {
                        ValueId h0 = hOf(at(c(0.0))), h1 = hOf(at(b_.sub(solid, c(1.0))));
                        ValueId span = b_.add(b_.abs(b_.sub(h1, h0)), width);
                        ValueId fill = b_.min(c(1.0), b_.div(b_.mul(width, solid), span));
                        return Vals{b_.mul(fill, intervalMean(b_.sub(b_.min(h0, h1), half),
                                                              b_.add(b_.max(h0, h1), half)))};
                    })[0];
                ValueId hs = hOf(at(solid)), he = hOf(at(b_.sub(count, c(1.0))));
                ValueId lo = b_.sub(b_.min(hs, he), half), hi = b_.add(b_.max(hs, he), half);
                ValueId hp = hOf(at(b_.max(b_.sub(solid, c(1.0)), c(0.0))));
                ValueId overlap = b_.select(
                    b_.gt(solid, c(0.0)),
                    intervalMean(b_.max(lo, b_.sub(hp, half)), b_.min(hi, b_.add(hp, half))),
                    c(0.0));
                return Vals{b_.sub(b_.add(spread, intervalMean(lo, hi)), overlap)};
            })[0];
    }
    // The strokes of the members `at(o)`, o in [from, to), sorted along their normal: each
    // one's mean less that of its overlap with the one before.
    template <class At, class HOf>
    ValueId sumStrokes(ValueId from, ValueId to, At at, HOf hOf) {
        Vals res = b_.loop(
            {from, c(0.0), c(0.0)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], to)}; },
            [&](std::span<const ValueId> v) {
                ValueId hv = hOf(at(v[0]));
                ValueId overlap = b_.select(b_.gt(v[0], from), overlapMean(v[1], hv), c(0.0));
                ValueId add = b_.sub(memberMean(b_.abs(hv)), overlap);
                return Vals{b_.add(v[0], c(1.0)), hv, b_.add(v[2], add)};
            });
        return res[2];
    }
    // The footprint mean of the band of residuals [lo, hi] (nothing where hi <= lo).
    ValueId intervalMean(ValueId lo, ValueId hi) {
        return bandMean(b_.mul(b_.add(lo, hi), c(0.5)),
                        b_.mul(b_.max(b_.sub(hi, lo), c(0.0)), c(0.5)));
    }

  private:
    ValueId c(double v) { return b_.constF(v); }
    ValueId both(ValueId a, ValueId b) { return b_.emit(Op::And, {a, b}); }
    ValueId eq(ValueId a, ValueId b) { return b_.emit(Op::Eq, {a, b}); }
    ValueId ceil(ValueId v) { return b_.neg(b_.floor(b_.neg(v))); }
    ValueId bandMean(ValueId centre, ValueId half) { return in_->bandMean(centre, half); }
    // One member's stroke (half-width t / 2) at residual `value`.
    ValueId memberMean(ValueId value) { return bandMean(value, b_.mul(in_->stroke, c(0.5))); }
    // The overlap of the strokes centred at residuals a and b (signed, along a common normal):
    // the stroke of half-width max(t - |a - b|, 0) / 2 centred on (a + b) / 2.
    ValueId overlapMean(ValueId a, ValueId bv) {
        ValueId overlap = b_.max(b_.sub(in_->stroke, b_.abs(b_.sub(a, bv))), c(0.0));
        return bandMean(b_.mul(b_.add(a, bv), c(0.5)), b_.mul(overlap, c(0.5)));
    }

    ir::Builder& b_;
    const ChainInputs* in_; // null for the period alone
};

} // namespace

TurnPeriod turnPeriod(ir::Builder& b, ValueId turn) {
    return Chains(b, nullptr).period(turn);
}

ValueId chainInk(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period) {
    return Chains(b, &in).draw(period);
}

} // namespace moire::lower
