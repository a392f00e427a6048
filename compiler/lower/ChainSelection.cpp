#include "compiler/lower/ChainSelection.h"

#include "compiler/lower/TwoPasses.h"

#include <numbers>
#include <span>
#include <vector>

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

constexpr double kTurn = 2.0 * std::numbers::pi;
// The residual over a turn is read at this many turns of the member, evenly spread.
constexpr double kSamples = 32;
// Bisection steps refining a crossing between two samples: within 2 pi / 32 / 2^12.
constexpr double kRootSteps = 12;
// Crossings nearer than this many samples are a tangency, where the two windows merge and
// the residual between them stays near zero: left to the estimate.
constexpr double kMinSeparation = 3;

class Selector {
  public:
    Selector(ir::Builder& b, const ChainInputs& in, const TurnPeriod& per)
        : b_(b), in_(in), per_(per) {}

    ChainWindows select() {
        ValueId last = b_.sub(in_.end, c(1.0));
        auto [first, final] = crossingsAt(in_.split, last);
        // Pair each crossing at the first far member with the nearer one at the last: the
        // level moves evenly with n, so each crossing moves one way, and the turns between the
        // two are every turn at which a member between reaches zero.
        ValueId straight = b_.add(gap(first.at[0], final.at[0]), gap(first.at[1], final.at[1]));
        ValueId crossed = b_.add(gap(first.at[0], final.at[1]), gap(first.at[1], final.at[0]));
        ValueId swap = b_.lt(crossed, straight);
        ChainWindows out;
        ValueId widest = c(0.0);
        const Normals normals = normalsAt(in_.split, first.at[0], first.at[1]);
        for (int w = 0; w < 2; ++w) {
            ValueId a = first.at[w];
            ValueId bAt = b_.select(swap, final.at[1 - w], final.at[w]);
            ValueId aSlope = first.slope[w];
            ValueId bSlope = b_.select(swap, final.slope[1 - w], final.slope[w]);
            auto [from, count, width] = window(a, bAt, b_.min(aSlope, bSlope), last);
            out.from[w] = from;
            out.count[w] = count;
            out.normalX[w] = normals.x[w];
            out.normalY[w] = normals.y[w];
            out.along[w] = in_.along;
            out.across[w] = in_.across;
            widest = b_.max(widest, width);
        }
        ValueId found = both(first.ok, final.ok);
        ValueId fits =
            b_.sub(c(1.0), b_.smoothstep(c(kSelectSlots - 2.0), c(kSelectSlots - 1.0), widest));
        out.weight = b_.select(found, b_.denan(fits, c(0.0)), c(0.0));
        return out;
    }

