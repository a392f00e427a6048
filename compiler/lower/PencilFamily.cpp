#include "compiler/lower/PencilFamily.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <numbers>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

LayerFields pencilFields(ir::Builder& b, ValueId qx, ValueId qy, ValueId lines, ValueId start) {
    // Whole lines only: a fraction would leave a seam at theta = pi.
    ValueId n = b.max(b.constF(1.0), b.round(lines));
    ValueId r = b.hypot(qx, qy);
    ValueId theta = b.emit(Op::Atan2, {qy, qx});
    ValueId pi = b.constF(std::numbers::pi);
    ValueId hole = b.sub(start, r);
    LayerFields out;
    out.distance = b.max(b.mul(r, b.abs(b.emit(Op::Sin, {b.wrap(theta, b.div(pi, n))}))), hole);
    ValueId smooth = b.div(b.mul(theta, n), pi);
    out.index = b.floor(smooth);
    // The winding index: member k is {smooth = k}. Across the branch cut of theta it jumps by
    // 2N, a whole number of members, so its level sets and gradient are continuous.
    out.smooth = smooth;
    out.gradX = b.emit(Op::DerivX, {smooth});
    out.gradY = b.emit(Op::DerivY, {smooth});
    // The sample is the phase family's (Eq. 14 from the index and |grad index| = N / (pi r)):
    // advancing the index by a turns the lines by a pi / N, and a member's distance becomes
    // its arc r pi / N |k - smooth - a|, the perpendicular distance r |sin| to second order
    // in the angle wherever a stroke is. The disc does not turn: it is the floor.
    ValueId grad = b.max(b.hypot(out.gradX, out.gradY), b.constF(ir::kTiny));
    out.sample = phaseSample(b, smooth, b.round(smooth), grad, std::nullopt);
    out.sample.floor = hole;
    return out;
}

FamilyBuilder pencilBuilder() {
    return [](ir::Builder& b, const FamilyInputs& in) {
        MOIRE_CHECK(in.params.size() == 2, "a pencil takes (lines, start)");
        return pencilFields(b, in.at.qx, in.at.qy, in.params[0][0], in.params[1][0]);
    };
}

} // namespace moire::lower
