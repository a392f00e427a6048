#include "compiler/lower/PencilFamily.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <numbers>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

namespace {
// An edge no pixel reaches: the pencil without a disc.
constexpr double kNoDisc = 1e30;
} // namespace

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
    // Under the mean filter the lines are averaged by their winding index, as a phase family's
    // members are: it is linear across a pixel but at the centre, and it counts every line the
    // pixel holds where they crowd towards the centre (the nearest line alone there drew the
    // fan's core light). The line through a point at angle a from it is r |sin a| away and
    // r a along the index's step, the same to second order where a stroke is. Where the
    // pixel reaches the open disc, which no line enters, the nearest line's distance.
    out.footprint = Footprint{smooth, grad, out.gradX, out.gradY, std::nullopt};
    out.footprint.edge = b.select(b.gt(start, b.constF(0.0)), b.sub(r, start), b.constF(kNoDisc));
    return out;
}

FamilyBuilder pencilBuilder() {
    return [](ir::Builder& b, const FamilyInputs& in) {
        MOIRE_CHECK(in.params.size() == 2, "a pencil takes (lines, start)");
        return pencilFields(b, in.at.qx, in.at.qy, in.params[0][0], in.params[1][0]);
    };
}

} // namespace moire::lower
