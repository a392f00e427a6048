// The convergents of a turn's share of a full turn, looked through in the kernel: the walking
// solver finds a turn's period by them (WalkingChains.cpp: the first q that brings member
// n + q back onto member n's chain) and how many of a crowd's members are distinct strokes
// (WalkingDensity.cpp: the first q that brings member n + q within a stroke of member n).
// Both ask the same question, the first convergent p / q of x that a test passes, which the
// continued fraction's recurrence answers: the convergents are the best approximations of x,
// so no q between two of them comes nearer.
#pragma once

#include "compiler/ir/Builder.h"

#include <span>
#include <vector>

namespace moire::lower {

// The convergent found: q (0 where none passed), p, and the denominator before q (consecutive
// convergents have p q' - p' q = +-1, so p's inverse modulo q is +-q').
struct Convergent {
    ir::ValueId q, p, before;
};

// The first convergent p / q of x >= 0 for which `fits(p, q)` (emitting a bool), q = 1 first
// with p the whole number nearest x, then the continued fraction's: a_k = floor(1 / r_k),
// p_k = a_k p_{k-1} + p_{k-2}, q_k likewise, r_{k+1} = 1 / r_k - a_k. It stops after `steps`
// terms, where the remainder r falls to `least` (x is that near p / q, and the float's next
// terms are noise), or once q passes `most` (every later q is larger still).
template <class Fits>
Convergent firstConvergent(ir::Builder& b, ir::ValueId x, int steps, double least, ir::ValueId most,
                           Fits fits) {
    using ir::Op;
    using ir::ValueId;
    using Vals = std::vector<ValueId>;
    auto c = [&](double v) { return b.constF(v); };
    auto both = [&](ValueId l, ValueId r) { return b.emit(Op::And, {l, r}); };
    const ValueId whole = b.floor(x), nearest = b.round(x);
    const ValueId first = fits(nearest, c(1.0));
    // Carried: the term, the remainder, p and q, the two before them, the found q (0: none),
    // its p and the q before it.
    Vals init{
        c(0.0),  b.sub(x, whole), whole, c(1.0), c(1.0), c(0.0), b.select(first, c(1.0), c(0.0)),
        nearest, c(0.0)};
    Vals res = b.loop(
        init,
        [&](std::span<const ValueId> v) {
            return Vals{both(both(b.lt(v[0], c(steps)), b.gt(v[1], c(least))),
                             both(b.emit(Op::Eq, {v[6], c(0.0)}), b.le(v[3], most)))};
        },
        [&](std::span<const ValueId> v) {
            const ValueId y = b.div(c(1.0), v[1]);
            const ValueId a = b.floor(y);
            const ValueId p = b.add(b.mul(a, v[2]), v[4]);
            const ValueId q = b.add(b.mul(a, v[3]), v[5]);
            const ValueId hit = fits(p, q);
            return Vals{b.add(v[0], c(1.0)),
                        b.sub(y, a),
                        p,
                        q,
                        v[2],
                        v[3],
                        b.select(hit, q, c(0.0)),
                        b.select(hit, p, v[7]),
                        b.select(hit, v[3], v[8])};
        });
    return {res[6], res[7], res[8]};
}

} // namespace moire::lower
