#include "compiler/lower/Envelope.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/Characters.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

ValueId sampleGap(ir::Builder& b, const PhaseSample& s) {
    // The pixel lies between member n - 1 and n where n is ahead of it (z >= 0), else
    // between n and n + 1. For a phase family both gaps are 1 / |grad index|.
    ValueId ahead = b.emit(ir::Op::Ge, {s.z, b.constF(0.0)});
    ValueId below = b.sub(s.z, s.down), above = b.abs(b.sub(s.up, s.z));
    ValueId usable = b.emit(ir::Op::And, {ahead, b.lt(below, b.constF(0.5 * kNoMember))});
    return b.select(b.emit(ir::Op::And, {usable, b.gt(below, b.constF(0.0))}), below, above);
}

ValueId tapDistance(ir::Builder& b, const PhaseSample& s, ValueId gap, ValueId advance) {
    // One gap is one period of this family here, whatever its pitch does across the frame.
    ValueId shift = b.mul(advance, gap);
    auto from = [&](ValueId k) { return b.abs(b.sub(k, shift)); };
    ValueId d = b.min(from(s.z), b.min(from(s.up), from(s.down)));
    if (s.fold) {
        // Short of the first member, the fold's estimate where it is the larger (as the
        // pattern measures it), for the index advanced by `advance`.
        const FoldSample& f = *s.fold;
        ValueId back = b.mul(advance, f.step);
        ValueId est = b.mul(b.mul(b.sub(f.lo, back), b.sub(f.hi, back)), f.scale);
        ValueId shortOf = b.lt(b.add(f.index, advance), b.constF(f.first));
        d = b.select(shortOf, b.select(f.exact, est, b.max(d, est)), d);
    }
    return b.max(d, s.floor);
}

std::vector<ValueId> sweepDirection(ir::Builder& b, const std::vector<EnvelopeLayer>& layers) {
    std::vector<ValueId> w(layers.size(), b.constF(1.0));
    if (layers.size() != 2) return w;
    const EnvelopeLayer& l1 = layers[0];
    const EnvelopeLayer& l2 = layers[1];
    if (l1.gradX == ir::kNoValue || l2.gradX == ir::kNoValue) return w;
    // eta(1,1) < eta(1,-1) (Eq. 11) is |g1 + g2|^2 < |g1 - g2|^2, that is g1 . g2 < 0.
    ValueId dot = b.add(b.mul(l1.gradX, l2.gradX), b.mul(l1.gradY, l2.gradY));
    w[1] = b.select(b.lt(dot, b.constF(0.0)), b.constF(-1.0), b.constF(1.0));

    // The licence: the nominal pitch ratio's character. It depends on the spacings alone, so
    // it is computed once a frame (the frame program takes what reads no pixel).
    using ir::BuiltValue;
    auto value = [&](ValueId v) { return BuiltValue(b, v); };
    auto pitch = [&](ValueId s) { return b.div(b.constF(1.0), b.max(b.abs(s), b.constF(1e-6))); };
    const ValueId zero = b.constF(0.0);
    PairCharacterT<BuiltValue> licensed = bestPairCharacter<BuiltValue>(
        {value(pitch(l1.spacing)), value(zero)}, {value(pitch(l2.spacing)), value(zero)});
    const ValueId k1 = licensed.k1.id, k2 = licensed.k2.id;
    ValueId deviates = b.emit(Op::And, {b.le(licensed.mu.id, b.constF(kFringeMerit)),
                                        b.emit(Op::Ne, {b.add(k1, k2), zero})});
    // Where it deviates, the pixel's own winner decides (a uniform branch: most stacks have no
    // licence and skip the search).
    std::vector<ValueId> licensedW = b.ifThenElse(
        deviates,
        [&] {
            PairCharacterT<BuiltValue> local = bestPairCharacter<BuiltValue>(
                {value(l1.gradX), value(l1.gradY)}, {value(l2.gradX), value(l2.gradY)});
            // The same character, or its negation (k and -k are one).
            ValueId same = b.emit(Op::Eq, {b.mul(local.k1.id, k2), b.mul(local.k2.id, k1)});
            same = b.emit(Op::And, {same, b.emit(Op::Ne, {local.k1.id, zero})});
            return std::vector<ValueId>{
                b.select(same, b.abs(k2), w[0]),
                b.select(same, b.neg(b.mul(k1, b.emit(Op::Sign, {k2}))), w[1])};
        },
        [&] {
            return std::vector<ValueId>{w[0], w[1]};
        });
    return licensedW;
}

