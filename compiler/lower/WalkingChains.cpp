#include "compiler/lower/WalkingChains.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Plane.h"
#include "compiler/lower/Bisection.h"
#include "compiler/lower/ChainSelection.h"
#include "compiler/lower/Convergents.h"
#include "compiler/lower/TwoPasses.h"
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
// double every two steps, so 24 reach past kMaxSelected.
constexpr int kPeriodConvergents = 24;
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
// and over so small a turn h_j stays convex to first order. 0 where no such q <= kMaxSelected.
// Past kMaxChains the chains are not all drawn: ChainSelection.h picks those that reach.
class Chains {
  public:
    Chains(ir::Builder& b, const ChainInputs* in) : b_(b), in_(in) {}

    TurnPeriod period(ValueId turnAngle) {
        const double turn = 2.0 * std::numbers::pi;
        ValueId x = b_.div(b_.abs(turnAngle), c(turn));
        auto fits = [&](ValueId p, ValueId q) {
            ValueId within = b_.mul(q, c(kChainDrift / (turn * kWalkSpanCap)));
            return both(b_.le(q, c(kMaxSelected)), b_.le(b_.abs(b_.sub(b_.mul(q, x), p)), within));
        };
        const Convergent found =
            firstConvergent(b_, x, kPeriodConvergents, 1e-12, c(kMaxSelected), fits);
        ValueId sign = b_.select(b_.lt(turnAngle, c(0.0)), c(-1.0), c(1.0));
        ValueId drift = b_.sub(b_.mul(found.q, turnAngle), b_.mul(sign, b_.mul(found.p, c(turn))));
        ValueId q = b_.max(found.q, c(1.0));
        ValueId pq = wholeMod(b_, b_.mul(wholeMod(b_, found.p, q), found.before), q);
        ValueId inverse =
            wholeMod(b_, b_.select(eq(pq, c(1.0)), found.before, b_.neg(found.before)), q);
        return {found.q, found.p, drift, inverse};
    }

