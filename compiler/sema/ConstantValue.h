// The value of an expression built from numbers alone (digits with their units, pi, tau, e,
// signs and arithmetic), as the checks need it for a param's range and step.
#pragma once

#include "compiler/parse/Ast.h"

#include <optional>

namespace moire::sema {

// The value in the language's units (radians for angles), or nothing when the expression
// names anything else (a field, a param, x, t, a function) or its value is not finite.
std::optional<double> constantValue(const ast::Expr& e);

} // namespace moire::sema