ValueId sumFade(ir::Builder& b, const std::vector<EnvelopeLayer>& layers,
                const std::vector<ValueId>& w) {
    if (layers.size() != 2) return ir::kNoValue;
    const EnvelopeLayer& l1 = layers[0];
    const EnvelopeLayer& l2 = layers[1];
    if (l1.gradX == ir::kNoValue || l2.gradX == ir::kNoValue) return ir::kNoValue;
    if (l1.sample.lattice || l2.sample.lattice) return ir::kNoValue;
    ValueId dot = b.add(b.mul(l1.gradX, l2.gradX), b.mul(l1.gradY, l2.gradY));
    ValueId norms = b.add(b.add(b.mul(l1.gradX, l1.gradX), b.mul(l1.gradY, l1.gradY)),
                          b.add(b.mul(l2.gradX, l2.gradX), b.mul(l2.gradY, l2.gradY)));
    ValueId q = b.div(b.mul(b.constF(2.0), dot), b.max(norms, b.constF(ir::kTiny)));
    ValueId share = b.smoothstep(b.constF(kSumFade), b.constF(-kSumFade), q);
    // Not where a licensed character holds the pixel: w = (1, +-1) otherwise.
    ValueId plain = b.emit(Op::And, {b.emit(Op::Eq, {w[0], b.constF(1.0)}),
                                     b.emit(Op::Eq, {b.abs(w[1]), b.constF(1.0)})});
    return b.select(plain, b.denan(share, b.constF(0.0)), b.constF(0.0));
}

void rankTwoRides(ir::Builder& b, const Character& c, std::vector<EnvelopeLayer>& layers) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    for (int j = 0; j < c.count; ++j) {
        EnvelopeLayer& l = layers.at(static_cast<size_t>(c.layer[static_cast<size_t>(j)]));
        if (l.sample.lattice) continue;
        // The character's term on this layer is k idx; k = +-1 is its own inverse.
        const ValueId k = c.k[static_cast<size_t>(j)];
        const ValueId unit = b.emit(Op::Eq, {b.abs(k), one});
        ValueId u = one, v = zero;
        for (int i = 0; i < c.count; ++i) {
            const EnvelopeLayer& other =
                layers.at(static_cast<size_t>(c.layer[static_cast<size_t>(i)]));
            if (i == j || !other.sample.lattice) continue;
            // k d(idx) + ku s + kv t = 0: idx rides -(ku s + kv t) / k.
            auto [ku, kv] = characterGenerators(b, c, i);
            ValueId pairs =
                b.emit(Op::And, {unit, b.emit(Op::Ne, {c.k[static_cast<size_t>(i)], zero})});
            u = b.select(pairs, b.neg(b.mul(ku, k)), u);
            v = b.select(pairs, b.neg(b.mul(kv, k)), v);
        }
        l.rideU = u;
        l.rideV = v;
    }
}

namespace {

bool hasLattice(const PhaseSample& s) {
    if (s.lattice) return true;
    if (s.morph)
        for (const PhaseSample& m : s.morph->members)
            if (hasLattice(m)) return true;
    return false;
}

// The distance to a layer's nearest member once its index is advanced: by `a` (Eq. 15, with
// the local gap `gap`) for one index, by (du, dv) for a lattice's pair (solved there anew),
// and for a morph across kinds each member by its own, blended as the pattern blends them.
ValueId advancedDistance(ir::Builder& b, const PhaseSample& s, ValueId gap, ValueId a, ValueId du,
                         ValueId dv) {
    if (s.lattice) return s.lattice->at(b, du, dv);
    if (!s.morph) return tapDistance(b, s, gap, a);
    const MorphSample& m = *s.morph;
    std::vector<ValueId> d;
    for (const PhaseSample& member : m.members)
        d.push_back(advancedDistance(b, member, sampleGap(b, member), a, du, dv));
    return b.mix(b.pick(m.from, d), b.pick(m.to, d), m.weight);
}

Ink over(ir::Builder& b, const Ink& acc, const EnvelopeLayer& l, ValueId cov) {
    return inkOver(b, acc, l.color[0], l.color[1], l.color[2], cov);
}

// The mean coverage of a stroke of half-width h over a period s of its index: the antialias
// band is symmetric about h, so the ramp integrates to the hard edge's 2h / s.
ValueId nominalCoverage(ir::Builder& b, const EnvelopeLayer& l) {
    ValueId s = b.max(l.spacing, b.constF(1e-6));
    ValueId duty =
        b.clamp(b.div(b.mul(b.constF(2.0), l.halfWidth), s), b.constF(0.0), b.constF(1.0));
    ValueId op = b.clamp(l.opacity, b.constF(0.0), b.constF(1.0));
    ValueId alpha = b.clamp(l.color[3], b.constF(0.0), b.constF(1.0));
    return b.mul(duty, b.mul(op, alpha));
}

} // namespace