    // The crowd drawn chain by chain (above): the chains laid over one another as independent
    // inks, but for a chain and its mirror. Where q is even and p odd, chain j + q / 2 is chain
    // j turned by a half turn; at the marginal drift (every member passing through the origin)
    // the far members of both lie along the same line through the origin, from its two sides,
    // so their last members' strokes overlap (exactly, for a polygon's flat facet; by what the
    // curvature leaves, for circles), and that overlap is ink both chains hold: laid
    // independently it would be counted twice. With that shared stroke m, the pair's union is
    // 1 - (1 - A)(1 - B) / (1 - m). The chains are visited in the order 0, q/2, 1, 1 + q/2, ...
    // so that a pair is met in two consecutive steps.
    // Where `picked`, only the chains of the two windows are visited (ChainSelection.h), each
    // with its mirror, the second window's chains that the first's (or their mirrors) already
    // drew left out; the near members [lo, split) are then laid over them one by one. Returns
    // the ink.
    ValueId draw(const TurnPeriod& per, ValueId picked, const ChainWindows& win) {
        ValueId q = per.q;
        ValueId halfQ = b_.mul(q, c(0.5));
        ValueId halfP = b_.mul(per.p, c(0.5));
        ValueId mirror =
            both(eq(halfQ, b_.floor(halfQ)), b_.emit(Op::Ne, {halfP, b_.floor(halfP)}));
        ValueId steps = b_.select(picked, c(4.0 * kSelectSlots), q);
        // Whether window w's chains, or where paired their mirrors, hold the chain at turn k.
        auto heldBy = [&](int w, ValueId k) {
            auto in = [&](ValueId at) {
                return b_.lt(wholeMod(b_, b_.sub(at, win.from[w]), q), win.count[w]);
            };
            return b_.emit(Op::Or, {in(k), both(mirror, in(wholeMod(b_, b_.add(k, halfQ), q)))});
        };
        ValueId nearBlank = nearPaper(per, [&](ValueId k) {
            return b_.emit(Op::Or, {heldBy(0, k), heldBy(1, k)});
        });
        // Carried: step, the paper left, the pending chain's ink, its last member's residual
        // and its band; picked: the band of the window's last pair drawn and each window's sum.
        Vals res = b_.loop(
            {c(0.0), c(1.0), c(0.0), c(kFar), c(kFar), c(-kFar), c(kFar), c(-kFar), c(0.0), c(0.0)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], steps)}; },
            [&](std::span<const ValueId> v) {
                ValueId t = v[0];
                ValueId pairStep = b_.floor(b_.mul(t, c(0.5)));
                ValueId second = b_.emit(Op::Ne, {pairStep, b_.mul(t, c(0.5))});
                ValueId j =
                    b_.select(mirror, b_.add(pairStep, b_.select(second, halfQ, c(0.0))), t);
                // Picked: pair step `pairStep` is the window's slot d; its chain sits at turn k.
                ValueId later = b_.emit(Op::Ge, {pairStep, c(kSelectSlots)});
                ValueId d = b_.sub(pairStep, b_.select(later, c(kSelectSlots), c(0.0)));
                ValueId k = wholeMod(b_, b_.add(b_.select(later, win.from[1], win.from[0]), d), q);
                ValueId jk = wholeMod(b_, b_.mul(k, per.inverse), q);
                jk = b_.select(second, wholeMod(b_, b_.add(jk, halfQ), q), jk);
                ValueId drawn = heldBy(0, k);
                ValueId take = both(b_.lt(d, b_.select(later, win.count[1], win.count[0])),
                                    b_.emit(Op::Or, {mirror, b_.emit(Op::Not, {second})}));
                take = both(take, b_.emit(Op::Not, {both(later, drawn)}));
                j = b_.select(picked, jk, j);
                ValueId active = b_.emit(Op::Or, {b_.emit(Op::Not, {picked}), take});
                // A window's chains are nearly one line at the pixel: across its normal.
                along_ =
                    b_.select(picked, b_.select(later, win.along[1], win.along[0]), in_->along);
                across_ =
                    b_.select(picked, b_.select(later, win.across[1], win.across[0]), in_->across);
                ChainInk got = chain(j, q, per.drift, active);
                ValueId ink = got.ink;
                ValueId shared = overlapMean(v[3], b_.neg(got.tail));
                ValueId kept = b_.max(b_.sub(c(1.0), shared), c(1e-6));
                ValueId pairBlank = b_.div(b_.mul(b_.sub(c(1.0), v[2]), b_.sub(c(1.0), ink)), kept);
                pairBlank = b_.clamp(pairBlank, c(0.0), b_.sub(c(1.0), b_.max(v[2], ink)));
                ValueId closes = both(mirror, second);
                ValueId opens = both(mirror, b_.emit(Op::Not, {second}));
                ValueId paper = b_.select(
                    opens, v[1], b_.mul(v[1], b_.select(closes, pairBlank, b_.sub(c(1.0), ink))));
                // Picked: the chains of a window are nearly parallel lines sorted along its
                // normal (by turn), and the strokes of neighbouring chains lie side by side:
                // laid as independent inks they leave paper between them that is not there
                // (a solid fan of lines drawn at 0.9). So a window's pairs are summed, each less
                // its overlap with the last pair drawn, as runUnion sums a run's strokes. A
                // mirror's band is its own residuals turned over (its normal is the other way).
                ValueId pairInk = b_.select(closes, b_.sub(c(1.0), pairBlank), ink);
                ValueId lo = b_.select(closes, b_.min(v[4], b_.neg(got.hi)), got.lo);
                ValueId hi = b_.select(closes, b_.max(v[5], b_.neg(got.lo)), got.hi);
                ValueId firstSlot = eq(d, c(0.0));
                ValueId prevLo = b_.select(firstSlot, c(kFar), v[6]);
                ValueId prevHi = b_.select(firstSlot, c(-kFar), v[7]);
                ValueId overlap = intervalMean(b_.max(prevLo, lo), b_.min(prevHi, hi));
                ValueId some = b_.lt(lo, hi);
                ValueId add = b_.select(some, b_.max(b_.sub(pairInk, overlap), c(0.0)), c(0.0));
                ValueId pairDone = b_.emit(Op::Not, {opens});
                add = b_.select(pairDone, add, c(0.0));
                ValueId keep = both(pairDone, some);
                return Vals{b_.add(t, c(1.0)),
                            paper,
                            ink,
                            got.tail,
                            got.lo,
                            got.hi,
                            b_.select(keep, lo, prevLo),
                            b_.select(keep, hi, prevHi),
                            b_.add(v[8], b_.select(later, c(0.0), add)),
                            b_.add(v[9], b_.select(later, add, c(0.0)))};
            });
        ValueId windows =
            b_.mul(b_.sub(c(1.0), b_.min(res[8], c(1.0))), b_.sub(c(1.0), b_.min(res[9], c(1.0))));
        return b_.sub(c(1.0), b_.mul(b_.select(picked, windows, res[1]), nearBlank));
    }
    // The paper the near members [lo, split) leave, each laid as an independent ink: they stand
    // at every turn and cross the pixel at their own angles. A member of a chain that is drawn
    // is left to its chain (from its first member on): near the far form's start such a member
    // can be the same line as its chain's far members, and laid apart it was counted twice.
    template <class Drawn>
    ValueId nearPaper(const TurnPeriod& per, Drawn drawnChain) {
        along_ = in_->along;
        across_ = in_->across;
        ValueId pm = wholeMod(b_, per.p, per.q);
        Vals res = b_.loop(
            {in_->lo, c(1.0)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], in_->split)}; },
            [&](std::span<const ValueId> v) {
                ValueId k = wholeMod(b_, b_.mul(wholeMod(b_, v[0], per.q), pm), per.q);
                auto [x, y] = in_->unturn(b_.mul(v[0], in_->turn));
                ValueId h = b_.abs(in_->residual(v[0], x, y));
                ValueId near = both(b_.lt(h, in_->reach), b_.emit(Op::Not, {drawnChain(k)}));
                ValueId ink = b_.select(near, memberMean(h), c(0.0));
                return Vals{b_.add(v[0], c(1.0)), b_.mul(v[1], b_.sub(c(1.0), ink))};
            });
        return b_.denan(res[1], c(1.0));
    }
    // Chain j's ink over the footprint, its last member's signed residual, and the band of
    // residuals its strokes within reach cover (lo > hi: none). Nothing where not `active`.
    struct ChainInk {
        ValueId ink, tail, lo, hi;
    };
    ChainInk chain(ValueId j, ValueId q, ValueId drift, ValueId active) {
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
            both(active, b_.lt(first, after)),
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
                Vals ink = b_.ifThenElse(
                    b_.lt(below, reach), [&] { return runs(first, last, h); },
                    [&] {
                        return Vals{c(0.0), c(kFar), c(-kFar)};
                    });
                return Vals{ink[0], hLast, ink[1], ink[2]};
            },
            [&] {
                return Vals{c(0.0), c(kFar), c(kFar), c(-kFar)};
            });
        return {got[0], got[1], got[2], got[3]};
    }
    // The ink of chain [first, last] (residuals h(i), convex in i) where some member may be
    // within reach: the runs of members within reach on either side of the lowest member;
    // with the band of residuals their strokes cover (lo > hi where no member reaches).
    // The two runs are summed as two passes of one loop, so that a run's union is built into
    // the kernel once rather than once a run (each copy was a sixth of a walking layer's
    // kernel, reading the residual nine times). Their four ends stay four bisections in
    // line: as four passes of a loop they saved 250 lines of the default scene's IR and cost
    // the chains' frame 4% (docs/filtering.md, "Cost").
    template <class H>
    Vals runs(ValueId first, ValueId last, H h) {
        ValueId reach = in_->reach;
        ValueId after = b_.add(last, c(1.0));
        ValueId low = firstWhere(b_, first, last, [&](ValueId i) {
            return b_.emit(Op::Ge, {h(b_.add(i, c(1.0))), h(i)});
        });
        ValueId hLow = h(low);
        return b_.ifThenElse(
            b_.lt(hLow, reach),
            [&] {
                ValueId past = b_.add(low, c(1.0));
                // The runs' ends: falling, from the first member down to the lowest, the first
                // members within reach (fa) and past it (fb); rising, past the lowest, the first
                // members back within reach (ra) and out of it (rb).
                ValueId fa =
                    firstWhere(b_, first, past, [&](ValueId i) { return b_.lt(h(i), reach); });
                ValueId fb = firstWhere(b_, first, past,
                                        [&](ValueId i) { return b_.lt(h(i), b_.neg(reach)); });
                ValueId ra = firstWhere(b_, past, after,
                                        [&](ValueId i) { return b_.gt(h(i), b_.neg(reach)); });
                ValueId rb = firstWhere(b_, past, after, [&](ValueId i) {
                    return b_.emit(Op::Ge, {h(i), reach});
                });
                // Rising: taken from the lowest where the run starts next to it (the two runs
                // share its stroke, counted once).
                ValueId fromLow = eq(ra, past);
                ValueId riseFrom = b_.select(fromLow, low, ra);
                // Each run's union, and the band its strokes cover: a run's members fall (rise)
                // in residual along it, so the band's ends are its first and last members'.
                const auto [fall, rise] = twoPasses(b_, 3, [&](ValueId rising) {
                    ValueId from = b_.select(rising, riseFrom, fa);
                    ValueId to = b_.select(rising, rb, fb);
                    ValueId ink = runUnion(from, to, h, rising);
                    ValueId hFirst = h(from), hLast = h(b_.max(b_.sub(to, c(1.0)), from));
                    return Vals{ink, b_.select(rising, hFirst, hLast),
                                b_.select(rising, hLast, hFirst)};
                });
                ValueId falling = fall[0];
                ValueId rising = b_.max(
                    b_.sub(rise[0], b_.select(fromLow, memberMean(b_.abs(hLow)), c(0.0))), c(0.0));
                ValueId half = b_.mul(in_->stroke, c(0.5));
                ValueId someFalling = b_.lt(fa, fb);
                ValueId someRising = b_.lt(riseFrom, rb);
                ValueId lo = b_.min(b_.select(someFalling, fall[1], c(kFar)),
                                    b_.select(someRising, rise[1], c(kFar)));
                ValueId hi = b_.max(b_.select(someFalling, fall[2], c(-kFar)),
                                    b_.select(someRising, rise[2], c(-kFar)));
                return Vals{b_.sub(c(1.0), b_.mul(b_.sub(c(1.0), falling), b_.sub(c(1.0), rising))),
                            b_.sub(lo, half), b_.add(hi, half)};
            },
            [&] {
                return Vals{c(0.0), c(kFar), c(-kFar)};
            });
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
    // rising one, `fromEnd`, a bool), so past that member every stroke overlaps the next and
    // their union is one band, from the first of them to the last widened by half a stroke;
    // the members before it stand a stroke or more apart and are summed one by one (or, past
    // kChainRun of them, taken as an even comb). A pile of hundreds of members on a flat facet
    // after a few far apart is then exact, where reading the run at evenly spread members
    // laid the few and the pile as one comb, solid across the gap. A short run is summed
    // whole by the same sum as a long run's members before its band (its band then empty).
    template <class HOf>
    ValueId runUnion(ValueId a, ValueId b, HOf hOf, ValueId fromEnd) {
        ValueId count = b_.sub(b, a);
        // The member `o` steps from the end where the steps are widest.
        ValueId last = b_.sub(b, c(1.0));
        auto at = [&](ValueId o) { return b_.select(fromEnd, b_.sub(last, o), b_.add(a, o)); };
        ValueId width = b_.max(in_->stroke, c(1e-9));
        ValueId half = b_.mul(width, c(0.5));
        ValueId few = b_.le(count, c(kChainRun));
        ValueId solid = b_.ifThenElse(
            few, [&] { return Vals{count}; },
            [&] {
                return Vals{firstWhere(b_, c(0.0), b_.sub(count, c(1.0)), [&](ValueId o) {
                    ValueId next = hOf(at(b_.add(o, c(1.0))));
                    return b_.lt(b_.abs(b_.sub(next, hOf(at(o)))), width);
                })};
            })[0];
        ValueId spread = b_.ifThenElse(
            b_.le(solid, c(kChainRun)), [&] { return Vals{sumStrokes(c(0.0), solid, at, hOf)}; },
            [&] {
                ValueId h0 = hOf(at(c(0.0))), h1 = hOf(at(b_.sub(solid, c(1.0))));
                ValueId span = b_.add(b_.abs(b_.sub(h1, h0)), width);
                ValueId fill = b_.min(c(1.0), b_.div(b_.mul(width, solid), span));
                return Vals{b_.mul(fill, intervalMean(b_.sub(b_.min(h0, h1), half),
                                                      b_.add(b_.max(h0, h1), half)))};
            })[0];
        return b_.ifThenElse(
            few, [&] { return Vals{spread}; },
            [&] {
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
    // The strokes of the members `at(o)`, o in [from, to), sorted along their normal
    // (sortedStrokesMean).
    template <class At, class HOf>
    ValueId sumStrokes(ValueId from, ValueId to, At at, HOf hOf) {
        return sortedStrokesMean(
            b_, in_->stroke, from, to, [&](ValueId o) { return hOf(at(o)); },
            [&](ValueId centre, ValueId half) { return bandMean(centre, half); });
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
    ValueId bandMean(ValueId centre, ValueId half) {
        return in_->bandMean(centre, half, along_, across_);
    }
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
    // The footprint the strokes being summed are drawn with.
    ValueId along_ = ir::kNoValue, across_ = ir::kNoValue;
};

} // namespace

std::pair<ValueId, ValueId> memberNormal(ir::Builder& b, const ChainInputs& in, ValueId n,
                                         ValueId psi, ValueId e) {
    auto [x, y] = in.unturn(psi);
    ValueId gx = b.sub(in.residual(n, b.add(x, e), y), in.residual(n, b.sub(x, e), y));
    ValueId gy = b.sub(in.residual(n, x, b.add(y, e)), in.residual(n, x, b.sub(y, e)));
    ValueId cs = b.cos(psi), sn = b.sin(psi);
    return {b.sub(b.mul(cs, gx), b.mul(sn, gy)), b.add(b.mul(sn, gx), b.mul(cs, gy))};
}

ValueId sortedStrokesMean(ir::Builder& b, ValueId stroke, ValueId from, ValueId to,
                          const std::function<ValueId(ValueId)>& h,
                          const std::function<ValueId(ValueId, ValueId)>& bandMean) {
    const ValueId half = b.mul(stroke, b.constF(0.5));
    // Carried: i, the last stroke's residual, the union so far.
    Vals res = b.loop(
        {from, b.constF(0.0), b.constF(0.0)},
        [&](std::span<const ValueId> v) { return Vals{b.lt(v[0], to)}; },
        [&](std::span<const ValueId> v) {
            ValueId hv = h(v[0]);
            // Two strokes centred at residuals a and b share the stroke of half-width
            // max(t - |a - b|, 0) / 2 centred on (a + b) / 2.
            ValueId shared = b.max(b.sub(stroke, b.abs(b.sub(v[1], hv))), b.constF(0.0));
            ValueId overlap = b.select(
                b.gt(v[0], from),
                bandMean(b.mul(b.add(v[1], hv), b.constF(0.5)), b.mul(shared, b.constF(0.5))),
                b.constF(0.0));
            ValueId add = b.sub(bandMean(b.abs(hv), half), overlap);
            return Vals{b.add(v[0], b.constF(1.0)), hv, b.add(v[2], add)};
        });
    return res[2];
}

TurnPeriod turnPeriod(ir::Builder& b, ValueId turn) {
    return Chains(b, nullptr).period(turn);
}

ValueId chainInk(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period, ValueId picked,
                 const ChainWindows& windows) {
    return Chains(b, &in).draw(period, picked, windows);
}

} // namespace moire::lower
