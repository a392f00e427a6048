// Lowering expressions to IR. A value of the language becomes 1 (number, angle), 2 (vector)
// or 4 (colour) IR floats. Names are resolved in a Frame: the coordinates x and y mean the
// frame's coordinates, so a field used in a family's phase is evaluated in the layer's own
// frame and elsewhere in the scene's.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/parse/Ast.h"
#include "compiler/sema/Sema.h"

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
    std::unordered_map<const ast::Decl*, Vals> fields; // fields already lowered here
};

class ExprLowering {
  public:
    explicit ExprLowering(ir::Builder& b) : b_(b) {}

    Vals lower(const ast::Expr& e, Frame& frame);
    ir::ValueId scalar(const ast::Expr& e, Frame& frame);

  private:
    Vals name(const ast::Expr& e, Frame& frame);
    Vals binary(const ast::Expr& e, Frame& frame);
    Vals call(const ast::Expr& e, Frame& frame);
    ir::ValueId literal(double value, int slot);

    ir::Builder& b_;
};

} // namespace moire::lower
