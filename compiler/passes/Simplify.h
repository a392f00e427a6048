// The cleanup passes run after lowering and after AD:
//  - constantFold: evaluates ops on constants with the shared semantics (Semantics.h), applies
//    exact identities (x + (-0), x * 1, mulz(0, x) = 0, select on a constant), and inlines an
//    `if` whose condition is constant;
//  - eliminateCommonSubexpressions: value numbering of pure ops, scoped by region;
//  - eliminateDeadCode: drops pure instructions whose results nothing live uses.
// Each rebuilds the function, so values end up densely numbered.
#pragma once

#include "compiler/ir/IR.h"

namespace moire::passes {

ir::Function constantFold(const ir::Function& f);
ir::Function eliminateCommonSubexpressions(const ir::Function& f);
ir::Function eliminateDeadCode(const ir::Function& f);

// fold, CSE and DCE until the instruction count stops shrinking.
ir::Function simplify(const ir::Function& f);

} // namespace moire::passes
