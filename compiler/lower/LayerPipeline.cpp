#include "compiler/lower/LayerPipeline.h"

#include "compiler/ir/Semantics.h"

namespace moire::lower {

using ir::Op;
using ir::ValueId;

LayerFields phaseFamilyFields(ir::Builder& b, ValueId phi, ValueId phase, ValueId spacing,
                              std::optional<int> first) {
    // A non-positive spacing has no members; it is held at a tiny positive pitch instead of
    // dividing by zero, so the layer degrades to solid ink rather than to NaN.
    ValueId s = b.max(spacing, b.constF(1e-6));
    ValueId index = b.mul(b.sub(phi, phase), b.div(b.constF(1.0), s)); // 1/s is per frame
    ValueId nearest = b.round(index);
    if (first) nearest = b.max(nearest, b.constF(*first));
    ValueId residual = b.abs(b.sub(index, nearest));
    // |grad index| by forward-mode AD; the floor keeps a critical point of the phase (the
    // centre of the circles) at a finite, large distance instead of 0/0.
    ValueId gx = b.emit(Op::DerivX, {index});
    ValueId gy = b.emit(Op::DerivY, {index});
    ValueId grad = b.max(b.hypot(gx, gy), b.constF(ir::kTiny));
    return {index, b.div(residual, grad), gx, gy};
}

ValueId strokeCoverage(ir::Builder& b, ValueId d, ValueId stroke, ValueId pixel, ValueId opacity,
                       ValueId alpha) {
    ValueId h = b.max(b.mul(stroke, b.constF(0.5)), b.mul(pixel, b.constF(1.15)));
    ValueId a = b.mul(pixel, b.constF(0.7));
    ValueId ink = b.sub(b.constF(1.0), b.smoothstep(b.sub(h, a), b.add(h, a), d));
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

Ink unpremultiply(ir::Builder& b, const Ink& acc) {
    ValueId inv = b.div(b.constF(1.0), b.max(acc.a, b.constF(ir::kTiny)));
    ValueId any = b.gt(acc.a, b.constF(0.0));
    auto straight = [&](ValueId c) { return b.select(any, b.mul(c, inv), b.constF(0.0)); };
    return {straight(acc.r), straight(acc.g), straight(acc.b), acc.a};
}

} // namespace moire::lower
