#include "compiler/lower/Envelope.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::lower {

using ir::ValueId;

ValueId tapDistance(ir::Builder& b, const PhaseSample& s, ValueId advance) {
    // One gap is one period of this family here, whatever its pitch does across the frame.
    ValueId shift = b.mul(advance, b.abs(b.sub(s.up, s.z)));
    auto from = [&](ValueId k) { return b.abs(b.sub(k, shift)); };
    ValueId d = b.min(from(s.z), b.min(from(s.up), from(s.down)));
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
    return w;
}

namespace {

ValueId coverage(ir::Builder& b, const EnvelopeLayer& l, const StrokeBand& band, ValueId d) {
    return strokeCoverage(b, d, band, l.opacity, l.color[3]);
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

Ink envelopeInk(ir::Builder& b, const Ink& paper, const std::vector<EnvelopeLayer>& layers,
                const EnvelopeSettings& settings) {
    if (layers.empty()) return paper;
    const std::vector<ValueId> w = sweepDirection(b, layers);
    ValueId taps = b.clamp(b.round(settings.taps), b.constF(1.0), b.constF(sema::kMaxEnvelopeTaps));
    ValueId step = b.div(b.constF(1.0), taps);
    std::vector<StrokeBand> bands;
    for (const EnvelopeLayer& l : layers) {
        ValueId gap = b.abs(b.sub(l.sample.up, l.sample.z));
        ValueId a =
            b.min(b.max(l.antialias, b.mul(b.mul(gap, step), b.constF(kTapBand))), l.halfWidth);
        bands.push_back({l.halfWidth, a});
    }
    // Carried: the tap j, the running sums of the stack's ink (r, g, b, a, premultiplied)
    // and of each layer's own coverage.
    const size_t n = layers.size();
    std::vector<ValueId> init(5 + n, b.constF(0.0));
    auto more = [&](std::span<const ValueId> v) { return std::vector<ValueId>{b.lt(v[0], taps)}; };
    std::vector<ValueId> sums = b.loop(init, more, [&](std::span<const ValueId> v) {
        ValueId u = b.mul(b.add(v[0], b.constF(0.5)), step);
        Ink acc = paper;
        std::vector<ValueId> next{b.add(v[0], b.constF(1.0))};
        std::vector<ValueId> covs;
        for (size_t i = 0; i < n; ++i) {
            // The advance u w_i, less its whole periods, keeps its sign: within (-1, 1).
            ValueId a = b.mul(u, w[i]);
            a = b.sub(a, b.mul(b.emit(ir::Op::Sign, {a}), b.floor(b.abs(a))));
            ValueId cov = coverage(b, layers[i], bands[i], tapDistance(b, layers[i].sample, a));
            acc = over(b, acc, layers[i], cov);
            covs.push_back(b.add(v[5 + i], cov));
        }
        const ValueId channels[] = {acc.r, acc.g, acc.b, acc.a};
        for (int k = 0; k < 4; ++k) next.push_back(b.add(v[1 + k], channels[k]));
        next.insert(next.end(), covs.begin(), covs.end());
        return next;
    });
    Ink mean{b.mul(sums[1], step), b.mul(sums[2], step), b.mul(sums[3], step),
             b.mul(sums[4], step)};
    // The pivot: the layers' own mean coverages composited, or a sole layer's nominal ink.
    Ink pivot = paper;
    for (size_t i = 0; i < n; ++i) {
        ValueId own = n == 1 ? nominalCoverage(b, layers[i]) : b.mul(sums[5 + i], step);
        pivot = over(b, pivot, layers[i], own);
    }
    auto grade = [&](ValueId p, ValueId m) { return b.add(p, b.mul(settings.gain, b.sub(m, p))); };
    ValueId alpha = b.clamp(grade(pivot.a, mean.a), b.constF(0.0), b.constF(1.0));
    auto channel = [&](ValueId p, ValueId m) { return b.clamp(grade(p, m), b.constF(0.0), alpha); };
    return {channel(pivot.r, mean.r), channel(pivot.g, mean.g), channel(pivot.b, mean.b), alpha};
}

} // namespace moire::lower
