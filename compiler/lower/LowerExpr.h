// Lowering expressions to IR. A value of the language becomes 1 (number, angle), 2 (vector)
// or 4 (colour) IR floats. Names are resolved in a Frame: the coordinates x and y mean the
// frame's coordinates, so a field used in a family's phase is evaluated in the layer's own
// frame and elsewhere in the scene's.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/parse/Ast.h"
#include "compiler/sema/Sema.h"

#include <functional>
#include <unordered_map>
#include <vector>

namespace moire::lower {

using Vals = std::vector<ir::ValueId>;

struct Frame {
    ir::ValueId x = ir::kNoValue, y = ir::kNoValue;
    ir::ValueId r = ir::kNoValue, theta = ir::kNoValue; // computed on first use
    // Inside a family body:
    const ast::Decl* family = nullptr;
    std::vector<Vals> params; // the layer's argument values
    std::vector<Vals> lets;   // lowered in order
    ir::ValueId spacing = ir::kNoValue;
    ir::ValueId u = ir::kNoValue;                      // inside an easing: the progress it shapes
    std::unordered_map<const ast::Decl*, Vals> fields; // fields already lowered here
};

// A timing's progress at the frame's clock: raw (linear, 0 to 1) and shaped by its easing.
struct Progress {
    ir::ValueId raw, eased;
};

class ExprLowering {
  public:
    explicit ExprLowering(ir::Builder& b) : b_(b) {}

    // How `ramp` and `progress` reach a timing's progress (set by the scene's lowering).
    void setTimings(std::function<Progress(const ast::Decl*)> progress) {
        progress_ = std::move(progress);
    }

    Vals lower(const ast::Expr& e, Frame& frame);
    // A `param`'s value: the one a tool set in its literal slots, else its default.
    Vals param(const ast::Decl& p, Frame& frame);
    ir::ValueId scalar(const ast::Expr& e, Frame& frame);
    // A block's property (`block` may be null: a scene without it) as written, or else its
    // default from `table` (sema/Properties.h).
    Vals property(const ast::Decl* block, const std::vector<sema::PropertySpec>& table,
                  std::string_view name, Frame& frame);

  private:
    Vals name(const ast::Expr& e, Frame& frame);
    Vals binary(const ast::Expr& e, Frame& frame);
    Vals call(const ast::Expr& e, Frame& frame);
    ir::ValueId literal(double value, int slot);

    ir::Builder& b_;
    std::function<Progress(const ast::Decl*)> progress_;
};

} // namespace moire::lower
