#include "compiler/lower/FineUnion.h"

#include "compiler/ir/BuiltValue.h"

#include <algorithm>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

bool joinsFineUnion(const Footprint& footprint, const PhaseSample& sample) {
    return footprint.grad != ir::kNoValue && footprint.gradX != ir::kNoValue &&
           sample.z != ir::kNoValue && !sample.lattice && !sample.morph;
}

namespace {

// footprintTransfer of an index whose gradient has components (u, v) along the pixel's sides.
ValueId transfer(ir::Builder& b, const PixelSides& g, const PixelFootprint& pixel) {
    ir::BuiltValue along(b, b.mul(b.abs(g.u), pixel.size));
    ir::BuiltValue across(b, b.mul(b.abs(g.v), pixel.size));
    return footprintTransfer(along, across).id;
}

// How far a layer's members are past being resolved: smoothstep(kCrowdFrom, kCrowdFull, nu),
// nu = |grad index| x pixel, and 0 where its footprint reaches below a first member (as
// meanInk, which draws such a pixel from its distance).
ValueId unresolved(ir::Builder& b, const Footprint& f, const PixelFootprint& pixel) {
    ValueId nu = b.mul(f.grad, pixel.size);
    ValueId weight = b.smoothstep(b.constF(kCrowdFrom), b.constF(kCrowdFull), nu);
    if (!f.first) return weight;
    ValueId lowest = b.sub(f.index, b.mul(nu, b.constF(0.5)));
    return b.select(b.lt(lowest, b.constF(*f.first - 0.5)), b.constF(0.0), weight);
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
// drawn.
Ink fineUnion(ir::Builder& b, const Ink& under, const Ink& independent,
              const std::vector<FineLayer>& run, const PixelFootprint& pixel) {
    if (run.size() < 2) return independent;
    std::vector<EnvelopeLayer> layers;
    for (const FineLayer& l : run) layers.push_back(l.sweep);
    ValueId engaged = b.constF(1.0);
    for (const FineLayer& l : run) engaged = b.min(engaged, unresolved(b, l.footprint, pixel));
    // The direction is chosen per pixel, so the weight is built behind the first branch.
    std::vector<ValueId> out = b.ifThenElse(
        b.gt(engaged, b.constF(0.0)),
        [&] {
            const std::vector<ValueId> w = sweepDirection(b, layers);
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
            ValueId weight =
                b.mul(engaged, b.clamp(b.sub(beat, apart), b.constF(0.0), b.constF(1.0)));
            weight = b.denan(weight, b.constF(0.0));
            // Swept only where the weight is above 0.
            return b.ifThenElse(
                b.gt(weight, b.constF(0.0)),
                [&] {
                    EnvelopeSettings settings{b.constF(1.0), b.constF(kUnionTaps)};
                    SweptInk swept = sweptInk(b, under, layers, settings, w);
                    auto add = [&](ValueId ind, ValueId mean, ValueId pivot) {
                        return b.add(ind, b.mul(weight, b.sub(mean, pivot)));
                    };
                    ValueId a = b.clamp(add(independent.a, swept.mean.a, swept.pivot.a),
                                        b.constF(0.0), b.constF(1.0));
                    auto channel = [&](ValueId ind, ValueId mean, ValueId pivot) {
                        return b.clamp(add(ind, mean, pivot), b.constF(0.0), a);
                    };
                    return std::vector<ValueId>{channel(independent.r, swept.mean.r, swept.pivot.r),
                                                channel(independent.g, swept.mean.g, swept.pivot.g),
                                                channel(independent.b, swept.mean.b, swept.pivot.b),
                                                a};
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

} // namespace moire::lower