namespace {

// The stack's mean ink swept along `w` (Eq. 13-15), and the pivot it is graded about.
using Swept = SweptInk;

Swept sweptMean(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                const EnvelopeSettings& settings, const std::vector<ValueId>& w) {
    const bool rankTwo = std::any_of(layers.begin(), layers.end(),
                                     [](const EnvelopeLayer& l) { return hasLattice(l.sample); });
    ValueId taps = b.clamp(b.round(settings.taps), b.constF(1.0), b.constF(sema::kMaxEnvelopeTaps));
    // The rank-two sweep covers the unit cell of the index pair (u, v) with a Fibonacci
    // lattice rule: N = F_k taps, tap j at ((j + 1/2) / N, ((j F_(k-1) mod N) + 1/2) / N),
    // which integrates every harmonic of the cell shorter than about 0.9 sqrt(N) exactly.
    // F_k is the Fibonacci number nearest M^2 / 8 (on a log scale), at most F_18 = 2584: 89 at
    // the default M = 24. Each tap re-solves every lattice, so a lattice's envelope costs
    // about N of its pattern's evaluations (docs/views.md).
    ValueId skew = ir::kNoValue;
    if (rankTwo) {
        const double phi = std::numbers::phi, root5 = std::sqrt(5.0);
        ValueId wanted = b.max(b.mul(b.mul(taps, taps), b.constF(0.125)), b.constF(1.0));
        ValueId k = b.round(
            b.div(b.emit(Op::Log, {b.mul(wanted, b.constF(root5))}), b.constF(std::log(phi))));
        k = b.clamp(k, b.constF(2.0), b.constF(kLatticeRuleOrder));
        taps =
            b.round(b.div(b.emit(Op::Exp, {b.mul(k, b.constF(std::log(phi)))}), b.constF(root5)));
        skew = b.round(b.div(taps, b.constF(phi))); // F_(k-1)
    }
    ValueId step = b.div(b.constF(1.0), taps);
    // What each tap reads of a layer, set once per pixel: its stroke's edge (Envelope.h) as
    // the start of the ramp and the ramp's slope, and the ink's strength.
    const size_t n = layers.size();
    struct Edge {
        ValueId gap, start, slope, strength;
    };
    std::vector<Edge> edges;
    for (size_t i = 0; i < layers.size(); ++i) {
        const EnvelopeLayer& l = layers[i];
        // A morph's members measure their own gaps (advancedDistance).
        ValueId gap = l.sample.lattice ? l.sample.lattice->cell
                      : l.sample.morph ? b.constF(1.0)
                                       : sampleGap(b, l.sample);
        // A layer swept |w_i| periods over the taps moves |w_i| times as far each tap; a
        // lattice's taps are spread over its cell, about 1 / sqrt(N) of a step apart.
        ValueId spread = l.sample.lattice ? b.sqrt(step) : step;
        ValueId perTap = b.mul(b.mul(gap, spread), b.abs(w[i]));
        ValueId a = b.max(l.antialias, b.mul(perTap, b.constF(kTapBand)));
        ValueId half = l.halfWidth;
        if (l.sample.lattice) {
            // A band symmetric about a round dot's edge adds ink: a dot of radius h ramped
            // over h +- a holds pi (h^2 + a^2 / 5). The ramp is centred on sqrt(h^2 - a^2 / 5)
            // instead, so the dot holds pi h^2, its true width's ink, whatever the band: the
            // mean does not depend on the band, so not on the pixel's size either. Held
            // under 0.9 h, the ramp stays clear of the dot's centre.
            a = b.min(a, b.mul(l.halfWidth, b.constF(0.9)));
            ValueId r2 = b.sub(b.mul(half, half), b.mul(b.mul(a, a), b.constF(0.2)));
            half = b.select(l.sample.lattice->dots, b.sqrt(b.max(r2, b.constF(0.0))), half);
        } else if (l.sample.morph) {
            // Its members' periods differ; it keeps the pattern's band.
            a = b.min(l.antialias, l.halfWidth);
        } else {
            a = b.min(a, l.halfWidth);
        }
        // On a fold itself the members do not slide by the gap (Eq. 5 has none there): the
        // fold's estimate moves the first member, and its edge keeps the pattern's band.
        if (l.sample.fold) a = b.select(l.sample.fold->exact, l.antialias, a);
        ValueId strength = b.mul(b.clamp(l.opacity, b.constF(0.0), b.constF(1.0)),
                                 b.clamp(l.color[3], b.constF(0.0), b.constF(1.0)));
        edges.push_back({gap, b.sub(half, a),
                         b.div(b.constF(1.0), b.max(b.mul(b.constF(2.0), a), b.constF(ir::kTiny))),
                         strength});
    }
    // A tap's composite is linear in the colours: over the paper P, layer i of coverage c_i
    // and ink k_i, it is P T_0 + sum_i k_i c_i T_i with T_i the product of (1 - c_j) over the
    // layers above i (and T_0 over all). So the loop carries only those scalar weights, the
    // colours are mixed once after it. Carried: the tap j, each layer's coverage, each
    // layer's weight c_i T_i, and the paper's T_0, all summed over the taps.
    std::vector<ValueId> init(2 + 2 * n, b.constF(0.0));
    auto more = [&](std::span<const ValueId> v) { return std::vector<ValueId>{b.lt(v[0], taps)}; };
    std::vector<ValueId> sums = b.loop(init, more, [&](std::span<const ValueId> v) {
        ValueId u = b.mul(b.add(v[0], b.constF(0.5)), step);
        ValueId t = ir::kNoValue; // the second generator's advance, in a rank-two sweep
        if (rankTwo)
            t = b.mul(b.add(b.emit(Op::Mod, {b.mul(v[0], skew), taps}), b.constF(0.5)), step);
        // An advance x w_i, less its whole periods, keeps its sign: within (-1, 1).
        auto advance = [&](ValueId x, size_t i) {
            ValueId a = b.mul(x, w[i]);
            return b.sub(a, b.mul(b.emit(ir::Op::Sign, {a}), b.floor(b.abs(a))));
        };
        std::vector<ValueId> cov(n);
        for (size_t i = 0; i < n; ++i) {
            // A one-index layer rides the generators' advance its character says
            // (rankTwoRides), else the first's.
            const PhaseSample& sample = layers[i].sample;
            ValueId ride = u;
            if (rankTwo && layers[i].rideU != ir::kNoValue)
                ride = b.add(b.mul(layers[i].rideU, u), b.mul(layers[i].rideV, t));
            ValueId du = rankTwo ? advance(u, i) : ir::kNoValue;
            ValueId dv = rankTwo ? advance(t, i) : ir::kNoValue;
            ValueId d = advancedDistance(b, sample, edges[i].gap, advance(ride, i), du, dv);
            // Eq. 4's 1 - smoothstep(h - a, h + a, d), with the ramp's slope set outside.
            ValueId t = b.clamp(b.mul(b.sub(d, edges[i].start), edges[i].slope), b.constF(0.0),
                                b.constF(1.0));
            ValueId ramp = b.mul(b.mul(t, t), b.sub(b.constF(3.0), b.mul(b.constF(2.0), t)));
            cov[i] = b.denan(b.mul(b.sub(b.constF(1.0), ramp), edges[i].strength), b.constF(0.0));
        }
        std::vector<ValueId> next(2 + 2 * n);
        next[0] = b.add(v[0], b.constF(1.0));
        ValueId through = b.constF(1.0); // what the layers above let through
        for (size_t k = n; k-- > 0;) {
            next[1 + k] = b.add(v[1 + k], cov[k]);
            next[1 + n + k] = b.add(v[1 + n + k], b.mul(cov[k], through));
            through = b.mul(through, b.sub(b.constF(1.0), cov[k]));
        }
        next[1 + 2 * n] = b.add(v[1 + 2 * n], through);
        return next;
    });
    auto meanOf = [&](size_t slot) { return b.mul(sums[slot], step); };
    ValueId bare = meanOf(1 + 2 * n);
    Ink mean{b.mul(paper.r, bare), b.mul(paper.g, bare), b.mul(paper.b, bare),
             b.mul(paper.a, bare)};
    for (size_t i = 0; i < n; ++i) {
        ValueId weight = meanOf(1 + n + i);
        const Vals& k = layers[i].color;
        mean = {b.add(mean.r, b.mul(k[0], weight)), b.add(mean.g, b.mul(k[1], weight)),
                b.add(mean.b, b.mul(k[2], weight)), b.add(mean.a, weight)};
    }
    // The pivot: the layers' own mean coverages composited, or a sole layer's nominal ink.
    Ink pivot = paper;
    for (size_t i = 0; i < n; ++i) {
        // A lattice's own mean is its nominal ink: translating it moves no point closer to
        // another.
        const bool nominal = n == 1 && !layers[i].sample.lattice;
        ValueId own = nominal ? nominalCoverage(b, layers[i]) : meanOf(1 + i);
        pivot = over(b, pivot, layers[i], own);
    }
    return {mean, pivot};
}

// The mean graded about the pivot by the envelope's gain (§4.4).
Ink graded(ir::Builder& b, const Swept& s, const EnvelopeSettings& settings) {
    const Ink& mean = s.mean;
    const Ink& pivot = s.pivot;
    auto grade = [&](ValueId p, ValueId m) { return b.add(p, b.mul(settings.gain, b.sub(m, p))); };
    ValueId alpha = b.clamp(grade(pivot.a, mean.a), b.constF(0.0), b.constF(1.0));
    auto channel = [&](ValueId p, ValueId m) { return b.clamp(grade(p, m), b.constF(0.0), alpha); };
    return {channel(pivot.r, mean.r), channel(pivot.g, mean.g), channel(pivot.b, mean.b), alpha};
}

} // namespace

