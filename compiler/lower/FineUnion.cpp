#include "compiler/lower/FineUnion.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LatticeUnion.h"
#include "compiler/lower/MeetingBeat.h"

#include <algorithm>
#include <functional>
#include <span>
#include <utility>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

bool joinsFineUnion(const Footprint& footprint, const PhaseSample& sample) {
    return footprint.grad != ir::kNoValue && footprint.gradX != ir::kNoValue &&
           footprint.edge == ir::kNoValue && sample.z != ir::kNoValue && !sample.lattice &&
           !sample.morph;
}

bool joinsAsStrands(const CrowdEstimate& crowd) {
    return !crowd.strands.empty() && crowd.strandsOn != ir::kNoValue;
}

bool joinsAsLattice(const CrowdEstimate& crowd) {
    return joinsAsStrands(crowd) || crowd.shape.has_value();
}

bool joinsByDistance(const CrowdEstimate& crowd) {
    return crowd.runs.has_value();
}

ValueId transfer(ir::Builder& b, const PixelSides& g, const PixelFootprint& pixel) {
    ir::BuiltValue along(b, b.mul(b.abs(g.u), pixel.size));
    ir::BuiltValue across(b, b.mul(b.abs(g.v), pixel.size));
    return footprintTransfer(along, across).id;
}

ValueId unresolved(ir::Builder& b, const Footprint& f, const PixelFootprint& pixel) {
    ValueId nu = b.mul(f.grad, pixel.size);
    ValueId weight = b.smoothstep(b.constF(kCrowdFrom), b.constF(kCrowdFull), nu);
    if (f.trust != ir::kNoValue) weight = b.mul(weight, f.trust);
    if (!f.first) return weight;
    ValueId lowest = b.sub(f.index, b.mul(nu, b.constF(0.5)));
    return b.select(b.lt(lowest, b.constF(*f.first - 0.5)), b.constF(0.0), weight);
}

ValueId pastFirst(ir::Builder& b, const Footprint& f) {
    if (!f.first) return b.constF(1.0);
    return b.clamp(b.sub(f.index, b.constF(*f.first + 0.5)), b.constF(0.0), b.constF(1.0));
}

Ink pairCorrection(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                   ValueId cov) {
    const ValueId one = b.constF(1.0);
    auto strength = [&](const EnvelopeLayer& l) {
        return inkCoverage(b, one, l.opacity, l.color[3]);
    };
    ValueId scale =
        b.denan(b.mul(b.mul(strength(l1.sweep), strength(l2.sweep)), cov), b.constF(0.0));
    const Vals& k = l1.sweep.color;
    return {b.mul(scale, b.sub(under.r, k[0])), b.mul(scale, b.sub(under.g, k[1])),
            b.mul(scale, b.sub(under.b, k[2])), b.mul(scale, b.sub(under.a, one))};
}

