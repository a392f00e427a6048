// The value of an expression of a checked scene at t = 0, for hover: the expression is
// lowered by the compiler's own lowering and run on the reference interpreter, so the figure
// is the one the first frame uses.
#pragma once

#include "compiler/Compile.h"

#include <optional>
#include <vector>

namespace moire::lsp {

// Its components (one for a number or an angle, in radians; two for a vector; four for a
// colour), or nothing when it depends on the position, sits inside a family or an easing
// (where its names mean a layer's values), or the scene did not compile.
std::optional<std::vector<double>> valueAtZero(const SceneProgram& program, const ast::Expr& e);

} // namespace moire::lsp
