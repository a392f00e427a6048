#include "compiler/lower/MorphBeat.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/FineUnion.h"

#include <cmath>
#include <numbers>
#include <span>
#include <tuple>
#include <utility>

namespace moire::lower {

using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

namespace {

// A family's lines over a crowded pixel, up to kWays of them: a phase family's one (its
// footprint), a square or triangle lattice's edges its strands where it draws them
// (CrowdEstimate::strands). Each as its index, the index's gradient along the pixel's sides in
// periods a pixel (gu, gv) and its length g, and `on`, 1 where the family draws the line and
// 0 in a slot it leaves empty (a lattice's points, a family without an index, the pencil,
// whose index does not reach its open disc).
constexpr size_t kWays = 3;
struct Way {
    ValueId index, gu, gv, g, on;
};
std::vector<Way> waysOf(ir::Builder& b, const LayerFields& f, const PixelFootprint& pixel) {
    auto c = [&](double v) { return b.constF(v); };
    std::vector<Way> out;
    auto add = [&](const Footprint& fp, ValueId on) {
        const PixelSides s = onPixelSides(b, fp.gradX, fp.gradY, pixel);
        const ValueId gu = b.mul(s.u, pixel.size), gv = b.mul(s.v, pixel.size);
        out.push_back({fp.index, gu, gv, b.hypot(gu, gv), on});
    };
    const Footprint& fp = f.footprint;
    if (joinsAsStrands(f.crowd) && f.crowd.strands.size() <= kWays) {
        for (const Footprint& st : f.crowd.strands)
            add(st, b.select(f.crowd.strandsOn, c(1.0), c(0.0)));
    } else if (fp.grad != ir::kNoValue && fp.gradX != ir::kNoValue && fp.edge == ir::kNoValue) {
        add(fp, c(1.0));
    }
    while (out.size() < kWays) out.push_back({c(0.0), c(0.0), c(0.0), c(0.0), c(0.0)});
    return out;
}

// The pair. Of every line i of the first family and j of the second, and each sense
// s = +-1 in which they may run together, the pair whose beat E = f_i - s f_j the pixel
// attenuates least: the transfer of its fundamental (footprintTransfer of E's steps across the
// pixel's sides, beat = grad f_i - s grad f_j), none where that is under `kLeast`.
//
// The chance at an offset. Over a pixel where f_i runs over many periods and E stands still,
// the two lines' distances are t1 = tri(u) / g_i and t2 = tri(u - E) / g_j at f_i = u, u
// uniform (tri the distance to the nearest whole number, g the index's periods a pixel,
// distances in pixels), and each family's other lines stand at R1, R2, independent of each
// other, distributed as their share within r given the pair's line's place (`rest` below: a
// square lattice's other line 2 r g, a triangle lattice's two met on the pair's line).
// With a = 1 - w, the pixel's ink at E is
//   C(E) = integral over u of P(a min(t1, R1) + w min(t2, R2) < h),
// and given t1 and t2, with Q(r) = P(a min(t1, R1) + w r < h), which is 1 where
// a t1 + w r < h and F1((h - w r) / a) beyond,
//   P = (1 - F2(t2)) Q(t2) + integral over r in [0, t2) of Q(r) dF2(r),
// the integral in kRestTaps steps of F2, taken only where the second family has other lines.
// F1 is read at (h - w r) / a, steep where a is small: the family of the larger weight goes
// first (the pair's roles and weights change places, and E -> -E). u is taken at kBeatSamples
// points, Q's step at a t1 + w r = h as a ramp of one point's width along its slope in u (so
// that where the step falls between two points counts, not only which points it separates),
// and F1 held at t1 across the ramp's inner half so that the two parts of Q meet there. The
// loop over the points is held twice, with the first family's other lines and without, and
// the kernel takes the one the first family needs.
//
// Over the pixel. E runs across the pixel with the beat: the pixel holds the mean of
// C(E + beat . x), which keeps each harmonic k of C (periodic in E) attenuated by the pixel's
// transfer at k times the beat, A_k. C is taken at M = kOffsets offsets a period apart,
// C_m = C(E + m / M) (u's points shifted by m / M of a step from one offset to the next), and
// the harmonics' sum at E is sum_m C_m K_m, with
//   K_m = (1 + 2 sum_{0<k<M/2} A_k cos(2 pi k m / M) + A_{M/2} cos(pi m)) / M:
// C(E) itself where the beat stands still (every A_k = 1: K is 1 at m = 0 and 0 elsewhere),
// and the mean of the C_m, which is this model's chance with the families independent, where
// the pixel spans whole periods of the beat (A_k = 0 for k > 0). What the pixel holds beyond
// independence is sum_m C_m (K_m - 1 / M): added to `independent`, whose own reading of each
// family (a lattice's share where its lines meet at its points, the box filter's ripple)
// stands, and which is the beat's limit where it is fast, and at either end of a change
// (where D is one family's distance, C does not depend on E, and the sum is 0).
//
// Behind a branch: where every pair beats faster than the pixel, nothing is added. Nor while
// the morph holds a family (w within kHeld of 0 or 1, morphBeat below), most of its time.
constexpr int kBeatSamples = 12;
constexpr int kOffsets = 8;
constexpr int kRestTaps = 3;
constexpr double kLeast = 1e-3;
constexpr double kHeld = 1e-4;
ValueId beatOf(ir::Builder& b, const std::vector<Way>& from, const std::vector<Way>& to, ValueId w,
               ValueId h, ValueId independent) {
    auto c = [&](double v) { return b.constF(v); };
    const ValueId zero = c(0.0), one = c(1.0);
    // The pair whose beat the pixel attenuates least.
    const ValueId least = c(kLeast);
    ValueId best = least, offset = zero, skipFrom = c(-1.0), skipTo = c(-1.0), g1 = one, g2 = one,
            beatU = zero, beatV = zero;
    for (size_t i = 0; i < kWays; ++i)
        for (size_t j = 0; j < kWays; ++j)
            for (double s : {1.0, -1.0}) {
                const ValueId bu = b.sub(from[i].gu, b.mul(c(s), to[j].gu));
                const ValueId bv = b.sub(from[i].gv, b.mul(c(s), to[j].gv));
                ir::BuiltValue along(b, b.abs(bu)), across(b, b.abs(bv));
                const ValueId t =
                    b.mul(footprintTransfer(along, across).id, b.mul(from[i].on, to[j].on));
                const ValueId better = b.gt(t, best);
                best = b.select(better, t, best);
                offset = b.select(better, b.sub(from[i].index, b.mul(c(s), to[j].index)), offset);
                skipFrom = b.select(better, c(double(i)), skipFrom);
                skipTo = b.select(better, c(double(j)), skipTo);
                g1 = b.select(better, from[i].g, g1);
                g2 = b.select(better, to[j].g, g2);
                beatU = b.select(better, bu, beatU);
                beatV = b.select(better, bv, beatV);
            }
    // The family of the larger weight goes first (above: "The chance at an offset").
    const ValueId swap = b.gt(w, c(0.5));
    auto swapped = [&](ValueId x, ValueId y) {
        return std::pair{b.select(swap, y, x), b.select(swap, x, y)};
    };
    const auto [skip1, skip2] = swapped(skipFrom, skipTo);
    const auto [a, wb] = swapped(b.sub(one, w), w);
    std::tie(g1, g2) = swapped(g1, g2);
    offset = b.select(swap, b.neg(offset), offset);
    // Each family's other lines (the pair's own slot off), and whether it has any: only their
    // periods a pixel and whether each is drawn are read.
    struct Other {
        ValueId g, on;
    };
    std::vector<Other> first(kWays), second(kWays);
    ValueId firstHas = zero, secondHas = zero;
    for (size_t q = 0; q < kWays; ++q) {
        std::tie(first[q].g, second[q].g) = swapped(from[q].g, to[q].g);
        std::tie(first[q].on, second[q].on) = swapped(from[q].on, to[q].on);
        auto notPair = [&](ValueId skip) {
            return b.select(b.emit(Op::Eq, {skip, c(double(q))}), zero, one);
        };
        first[q].on = b.mul(first[q].on, notPair(skip1));
        second[q].on = b.mul(second[q].on, notPair(skip2));
        firstHas = b.add(firstHas, first[q].on);
        secondHas = b.add(secondHas, second[q].on);
    }
    // A family's other lines: the chance that the nearest is within r, where the pair's own
    // line of it is `residual` periods off. A phase family has none, a square lattice one
    // (within r of it: 2 r g of its period). A triangle lattice has two, whose lines meet the
    // pair's at its points: along a line of the pair's strand its other two strands' lines
    // sit a period apart each, the one set `residual` of a period off the other (the strands'
    // indices are u, v and u + v), so within r of them is the union of intervals 2 r g wide
    // about each, over a period of the line; laid as independent, the two counted their
    // overlap as if spread over the plane. Read from their periods a pixel summed and the
    // least of them, taken once.
    struct Rest {
        ValueId has, sum, least;
    };
    auto restOf = [&](const std::vector<Other>& ways, ValueId has) {
        ValueId sum = zero, least = c(1e30);
        for (size_t q = 0; q < kWays; ++q) {
            sum = b.add(sum, b.mul(ways[q].on, ways[q].g));
            least = b.min(least, b.select(b.gt(ways[q].on, zero), ways[q].g, c(1e30)));
        }
        return Rest{b.gt(has, c(1.5)), sum, least};
    };
    const Rest firstRest = restOf(first, firstHas), secondRest = restOf(second, secondHas);
    auto rest = [&](const Rest& ways, ValueId r, ValueId residual) {
        const ValueId reach = b.mul(b.max(r, zero), c(2.0));
        const ValueId width = b.mul(reach, ways.sum);
        // The two sets' intervals overlap across each gap between them, |residual| and its
        // complement, by as much as their half-widths pass the gap, at most the narrower's
        // width.
        const ValueId gap = b.abs(residual);
        auto overlap = [&](ValueId apart) {
            return b.clamp(b.sub(b.mul(width, c(0.5)), apart), zero, b.mul(reach, ways.least));
        };
        const ValueId met = b.sub(width, b.add(overlap(gap), overlap(b.sub(one, gap))));
        return b.min(b.select(ways.has, met, width), one);
    };
    const ValueId wFloor = b.max(wb, c(1e-6)); // a >= 1/2
    g1 = b.max(g1, c(1e-9));
    g2 = b.max(g2, c(1e-9));
    auto tri = [&](ValueId u) { return b.sub(u, b.round(u)); }; // signed: its sign is the slope's
    // P at f_i = u and offset e: the chance that the blend is within the stroke, given the
    // pair's distances, over each family's other lines.
    // `firstOthers`: whether the first family's other lines are read.
    auto chanceAt = [&](ValueId u, ValueId e, bool firstOthers) {
        const ValueId r1 = tri(u), r2 = tri(b.sub(u, e));
        const ValueId t1 = b.div(b.abs(r1), g1), t2 = b.div(b.abs(r2), g2);
        auto sign = [&](ValueId x) { return b.select(b.lt(x, zero), c(-1.0), one); };
        const ValueId step =
            b.max(b.mul(b.abs(b.add(b.div(b.mul(a, sign(r1)), g1), b.div(b.mul(wb, sign(r2)), g2))),
                        c(1.0 / kBeatSamples)),
                  c(1e-9));
        // Q(r), the chance that the blend is within the stroke where the second family's
        // distance is r: 1 where w1 t1 + w2 r < h, a ramp of one point's width along u (its
        // slope, `step` a point), else the first family's other lines within
        // (h - w2 r) / w1, held at t1 across the ramp's inner half so that the two meet.
        auto inside = [&](ValueId r) {
            return b.clamp(b.add(b.div(b.sub(h, b.add(b.mul(a, t1), b.mul(wb, r))), step), c(0.5)),
                           zero, one);
        };
        auto within = [&](ValueId r) {
            const ValueId in = inside(r);
            if (!firstOthers) return in;
            const ValueId other = rest(firstRest, b.min(b.div(b.sub(h, b.mul(wb, r)), a), t1), r1);
            return b.add(in, b.mul(b.sub(one, in), other));
        };
        // The second family's distance, min(t2, R2): t2 where its other lines are further,
        // else R2, in kRestTaps steps of their share below t2 (or below h / w2, past which
        // nothing is within the stroke), where it has other lines.
        return b.ifThenElse(
            b.gt(secondHas, zero),
            [&] {
                ValueId p = b.mul(b.sub(one, rest(secondRest, t2, r2)), within(t2));
                const ValueId top = b.min(t2, b.div(h, wFloor));
                ValueId below = zero;
                for (int m = 1; m <= kRestTaps; ++m) {
                    const ValueId at = rest(secondRest, b.mul(top, c(double(m) / kRestTaps)), r2);
                    p = b.add(
                        p, b.mul(b.sub(at, below), within(b.mul(top, c((m - 0.5) / kRestTaps)))));
                    below = at;
                }
                return Vals{p};
            },
            [&] { return Vals{within(t2)}; })[0];
    };
    // The C_m, weighed by K_m - 1 / M, where any pair beats slowly enough.
    const ValueId beat = b.ifThenElse(
        b.gt(best, least),
        [&] {
            ValueId harmonic[kOffsets / 2 + 1];
            for (int k = 1; k <= kOffsets / 2; ++k) {
                ir::BuiltValue along(b, b.mul(b.abs(beatU), c(k)));
                ir::BuiltValue across(b, b.mul(b.abs(beatV), c(k)));
                harmonic[k] = footprintTransfer(along, across).id;
            }
            Vals kernel;
            for (int m = 0; m < kOffsets; ++m) {
                ValueId sum = zero;
                for (int k = 1; k <= kOffsets / 2; ++k)
                    sum = b.add(sum, b.mul(harmonic[k],
                                           c((k < kOffsets / 2 ? 2.0 : 1.0) *
                                             std::cos(2.0 * std::numbers::pi * k * m / kOffsets))));
                kernel.push_back(b.mul(sum, c(1.0 / (kOffsets * kBeatSamples))));
            }
            auto sum = [&](bool firstOthers) {
                return b.loop(
                    {zero, zero},
                    [&](std::span<const ValueId> v) {
                        return Vals{b.lt(v[0], c(kOffsets * kBeatSamples))};
                    },
                    [&](std::span<const ValueId> v) {
                        const ValueId m = b.floor(b.mul(v[0], c(1.0 / kBeatSamples)));
                        const ValueId j = b.sub(v[0], b.mul(m, c(kBeatSamples)));
                        const ValueId u =
                            b.mul(b.add(j, b.add(c(0.5), b.mul(m, c(1.0 / kOffsets)))),
                                  c(1.0 / kBeatSamples));
                        const ValueId e = b.add(offset, b.mul(m, c(1.0 / kOffsets)));
                        ValueId weight = kernel.back();
                        for (int q = kOffsets - 1; q-- > 0;)
                            weight = b.select(b.lt(m, c(q + 0.5)), kernel[q], weight);
                        return Vals{b.add(v[0], one),
                                    b.add(v[1], b.mul(weight, chanceAt(u, e, firstOthers)))};
                    })[1];
            };
            return b.ifThenElse(
                b.gt(firstHas, zero), [&] { return Vals{sum(true)}; },
                [&] { return Vals{sum(false)}; });
        },
        [&] { return Vals{zero}; })[0];
    return b.add(independent, beat);
}

} // namespace

ValueId morphBeat(ir::Builder& b, const std::vector<LayerFields>& fields, ValueId from, ValueId to,
                  ValueId w, ValueId halfWidth, const PixelFootprint& pixel,
                  const std::function<ValueId(ValueId, const Vals&)>& pick, ValueId independent) {
    // While the morph holds a family, D is that family's distance and the beat adds nothing.
    const ValueId changing =
        b.emit(Op::And, {b.gt(w, b.constF(kHeld)), b.lt(w, b.constF(1.0 - kHeld))});
    return b.ifThenElse(
        changing,
        [&] {
            std::vector<std::vector<Way>> ways;
            for (const LayerFields& f : fields) ways.push_back(waysOf(b, f, pixel));
            auto picked = [&](ValueId which) {
                std::vector<Way> out(kWays);
                for (size_t q = 0; q < kWays; ++q) {
                    Vals index, gu, gv, g, on;
                    for (const std::vector<Way>& fw : ways) {
                        index.push_back(fw[q].index);
                        gu.push_back(fw[q].gu);
                        gv.push_back(fw[q].gv);
                        g.push_back(fw[q].g);
                        on.push_back(fw[q].on);
                    }
                    out[q] = {pick(which, index), pick(which, gu), pick(which, gv), pick(which, g),
                              pick(which, on)};
                }
                return out;
            };
            return Vals{
                beatOf(b, picked(from), picked(to), w, b.div(halfWidth, pixel.size), independent)};
        },
        [&] { return Vals{independent}; })[0];
}

} // namespace moire::lower