namespace {

// A pair's correlation in closed form: the sweep's mean less its pivot, for two layers whose
// strokes are boxes in their index. Over the sweep layer i covers c_i = k_i A_i (k_i its
// opacity times its alpha, A_i in {0, 1} its stroke at the advanced index); a tap's composite
// over the ink beneath, P, is P (1 - c1)(1 - c2) + K1 c1 (1 - c2) + K2 c2 (K_i = (r, g, b, 1),
// as inkOver lays a layer), whose mean over the sweep is
//   P (1 - k1 a - k2 b + k1 k2 E) + K1 k1 (a - k2 E) + K2 k2 b,
// a = E[A_1] = 2 w1, b = E[A_2] = 2 w2 (w_i the half-width in index units, held within
// [0, 1/2]) and E = E[A_1 A_2] (sweptOverlap). The pivot composites the layers' own means,
// which is the same with a b in place of E; so the correlation is
//   k1 k2 (E - a b) (P - K1)
// per premultiplied channel. The sweep's taps draw each stroke with kTapBand taps' worth of
// antialias ramp, whose overlap differs from the boxes' by a hair at the trapezoid's corners:
// the closed form is the exact box. E is taken as the pixel's mean over the offsets it spans
// (sweptOverlap), so the beat's resolution is the footprint's exactly, harmonic by harmonic,
// and what remains of the weight is the resolved members' share (fineUnion). Where the sum
// beat's fade mixes the two sweeps (sumFade), their overlaps are mixed the same way. A family that
// starts at a member has no members below it, which the periodic strokes count: within one member
// past the first the correlation is faded out (the union of the means stands there).
Ink pairCorrelation(ir::Builder& b, const Ink& under, const std::vector<FineLayer>& run,
                    const std::vector<ValueId>& w, const PixelFootprint& pixel) {
    const FineLayer& l1 = run[0];
    const FineLayer& l2 = run[1];
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const ValueId w1 = b.mul(l1.sweep.halfWidth, l1.footprint.grad);
    const ValueId w2 = b.mul(l2.sweep.halfWidth, l2.footprint.grad);
    const PixelSides g1 = onPixelSides(b, l1.footprint.gradX, l1.footprint.gradY, pixel);
    const PixelSides g2 = onPixelSides(b, l2.footprint.gradX, l2.footprint.gradY, pixel);
    auto overlap = [&](ValueId p, ValueId q) {
        // D = q f1 - p f2 steps |q g1 - p g2 . side| x pixel across each side.
        auto step = [&](ValueId c1, ValueId c2) {
            return b.mul(b.abs(b.sub(b.mul(q, c1), b.mul(p, c2))), pixel.size);
        };
        return sweptOverlap(value(l1.footprint.index), value(l2.footprint.index), value(p),
                            value(q), value(w1), value(w2), value(step(g1.u, g2.u)),
                            value(step(g1.v, g2.v)))
            .id;
    };
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    ValueId e = overlap(w[0], w[1]);
    const ValueId fade = sumFade(b, {l1.sweep, l2.sweep}, w);
    if (fade != ir::kNoValue) {
        // Inside the band w = (1, +-1), and the other sweep is (1, -+1): the sweep mixes the
        // difference's by 1 - fade and the sum's by fade, so w's own overlap takes the other's
        // by fade (w the difference) or by 1 - fade (w the sum). Built behind a branch: the
        // band is narrow.
        ValueId inBand = b.emit(Op::And, {b.gt(fade, zero), b.lt(fade, one)});
        e = b.ifThenElse(
            inBand,
            [&] {
                ValueId other = overlap(w[0], b.neg(w[1]));
                ValueId share = b.select(b.gt(w[1], zero), fade, b.sub(one, fade));
                return std::vector<ValueId>{b.mix(e, other, share)};
            },
            [&] { return std::vector<ValueId>{e}; })[0];
    }
    auto duty = [&](ValueId half) { return b.clamp(b.mul(b.constF(2.0), half), zero, one); };
    ValueId cov = b.sub(e, b.mul(duty(w1), duty(w2)));
    for (const FineLayer* l : {&l1, &l2}) cov = b.mul(cov, pastFirst(b, l->footprint));
    return pairCorrection(b, under, l1, l2, cov);
}

// Two layers of lines given by their distance that both run three ways: the meeting points'
// term the pairs taken as independent miss (MeetingBeat.h), where each layer's third way
// holds lines and the three pairs are one to one, faded as the least of the pairs' weights.
// Behind a branch: a layer of one or two ways pays a handful of instructions.
ValueId meetingPoints(ir::Builder& b, const FineLayer& l1, const FineLayer& l2,
                      const MeetingSide& first, const MeetingSide& second, const ValueId blanks[2],
                      const std::vector<ValueId>& partners, const std::vector<ValueId>& weights) {
    const ValueId zero = b.constF(0.0);
    auto threeWays = [&](const FineLayer& l) {
        return b.emit(Op::And, {b.gt(l.twoWays, zero),
                                b.emit(Op::And, {b.gt(l.strands[2].footprint.trust, zero),
                                                 b.gt(l.strands[2].mean, zero)})});
    };
    ValueId on = b.emit(Op::And, {threeWays(l1), threeWays(l2)});
    for (size_t i = 0; i < 3; ++i)
        on = b.emit(Op::And, {on, b.emit(Op::Ne, {partners[i], partners[(i + 1) % 3]})});
    ValueId weight = b.min(b.min(weights[0], weights[1]), weights[2]);
    return b.ifThenElse(
        on,
        [&] {
            const ValueId cov = meetingCovariance(b, first, second, blanks[0], blanks[1]);
            return std::vector<ValueId>{
                b.denan(b.mul(b.clamp(weight, zero, b.constF(1.0)), cov), zero)};
        },
        [&] { return std::vector<ValueId>{zero}; })[0];
}

// The beats a strand pair is read by, (p, q) for D = q f_x - p f_y: the lines' own (1, +-1),
// and where a line of one layer stands about twice as fine as its partner's, the coarser
// one's second harmonic with the finer one's first, (1, +-2) and (2, +-1). The slowest at
// the pixel is the pair's. The meeting points' term reads the first alone.
constexpr std::pair<double, double> kFirstHarmonics[] = {{1, 1}, {1, -1}};
constexpr std::pair<double, double> kHarmonicPairs[] = {{1, 1},  {1, -1}, {1, 2},
                                                        {1, -2}, {2, 1},  {2, -1}};
using Beats = std::span<const std::pair<double, double>>;

// The correlation of a pair with a lattice, by its strands. Each layer's ink is the union of
// its strands laid as independent, c = 1 - prod(1 - x_i) (x_i a strand's periodic stroke; a
// phase family is one strand). Lines of different directions are independent over a fine
// pixel, but a line of the first layer and the second's line nearly parallel to it are not:
// their strokes beat, as a pair of phase families does (pairCorrelation). So each strand x of
// the first layer is paired with the strand y of the second, and the sense s = +-1, whose
// beat D = s f_x - f_y runs slowest (the least |s grad f_x - grad f_y|; or a second
// harmonic's beat, kHarmonicPairs), and their covariance over the pixel is the pair's closed
// form, cov_xy = weight (E - a b) with the pair's weight 1 - T_x T_y / T_D. With the pairs
// independent of one another,
//   E[(1 - c1)(1 - c2)] = prod_all (1 - m) prod_pairs (1 + cov_xy / ((1 - m_x)(1 - m_y)))
// (m the strands' footprint means), so the layers' covariance is prod_all (1 - m) times
// (prod_pairs (1 + ratio) - 1), and it enters the composite as a pair's does:
// k1 k2 cov (P - K1). Exact where each line has one partner and the lines of one layer cross
// (the square lattice's); for the triangle lattice's three, which meet at its points, as its
// own mean, to first order, and for two layers of lines given by their distance that both run
// three ways, with the harmonics of their meeting points (meetingPoints, MeetingBeat.h). A
// strand the greedy choice leaves unpaired counts its mean alone.
Ink strandCorrelation(ir::Builder& b, const Ink& under, const FineLayer& l1, const FineLayer& l2,
                      const PixelFootprint& pixel) {
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    if (l1.strands.empty() || l2.strands.empty()) return {zero, zero, zero, zero}; // the honeycomb
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    // A strand as the pair reads it: its gradient along the pixel's sides, its transfer, how
    // far it is past resolved, and its half-width in index units.
    struct Seen {
        const Strand* strand;
        PixelSides g;
        ValueId transfer, unresolved, half;
    };
    auto seen = [&](const FineLayer& l) {
        std::vector<Seen> out;
        for (const Strand& s : l.strands) {
            const PixelSides g = onPixelSides(b, s.footprint.gradX, s.footprint.gradY, pixel);
            out.push_back({&s, g, transfer(b, g, pixel), unresolved(b, s.footprint, pixel),
                           b.mul(l.sweep.halfWidth, s.footprint.grad)});
        }
        return out;
    };
    const std::vector<Seen> first = seen(l1), second = seen(l2);
    auto duty = [&](ValueId half) { return b.clamp(b.mul(b.constF(2.0), half), zero, one); };
    ValueId blank = one, factor = one;
    ValueId blanks[2] = {one, one};
    for (int j = 0; j < 2; ++j)
        for (const Seen& x : j == 0 ? first : second) {
            blank = b.mul(blank, b.sub(one, x.strand->mean));
            blanks[j] = b.mul(blanks[j], b.sub(one, x.strand->mean));
        }
    // Two layers given by their distance, three strands each: each line of the first layer
    // with its partner, for the meeting points' term below.
    const bool meeting = l1.byDistance && l2.byDistance && first.size() == 3 && second.size() == 3;
    MeetingSide meets, seconds;
    std::vector<ValueId> partners, weights;
    for (const Seen& x : first) {
        // The partner: carried through selects, the candidates tried in turn.
        ValueId rate = b.constF(1e30), sense = one, du = zero, dv = zero;
        ValueId index = zero, tr = zero, un = zero, half = zero, mean = zero, past = one;
        ValueId slot = zero, times = one;
        for (size_t j = 0; j < second.size(); ++j)
            for (const auto& [p, q] : meeting ? Beats(kFirstHarmonics) : Beats(kHarmonicPairs)) {
                const Seen& y = second[j];
                // The beat D = q f_x - p f_y steps q grad f_x - p grad f_y.
                ValueId cu = b.sub(b.mul(b.constF(q), x.g.u), b.mul(b.constF(p), y.g.u));
                ValueId cv = b.sub(b.mul(b.constF(q), x.g.v), b.mul(b.constF(p), y.g.v));
                ValueId r = b.add(b.mul(cu, cu), b.mul(cv, cv));
                ValueId better = b.lt(r, rate);
                auto pick = [&](ValueId mine, ValueId held) {
                    return b.select(better, mine, held);
                };
                ValueId yPast = pastFirst(b, y.strand->footprint);
                rate = pick(r, rate);
                sense = pick(b.constF(q), sense);
                times = pick(b.constF(p), times);
                du = pick(cu, du);
                dv = pick(cv, dv);
                index = pick(y.strand->footprint.index, index);
                tr = pick(y.transfer, tr);
                un = pick(y.unresolved, un);
                half = pick(y.half, half);
                mean = pick(y.strand->mean, mean);
                past = pick(yPast, past);
                slot = pick(b.constF(double(j)), slot);
            }
        ValueId along = b.mul(b.abs(du), pixel.size), across = b.mul(b.abs(dv), pixel.size);
        ValueId e =
            sweptOverlap(value(x.strand->footprint.index), value(index), value(times), value(sense),
                         value(x.half), value(half), value(along), value(across))
                .id;
        ValueId beat = footprintTransfer(value(along), value(across)).id;
        ValueId weight =
            b.mul(b.min(x.unresolved, un),
                  b.clamp(b.sub(one, b.div(b.mul(x.transfer, tr), b.max(beat, b.constF(1e-6)))),
                          zero, one));
        past = b.mul(past, pastFirst(b, x.strand->footprint));
        ValueId cov = b.mul(b.mul(weight, past), b.sub(e, b.mul(duty(x.half), duty(half))));
        ValueId pair = b.mul(b.sub(one, x.strand->mean), b.sub(one, mean));
        ValueId ratio = b.max(b.div(cov, b.max(pair, b.constF(1e-12))), b.constF(-1.0));
        factor = b.mul(factor, b.add(one, b.denan(ratio, zero)));
        if (meeting) {
            meets.lines[partners.size()] = {x.strand->footprint.index,
                                            b.mul(x.g.u, pixel.size),
                                            b.mul(x.g.v, pixel.size),
                                            x.half,
                                            index,
                                            half,
                                            sense};
            partners.push_back(slot);
            weights.push_back(b.mul(weight, past));
        }
    }
    ValueId cov = b.mul(blank, b.sub(factor, one));
    if (meeting) {
        for (size_t k = 0; k < 3; ++k)
            seconds.lines[k] = {second[k].strand->footprint.index,
                                b.mul(second[k].g.u, pixel.size),
                                b.mul(second[k].g.v, pixel.size),
                                second[k].half,
                                zero,
                                zero,
                                one};
        cov = b.add(cov, meetingPoints(b, l1, l2, meets, seconds, blanks, partners, weights));
    }
    for (const FineLayer* l : {&l1, &l2})
        if (l->strandsOn != ir::kNoValue) cov = b.select(l->strandsOn, cov, zero);
    return pairCorrection(b, under, l1, l2, cov);
}

// A pair with a lattice: its strands' correlation (strandCorrelation), or its shape's
// (LatticeUnion.h: two dot screens, a screen with lines, two lattices of one kind by their
// cells), computed behind a branch where each layer's strands, dots or cells are past resolved.
Ink strandUnion(ir::Builder& b, const Ink& under, const Ink& independent,
                const std::vector<FineLayer>& run, const PixelFootprint& pixel) {
    const ValueId zero = b.constF(0.0);
    ValueId engaged = b.constF(1.0);
    for (const FineLayer& l : run) {
        ValueId most = zero;
        for (const Strand& s : l.strands) most = b.max(most, unresolved(b, s.footprint, pixel));
        if (l.strandsOn != ir::kNoValue)
            most = b.select(l.strandsOn, most, zero);
        else if (l.lattice())
            most = zero;
        if (l.shape) {
            // Its dots, and its edges where its cells are laid on another's (cellCorrelation).
            const ValueId crowded = dotsCrowded(b, *l.shape, pixel);
            most = b.max(most,
                         l.shape->cells.empty() ? b.select(l.shape->dots, crowded, zero) : crowded);
        }
        engaged = b.min(engaged, most);
    }
    auto ink = [&](const Ink& corr) {
        const Ink sum = addCorrection(b, independent, corr, b.constF(1.0));
        return std::vector<ValueId>{sum.r, sum.g, sum.b, sum.a};
    };
    // Which layer draws dots is a uniform (the lattice's `edges`): one correlation is built
    // per pixel, by branches on it. Both: the two screens' (LatticeUnion.h); one: the screen's
    // with the other's lines; neither: two lattices of one kind by their cells, else the
    // strands'.
    auto byDots = [&] {
        const bool cells = run[0].shape && run[1].shape && sameCells(*run[0].shape, *run[1].shape);
        auto strands = [&] {
            if (cells) return ink(cellCorrelation(b, under, run[0], run[1], pixel));
            // A honeycomb's edges with the other layer's lines, by its hexagons' paper.
            for (bool first : {true, false}) {
                const FineLayer& hex = first ? run[0] : run[1];
                const FineLayer& other = first ? run[1] : run[0];
                if (hex.shape && honeycombCells(*hex.shape) && !other.strands.empty())
                    return ink(hexLineCorrelation(b, under, run[0], run[1], first, pixel));
            }
            return ink(strandCorrelation(b, under, run[0], run[1], pixel));
        };
        auto onlyOne = [&](bool first, const std::function<std::vector<ValueId>()>& otherwise) {
            const FineLayer& dots = first ? run[0] : run[1];
            const FineLayer& other = first ? run[1] : run[0];
            if (!dots.shape) return otherwise();
            return b.ifThenElse(
                dots.shape->dots,
                [&] {
                    // With a honeycomb's edges, by its hexagons' paper; else by the lines.
                    if (other.shape && honeycombCells(*other.shape))
                        return ink(hexDotCorrelation(b, under, run[0], run[1], !first, pixel));
                    return ink(dotLineCorrelation(b, under, run[0], run[1], first, pixel));
                },
                otherwise);
        };
        auto mixed = [&] { return onlyOne(true, [&] { return onlyOne(false, strands); }); };
        if (!run[0].shape || !run[1].shape) return mixed();
        return b.ifThenElse(
            b.emit(Op::And, {run[0].shape->dots, run[1].shape->dots}),
            [&] { return ink(dotCorrelation(b, under, run[0], run[1], pixel)); }, mixed);
    };
    std::vector<ValueId> out = b.ifThenElse(b.gt(engaged, zero), byDots, [&] {
        return std::vector<ValueId>{independent.r, independent.g, independent.b, independent.a};
    });
    return {out[0], out[1], out[2], out[3]};
}

} // namespace