SweptInk sweptInk(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                  const EnvelopeSettings& settings, const std::vector<ValueId>& w) {
    const ValueId fade = sumFade(b, layers, w);
    if (fade == ir::kNoValue) return sweptMean(b, paper, layers, settings, w);
    // Inside the hand-over band both sweeps, their means mixed; elsewhere the one w picks.
    ValueId inBand = b.emit(Op::And, {b.gt(fade, b.constF(0.0)), b.lt(fade, b.constF(1.0))});
    auto values = [](const Swept& s) {
        return std::vector<ValueId>{s.mean.r,  s.mean.g,  s.mean.b,  s.mean.a,
                                    s.pivot.r, s.pivot.g, s.pivot.b, s.pivot.a};
    };
    std::vector<ValueId> mixed = b.ifThenElse(
        inBand,
        [&] {
            std::vector<ValueId> diff =
                values(sweptMean(b, paper, layers, settings, {w[0], b.constF(1.0)}));
            std::vector<ValueId> sum =
                values(sweptMean(b, paper, layers, settings, {w[0], b.constF(-1.0)}));
            for (size_t k = 0; k < diff.size(); ++k) diff[k] = b.mix(diff[k], sum[k], fade);
            return diff;
        },
        [&] { return values(sweptMean(b, paper, layers, settings, w)); });
    return {{mixed[0], mixed[1], mixed[2], mixed[3]}, {mixed[4], mixed[5], mixed[6], mixed[7]}};
}

Ink envelopeInk(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                const EnvelopeSettings& settings) {
    if (layers.empty()) return paper;
    const std::vector<ValueId> w = sweepDirection(b, layers);
    return graded(b, sweptInk(b, paper, layers, settings, w), settings);
}

} // namespace moire::lower
