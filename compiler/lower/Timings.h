// Timings in the IR: a timing's progress at the frame's clock (raw and eased), for `ramp`,
// `progress` and morphs. Everything here depends on the clock alone, so the frame split
// moves it into the per-frame program: nothing accumulates from one frame to the next.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/LowerScene.h"
#include "compiler/sema/Sema.h"

#include <unordered_map>
#include <vector>

namespace moire::lower {

class TimingLowering {
  public:
    TimingLowering(ir::Builder& b, ExprLowering& exprs, const sema::CheckedScene& scene)
        : b_(b), exprs_(exprs), scene_(scene) {}

    // The timing's progress: raw in [0, 1] (linear in the clock within each pass) and eased.
    Progress progress(const ast::Decl* timing);
    // Its period (seconds per pass), floored at a microsecond.
    ir::ValueId period(const ast::Decl* timing);
    // An easing of the scene or the standard library, by name, at u.
    ir::ValueId ease(const std::string& easing, ir::ValueId u);
    // Outputs, from `firstSlot` on, the period, delay and mode of every timing used, and
    // records them in the layout.
    void outputSettings(OutputLayout& layout, int firstSlot);

  private:
    struct Lowered {
        ir::ValueId period, delay;
        Progress progress;
    };
    const Lowered& lowered(const ast::Decl* timing);

    ir::Builder& b_;
    ExprLowering& exprs_;
    const sema::CheckedScene& scene_;
    std::unordered_map<const ast::Decl*, Lowered> done_;
};

} // namespace moire::lower