// The weight of the correlation. For two layers of inks c1(f1), c2(f2), take their
// fundamentals, c_i = a_i + b_i cos(2 pi f_i). Over the pixel the union 1 - (1 - c1)(1 - c2)
// departs from the union of the pixel's means by the covariance of c1 and c2 over the pixel,
// whose leading term is
//   (b1 b2 / 2) cos(2 pi D) (T_D - T_1 T_2)
// with D = f1 - f2, T_D the footprint's transfer (footprintTransfer) of D, T_i that of f_i.
// The sweep's mean less its pivot is (b1 b2 / 2) cos(2 pi D) and the rest of Phi(D)'s
// harmonics, so it is added with the weight T_D - T_1 T_2: 0 where the members are resolved
// (T_i -> 1, and T_D too), T_D where they are not (T_i -> 0), which is 1 while the beat is
// resolved and falls to 0 where a pixel spans a whole period of it, where the union of the
// means is right. D is the sweep's invariant: a layer advances by w_i per tap, so D =
// w_j f_i - w_i f_j for each pair; with more than two layers the consecutive pairs span the
// invariants, and the weight takes the least T_D and the greatest T_i T_j among them. It is
// also held to the least hand-over weight of the run's layers (`unresolved`), so that the
// point rule's floored strokes, which the fundamentals above do not describe, are left as
// drawn. A pair's closed form (pairCorrelation) is E's mean over the pixel, which carries
// T_D (for each harmonic its own), so it takes the weight 1 - T_1 T_2 / T_D: the same for the
// fundamental. With T_D = 0 and T_1 T_2 = 0 (members and beat unresolved) that weight is 1,
// and E's mean over whole beats is a b, the independent stack's.
namespace {

// A run of phase families (and families given by their distance, by their index), as above.
Ink phaseUnion(ir::Builder& b, const Ink& under, const Ink& independent,
               const std::vector<FineLayer>& run, const PixelFootprint& pixel) {
    std::vector<EnvelopeLayer> layers;
    for (const FineLayer& l : run) layers.push_back(l.sweep);
    ValueId engaged = b.constF(1.0);
    for (const FineLayer& l : run) engaged = b.min(engaged, unresolved(b, l.footprint, pixel));
    const std::vector<ValueId> w = sweepDirection(b, layers);
    std::vector<ValueId> out = b.ifThenElse(
        b.gt(engaged, b.constF(0.0)),
        [&] {
            ValueId beat = b.constF(1.0), apart = b.constF(0.0);
            std::vector<ValueId> own;
            for (const FineLayer& l : run)
                own.push_back(transfer(
                    b, onPixelSides(b, l.footprint.gradX, l.footprint.gradY, pixel), pixel));
            for (size_t i = 0; i + 1 < run.size(); ++i) {
                const Footprint& fi = run[i].footprint;
                const Footprint& fj = run[i + 1].footprint;
                // grad D = w_j grad f_i - w_i grad f_j
                ValueId dx = b.sub(b.mul(w[i + 1], fi.gradX), b.mul(w[i], fj.gradX));
                ValueId dy = b.sub(b.mul(w[i + 1], fi.gradY), b.mul(w[i], fj.gradY));
                beat = b.min(beat, transfer(b, onPixelSides(b, dx, dy, pixel), pixel));
                apart = b.max(apart, b.mul(own[i], own[i + 1]));
            }
            // A pair's overlap in closed form is the pixel's mean over the beat already
            // (pairCorrelation), T_D's share of it: it takes 1 - T_1 T_2 / T_D, the same
            // weight for the fundamental.
            ValueId weight =
                run.size() == 2
                    ? b.mul(engaged,
                            b.clamp(b.sub(b.constF(1.0), b.div(apart, b.max(beat, b.constF(1e-6)))),
                                    b.constF(0.0), b.constF(1.0)))
                    : b.mul(engaged, b.clamp(b.sub(beat, apart), b.constF(0.0), b.constF(1.0)));
            weight = b.denan(weight, b.constF(0.0));
            // Added only where the weight is above 0.
            return b.ifThenElse(
                b.gt(weight, b.constF(0.0)),
                [&] {
                    // A pair in closed form; a longer run by the sweep (a choice of the run's
                    // structure, made once here).
                    Ink corr;
                    if (run.size() == 2) {
                        corr = pairCorrelation(b, under, run, w, pixel);
                    } else {
                        EnvelopeSettings settings{b.constF(1.0), b.constF(kUnionTaps)};
                        SweptInk swept = sweptInk(b, under, layers, settings, w);
                        corr = {
                            b.sub(swept.mean.r, swept.pivot.r), b.sub(swept.mean.g, swept.pivot.g),
                            b.sub(swept.mean.b, swept.pivot.b), b.sub(swept.mean.a, swept.pivot.a)};
                    }
                    const Ink out = addCorrection(b, independent, corr, weight);
                    return std::vector<ValueId>{out.r, out.g, out.b, out.a};
                },
                [&] {
                    return std::vector<ValueId>{independent.r, independent.g, independent.b,
                                                independent.a};
                });
        },
        [&] {
            return std::vector<ValueId>{independent.r, independent.g, independent.b, independent.a};
        });
    return {out[0], out[1], out[2], out[3]};
}

} // namespace

