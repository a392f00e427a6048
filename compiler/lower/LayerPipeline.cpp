#include "compiler/lower/LayerPipeline.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Semantics.h"

namespace moire::lower {

using ir::Op;
using ir::ValueId;

namespace {
// A non-positive spacing has no members; it is held at a tiny positive pitch instead of
// dividing by zero, so the layer degrades to solid ink rather than to NaN.
ValueId heldSpacing(ir::Builder& b, ValueId spacing) {
    return b.max(spacing, b.constF(1e-6));
}
} // namespace

ValueId indexOfPhase(ir::Builder& b, ValueId phi, ValueId phase, ValueId spacing) {
    return b.mul(b.sub(phi, phase), b.div(b.constF(1.0), heldSpacing(b, spacing))); // per frame
}

LayerFields phaseFamilyFields(ir::Builder& b, ValueId phi, ValueId phase, ValueId spacing,
                              std::optional<int> first, ValueId phiNear) {
    ValueId s = heldSpacing(b, spacing);
    ValueId index = indexOfPhase(b, phi, phase, spacing);
    ValueId nearest = b.round(index);
    if (first) nearest = b.max(nearest, b.constF(*first));
    ValueId residual = b.abs(b.sub(index, nearest));
    // |grad index| by forward-mode AD; the floor keeps a critical point of the phase (the
    // centre of the circles) at a finite, large distance instead of 0/0.
    ValueId gx = b.emit(Op::DerivX, {index});
    ValueId gy = b.emit(Op::DerivY, {index});
    ValueId grad = b.max(b.hypot(gx, gy), b.constF(ir::kTiny));
    ValueId distance = b.div(residual, grad);
    std::optional<FoldSample> foldSample; // for the envelope's taps
    if (first) {
        // Short of the first member (index < first) the nearest member is `first`, but the
        // gradient at the point says nothing about the way there: a family excludes its lower
        // members exactly where the phase is singular. The hyperbola's phase sqrt|x^2 - y^2|
        // has an infinite gradient on the asymptote pair (its excluded member 0), so Eq. 5
        // shrinks to zero along the asymptotes and inks the member the family excludes (a
        // hairline widening away from the centre; tests/families_identities_test.cpp).
        // A phase with such a fold is the square root of a smooth function, so in this band
        // Eq. 5 is applied to phi^2 instead, whose gradient 2 phi grad(phi) stays finite:
        //   d = (c^2 - phi^2) / |grad phi^2| = (c - phi)(c + phi) / (2 phi |grad phi|),
        // with c the first member's level. For 0 < phi < c this is never less than plain
        // Eq. 5 (it is that times (c + phi) / 2 phi) and equals it on the first member; for
        // the hyperbola it is the first-order distance to x^2 - y^2 = +-c^2, c^2 / 2|p| on
        // the asymptotes, which is the true distance there away from the centre (nearer the
        // centre it overstates it: measured within +12% below member 1, docs/families.md).
        ValueId c = b.add(b.mul(b.constF(*first), s), phase);
        ValueId twoPhiGrad = b.mul(b.mul(b.constF(2.0), phi), b.mul(s, grad)); // |grad phi^2|
        ValueId fold =
            b.div(b.mul(b.sub(c, phi), b.add(c, phi)), b.max(twoPhiGrad, b.constF(ir::kTiny)));
        // On the fold itself (phi exactly 0: a pixel centre on the hyperbola's asymptote, as
        // along whole diagonals of a centred view of even size) phi grad(phi) is 0 * infinity,
        // which AD reads as 0, so both estimates were infinite and a line of paper ran through
        // the ink. There the estimate is c^2 / |grad phi^2|, and |grad phi^2| (the gradient of
        // |x^2 - y^2| for the hyperbola) is continuous across the fold: it is read at a point a
        // hair away, off the fold, where 2 phi |grad phi| is well defined.
        ValueId onFold = distance;
        // The envelope's taps measure the first member the same way (FoldSample): the
        // estimate's 1 / |grad phi^2|, and whether it alone is the distance (on the fold).
        ValueId offFold = b.gt(phi, b.constF(0.0));
        ValueId scale = b.select(
            offFold, b.div(b.constF(1.0), b.max(twoPhiGrad, b.constF(ir::kTiny))), b.constF(0.0));
        ValueId exact = b.constB(false);
        if (phiNear != ir::kNoValue) {
            ValueId gradNear =
                b.hypot(b.emit(Op::DerivX, {phiNear}), b.emit(Op::DerivY, {phiNear}));
            ValueId twoPhiGradNear = b.mul(b.mul(b.constF(2.0), phiNear), gradNear);
            ValueId atFold = b.div(b.mul(c, c), b.max(twoPhiGradNear, b.constF(ir::kTiny)));
            ValueId nearOff = b.gt(phiNear, b.constF(0.0));
            onFold = b.select(nearOff, atFold, distance);
            exact = b.emit(Op::And, {b.emit(Op::Not, {offFold}), nearOff});
            scale = b.select(
                exact, b.div(b.constF(1.0), b.max(twoPhiGradNear, b.constF(ir::kTiny))), scale);
        }
        ValueId inFold = b.select(offFold, b.max(distance, fold), onFold);
        distance = b.select(b.lt(index, b.constF(*first)), inFold, distance);
        foldSample =
            FoldSample{*first, ir::kNoValue, b.sub(c, phi), b.add(c, phi), s, scale, exact};
    }
    LayerFields out;
    out.index = index;
    out.distance = distance;
    out.gradX = gx;
    out.gradY = gy;
    out.sample = phaseSample(b, index, nearest, grad, foldSample);
    out.footprint = Footprint{index, grad, gx, gy, first};
    return out;
}

// Exact for a phase family: advancing the index by a moves member m's index residual from
// m - index to m - index - a, and its distance is that residual over |grad index| (Eq. 5).
PhaseSample phaseSample(ir::Builder& b, ValueId index, ValueId nearest, ValueId grad,
                        const std::optional<FoldSample>& fold) {
    ValueId perIndex = b.div(b.constF(1.0), grad); // world units per unit of index
    auto at = [&](double step) {
        return b.mul(b.sub(b.add(nearest, b.constF(step)), index), perIndex);
    };
    PhaseSample s{at(0.0), at(1.0), at(-1.0), b.constF(0.0), std::nullopt, std::nullopt, nullptr};
    if (fold) {
        s.down = b.select(b.lt(nearest, b.constF(fold->first + 1.0)), b.constF(kNoMember), s.down);
        s.fold = *fold;
        s.fold->index = index;
    }
    return s;
}

StrokeBand strokeBand(ir::Builder& b, ValueId stroke, ValueId pixel, bool floored) {
    StrokeBandT<ir::BuiltValue> band =
        strokeBandOf(ir::BuiltValue(b, stroke), ir::BuiltValue(b, pixel), floored);
    return {band.h.id, band.a.id};
}

ValueId strokeCoverage(ir::Builder& b, ValueId d, const StrokeBand& band, ValueId opacity,
                       ValueId alpha) {
    return inkCoverage(b, strokeInk(b, d, band), opacity, alpha);
}

ValueId strokeInk(ir::Builder& b, ValueId d, const StrokeBand& band) {
    return b.sub(b.constF(1.0), b.smoothstep(b.sub(band.h, band.a), b.add(band.h, band.a), d));
}

ValueId inkCoverage(ir::Builder& b, ValueId ink, ValueId opacity, ValueId alpha) {
    ValueId cov = b.mul(ink, b.mul(b.clamp(opacity, b.constF(0.0), b.constF(1.0)),
                                   b.clamp(alpha, b.constF(0.0), b.constF(1.0))));
    return b.denan(b.clamp(cov, b.constF(0.0), b.constF(1.0)), b.constF(0.0));
}

Ink paper(ir::Builder& b, ValueId r, ValueId g, ValueId bl, ValueId a) {
    ValueId alpha = b.clamp(a, b.constF(0.0), b.constF(1.0));
    return {b.mul(r, alpha), b.mul(g, alpha), b.mul(bl, alpha), alpha};
}

Ink inkOver(ir::Builder& b, const Ink& acc, ValueId r, ValueId g, ValueId bl, ValueId cov) {
    // Premultiplied "over": c' = c (1 - cov) + ink cov. On opaque paper this is exactly the
    // running mix(c, ink, cov); two black layers give the union a1 + a2 - a1 a2.
    ValueId keep = b.sub(b.constF(1.0), cov);
    auto over = [&](ValueId c, ValueId ink) { return b.add(b.mul(c, keep), b.mul(ink, cov)); };
    return {over(acc.r, r), over(acc.g, g), over(acc.b, bl), over(acc.a, b.constF(1.0))};
}

Ink addCorrection(ir::Builder& b, const Ink& acc, const Ink& d, ValueId scale) {
    // A correction may push a sum of means past what ink can be: alpha is held to [0, 1] and
    // each premultiplied channel to [0, alpha], so the colour stays one the paper can show.
    auto add = [&](ValueId c, ValueId dc) { return b.add(c, b.mul(scale, dc)); };
    ValueId a = b.clamp(add(acc.a, d.a), b.constF(0.0), b.constF(1.0));
    auto channel = [&](ValueId c, ValueId dc) { return b.clamp(add(c, dc), b.constF(0.0), a); };
    return {channel(acc.r, d.r), channel(acc.g, d.g), channel(acc.b, d.b), a};
}

Ink unpremultiply(ir::Builder& b, const Ink& acc) {
    ValueId inv = b.div(b.constF(1.0), b.max(acc.a, b.constF(ir::kTiny)));
    ValueId any = b.gt(acc.a, b.constF(0.0));
    auto straight = [&](ValueId c) { return b.select(any, b.mul(c, inv), b.constF(0.0)); };
    return {straight(acc.r), straight(acc.g), straight(acc.b), acc.a};
}

} // namespace moire::lower