  private:
    // Where the residual of member n over a full turn of it crosses zero: two crossings, each
    // with the slope of the chord of the samples about it.
    struct Crossings {
        ValueId ok;
        ValueId at[2], slope[2];
    };
    ValueId f(ValueId n, ValueId psi) {
        auto [x, y] = in_.unturn(psi);
        return in_.residual(n, x, y);
    }
    ValueId negative(ValueId h) { return b_.select(b_.lt(h, c(0.0)), c(1.0), c(0.0)); }
    ValueId changes(ValueId h0, ValueId h1) {
        return b_.emit(Op::Ne, {negative(h0), negative(h1)});
    }
    Crossings crossings(ValueId n) {
        const double step = kTurn / kSamples;
        // Samples m = 1 .. kSamples (the last is the first again); at m, sample m - 1 is judged
        // with both neighbours: a sample within reach of zero, or near enough that the
        // residual may dip within reach between it and a neighbour, and next to no crossing,
        // is a near miss the windows would not hold. Carried: m, f(m - 2), f(m - 1), the
        // crossings so far, the sample after each of the first two, their chords, the misses.
        Vals res = b_.loop(
            {c(1.0), f(n, c(-step)), f(n, c(0.0)), c(0.0), c(0.0), c(0.0), c(0.0), c(0.0), c(0.0)},
            [&](std::span<const ValueId> v) { return Vals{b_.le(v[0], c(kSamples))}; },
            [&](std::span<const ValueId> v) {
                ValueId m = v[0];
                ValueId fm = f(n, b_.mul(m, c(step)));
                ValueId here = changes(v[2], fm);
                ValueId before = changes(v[1], v[2]);
                ValueId dip =
                    b_.mul(b_.max(b_.abs(b_.sub(v[2], v[1])), b_.abs(b_.sub(fm, v[2]))), c(0.75));
                ValueId near = b_.lt(b_.abs(v[2]), b_.add(in_.reach, dip));
                ValueId miss = both(near, b_.emit(Op::Not, {b_.emit(Op::Or, {here, before})}));
                ValueId chord = b_.div(b_.abs(b_.sub(fm, v[2])), c(step));
                ValueId isFirst = both(here, eq(v[3], c(0.0)));
                ValueId isSecond = both(here, eq(v[3], c(1.0)));
                return Vals{b_.add(m, c(1.0)),
                            v[2],
                            fm,
                            b_.add(v[3], b_.select(here, c(1.0), c(0.0))),
                            b_.select(isFirst, m, v[4]),
                            b_.select(isSecond, m, v[5]),
                            b_.select(isFirst, chord, v[6]),
                            b_.select(isSecond, chord, v[7]),
                            b_.add(v[8], b_.select(miss, c(1.0), c(0.0)))};
            });
        ValueId apart = b_.sub(res[5], res[4]);
        apart = b_.min(apart, b_.sub(c(kSamples), apart));
        Crossings out;
        out.ok = both(both(eq(res[3], c(2.0)), eq(res[8], c(0.0))),
                      b_.emit(Op::Ge, {apart, c(kMinSeparation)}));
        // Both crossings refined together: each bracket [m - 1, m] samples, halved.
        ValueId lo0 = b_.mul(b_.sub(res[4], c(1.0)), c(step));
        ValueId lo1 = b_.mul(b_.sub(res[5], c(1.0)), c(step));
        ValueId neg0 = negative(f(n, lo0)), neg1 = negative(f(n, lo1));
        Vals refined = b_.loop(
            {c(0.0), lo0, lo1, c(step)},
            [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], c(kRootSteps))}; },
            [&](std::span<const ValueId> v) {
                ValueId half = b_.mul(v[3], c(0.5));
                ValueId m0 = b_.add(v[1], half), m1 = b_.add(v[2], half);
                ValueId same0 = eq(negative(f(n, m0)), neg0);
                ValueId same1 = eq(negative(f(n, m1)), neg1);
                return Vals{b_.add(v[0], c(1.0)), b_.select(same0, m0, v[1]),
                            b_.select(same1, m1, v[2]), half};
            });
        ValueId half = b_.mul(refined[3], c(0.5));
        out.at[0] = b_.add(refined[1], half);
        out.at[1] = b_.add(refined[2], half);
        out.slope[0] = res[6];
        out.slope[1] = res[7];
        return out;
    }
    // The crossings of members n0 and n1, as two passes of one loop: the residual over a turn
    // and its refinement are built into the kernel once, as are the four residuals of each
    // normal (normalsAt).
    std::pair<Crossings, Crossings> crossingsAt(ValueId n0, ValueId n1) {
        const auto [a, z] = twoPasses(b_, 5, [&](ValueId second) {
            Crossings x = crossings(b_.select(second, n1, n0));
            return Vals{b_.select(x.ok, c(1.0), c(0.0)), x.at[0], x.at[1], x.slope[0], x.slope[1]};
        });
        auto unpack = [&](const Vals& r) {
            return Crossings{b_.gt(r[0], c(0.5)), {r[1], r[2]}, {r[3], r[4]}};
        };
        return {unpack(a), unpack(z)};
    }
    // The normals at the pixel of member n turned by psi0 and by psi1 (memberNormal), as two
    // passes of one loop (four residuals each).
    struct Normals {
        ValueId x[2], y[2];
    };
    Normals normalsAt(ValueId n, ValueId psi0, ValueId psi1) {
        const auto [a, z] = twoPasses(b_, 2, [&](ValueId second) {
            auto [nx, ny] =
                memberNormal(b_, in_, n, b_.select(second, psi1, psi0), b_.max(in_.reach, c(1e-6)));
            return Vals{nx, ny};
        });
        return {{a[0], z[0]}, {a[1], z[1]}};
    }
    // The angle between two turns, the shorter way round.
    ValueId gap(ValueId a, ValueId bv) { return b_.abs(b_.wrap(b_.sub(bv, a), c(kTurn))); }
    // The window of chains whose members in [split, end) may reach the pixel, given the
    // crossing's turn at the first far member (a) and at the last (bAt), and the residual's
    // slope along the turn: the turns between the two, widened by the reach over the slope,
    // less each member's own remainder n e / q, as k = sign (turn) q / 2 pi.
    struct Window {
        ValueId from, count, width;
    };
    Window window(ValueId a, ValueId bAt, ValueId slope, ValueId last) {
        ValueId moved = b_.wrap(b_.sub(bAt, a), c(kTurn));
        ValueId margin = b_.add(b_.div(b_.mul(in_.reach, c(1.25)), b_.max(slope, c(1e-9))),
                                c(4.0 * kTurn / kSamples / double(1 << int(kRootSteps))));
        ValueId lo = b_.sub(b_.add(a, b_.min(moved, c(0.0))), margin);
        ValueId hi = b_.add(b_.add(a, b_.max(moved, c(0.0))), margin);
        ValueId perMember = b_.div(per_.drift, per_.q);
        ValueId e0 = b_.mul(in_.split, perMember), e1 = b_.mul(last, perMember);
        lo = b_.sub(lo, b_.max(e0, e1));
        hi = b_.sub(hi, b_.min(e0, e1));
        ValueId scale = b_.div(per_.q, c(kTurn));
        ValueId backwards = b_.lt(in_.turn, c(0.0));
        ValueId uLo = b_.mul(b_.select(backwards, b_.neg(hi), lo), scale);
        ValueId uHi = b_.mul(b_.select(backwards, b_.neg(lo), hi), scale);
        ValueId start = b_.neg(b_.floor(b_.neg(uLo)));
        ValueId count = b_.max(b_.add(b_.sub(b_.floor(uHi), start), c(1.0)), c(0.0));
        Window out;
        out.from = wholeMod(b_, start, per_.q);
        out.count = b_.min(count, c(kSelectSlots));
        out.width = b_.sub(uHi, uLo);
        return out;
    }

    ValueId c(double v) { return b_.constF(v); }
    ValueId both(ValueId a, ValueId bv) { return b_.emit(Op::And, {a, bv}); }
    ValueId eq(ValueId a, ValueId bv) { return b_.emit(Op::Eq, {a, bv}); }

    ir::Builder& b_;
    const ChainInputs& in_;
    const TurnPeriod& per_;
};

} // namespace

ValueId wholeMod(ir::Builder& b, ValueId v, ValueId q) {
    ValueId r = b.sub(v, b.mul(q, b.floor(b.div(v, q))));
    // a / q rounded in single precision may floor one off either way.
    r = b.select(b.lt(r, b.constF(0.0)), b.add(r, q), r);
    return b.select(b.emit(Op::Ge, {r, q}), b.sub(r, q), r);
}

ChainWindows selectChains(ir::Builder& b, const ChainInputs& in, const TurnPeriod& period) {
    return Selector(b, in, period).select();
}

} // namespace moire::lower
