// The cleanup passes run after lowering and after AD:
//  - constantFold: evaluates ops on constants with the shared semantics (Semantics.h), applies
//    exact identities (x + (-0), x * 1, mulz(0, x) = 0, select on a constant), and inlines an
//    `if` whose condition is constant;
//  - eliminateCommonSubexpressions: value numbering of pure ops, scoped by region;
//  - eliminateDeadCode: drops pure instructions whose results nothing live uses.
// Each rebuilds the function, so values end up densely numbered.
#pragma once

#include "compiler/ir/IR.h"
#include "compiler/passes/Rewriter.h"

namespace moire::passes {

ir::Function constantFold(const ir::Function& f, Check check = Check::Verify);
// `merged`, when given, receives the number of instructions replaced by an earlier one.
ir::Function eliminateCommonSubexpressions(const ir::Function& f, Check check = Check::Verify,
                                           size_t* merged = nullptr);
ir::Function eliminateDeadCode(const ir::Function& f, Check check = Check::Verify);

// fold, CSE and DCE, again while CSE merges anything: a merge can make a fold possible (x - y
// with y merged into x), but a fold is seen by the CSE of its own round, and dropping dead
// code makes neither possible. The result is verified once, at the end.
ir::Function simplify(const ir::Function& f);

} // namespace moire::passes
