// Forward-mode automatic differentiation as an IR-to-IR pass.
//
// Every float value v that a `deriv.x` / `deriv.y` needs is paired with its tangent
// (dv/dx, dv/dy) with respect to the values marked `indep 0` and `indep 1`. Tangents are
// structural: a value that does not depend on an independent variable has no tangent at
// all (not a zero), so constants and uniforms cost nothing. Chain-rule products use `mulz`,
// whose exact zero wins over inf and NaN (the zero rule).
#pragma once

#include "compiler/ir/IR.h"

namespace moire::passes {

ir::Function autoDiff(const ir::Function& f);

} // namespace moire::passes
