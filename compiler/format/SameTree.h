// Whether two parsed modules say the same thing, for the formatter's check of its own output:
// the same declarations (kinds, names, parameters, lets, properties, in order), expressions
// equal node for node (kind, name, operator, number and unit, colour, literal slot) and the
// same literal table. Where things are written is not compared.
//
// The walk keeps its own stack: a chain `a + b + c + ...` is as deep as it is long, and
// neither recursion nor a printed tree (ast::printModule indents each node by its depth)
// would do for one of a hundred thousand terms.
#pragma once

#include "compiler/parse/Ast.h"

namespace moire::format {

bool sameModule(const ast::Module& a, const ast::Module& b);
bool sameExpr(const ast::Expr& a, const ast::Expr& b);

} // namespace moire::format
