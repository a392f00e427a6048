#include "compiler/lower/Compose.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::lower {

using ir::ValueId;

Compose::Compose(ir::Builder& b, ViewMode mode, const Vals& background)
    : b_(b), mode_(mode),
      acc_(paper(b, background[0], background[1], background[2], background[3])),
      zero_(b.constF(0.0)), unresolved_(zero_) {}

void Compose::layer(const LayerInk& ink) {
    if (ink.sampling != ir::kNoValue) unresolved_ = b_.max(unresolved_, ink.sampling);
    b_.setLoc(ink.where);
    switch (mode_) {
    case ViewMode::Pattern: {
        ValueId cov = strokeCoverage(b_, ink.fields.distance, ink.band, ink.opacity, ink.color[3]);
        acc_ = inkOver(b_, acc_, ink.color[0], ink.color[1], ink.color[2], cov);
        return;
    }
    }
    MOIRE_ICE("unknown view mode");
}

void Compose::output(const std::function<Vals()>& unresolvedTint) {
    // The sampling limit (§10.4): a carrier of pitch s cannot show fringes much finer than
    // 3 s, so where an encoded field is that steep the scene's `unresolved` tint is laid
    // over everything (transparent unless the scene sets it).
    if (unresolved_ != zero_) {
        Vals tint = unresolvedTint();
        ValueId mark = b_.smoothstep(b_.constF(0.30), b_.constF(0.37), unresolved_);
        acc_ = inkOver(b_, acc_, tint[0], tint[1], tint[2],
                       b_.mul(mark, b_.clamp(tint[3], zero_, b_.constF(1.0))));
    }
    Ink out = unpremultiply(b_, acc_);
    b_.output(0, out.r);
    b_.output(1, out.g);
    b_.output(2, out.b);
    b_.output(3, out.a);
}

} // namespace moire::lower