Ink fineUnion(ir::Builder& b, const Ink& under, const Ink& independent,
              const std::vector<FineLayer>& run, const PixelFootprint& pixel) {
    if (run.size() < 2) return independent;
    if (run[0].lattice() || run[1].lattice()) return strandUnion(b, under, independent, run, pixel);
    // A grid given by its distance, where its members run two ways, beats by its two ways'
    // strands, as a lattice's lines do, and dots given by their distance, where they are read
    // as a screen, by its shape, as a lattice's dots do; elsewhere by its index, as a phase
    // family.
    ValueId asLattice = ir::kNoValue;
    auto either = [&](ValueId flag) {
        asLattice = asLattice == ir::kNoValue ? flag : b.emit(Op::Or, {asLattice, flag});
    };
    for (const FineLayer& l : run) {
        if (l.twoWays != ir::kNoValue) either(b.gt(l.twoWays, b.constF(0.0)));
        if (l.byDistance && l.shape) either(l.shape->dots);
    }
    if (asLattice == ir::kNoValue) return phaseUnion(b, under, independent, run, pixel);
    auto values = [](const Ink& i) { return std::vector<ValueId>{i.r, i.g, i.b, i.a}; };
    const std::vector<ValueId> out = b.ifThenElse(
        asLattice, [&] { return values(strandUnion(b, under, independent, run, pixel)); },
        [&] { return values(phaseUnion(b, under, independent, run, pixel)); });
    return {out[0], out[1], out[2], out[3]};
}

} // namespace moire::lower
