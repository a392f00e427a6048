// A scene's parameters (`param name = value in lo .. hi step s`) as the tools that turn them
// see them: the viewer's sliders, `moire serve`'s page, `moire export`'s page.
//
// A parameter is a uniform. Its value reaches the kernel through the frame program, which
// takes the parameter's own literal slots when its `set` slot is 1 and its default expression
// otherwise. So a slider writes a copy of the literal table (FrameRequest::literals) and never
// recompiles; a default that is an expression (of `t`, of other parameters) is evaluated once
// per frame, like any value that does not depend on the position.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/lex/Token.h" // Unit
#include "compiler/parse/Ast.h"
#include "compiler/sema/Sema.h"

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace moire {

struct Parameter {
    std::string name;
    ast::Type type = ast::Type::Num; // Num, Angle, Vec2, Color or Bool
    int components = 1;              // 1 (number, angle, boolean), 2 (vector), 4 (colour)
    // The declared range and step, in the language's units (radians for angles); for a
    // vector, they hold for each component. A colour or a boolean has none.
    std::optional<double> min, max, step;
    std::string unitLabel; // `unit mm`: a word a slider shows beside the value; may be empty
    // How the default's angle was written (Deg or Rad), so that a slider shows degrees for
    // `30deg`; None for every other type.
    Unit unit = Unit::None;
    SourceRange nameRange;  // the parameter's name in its declaration
    SourceRange valueRange; // the default value's text: a write-back replaces exactly this
    int valueSlot = -1;     // the first of `components` literal slots holding a set value
    int setSlot = -1;       // a literal slot: 1 when the set value replaces the default
};

// The checked scene's params, as tools see them.
std::vector<Parameter> collectParameters(const sema::CheckedScene& scene);

// Components of a colour are straight (not premultiplied) sRGB in 0..1, as in the literal
// table; a boolean is 0 or 1; an angle is in radians.

// Why `value` cannot be the parameter's value (its arity, a boolean not 0 or 1, a colour
// component outside 0..1, a number outside the declared range, a non-finite number), as a
// message without a location; empty when it can.
std::string checkParameterValue(const Parameter& p, std::span<const double> value);

// Sets the parameter in `literals` (a copy of SceneProgram::literals): the frame program then
// uses `value` in place of the default. `value` must pass checkParameterValue.
void setParameterValue(const Parameter& p, std::span<const double> value,
                       std::vector<double>& literals);
// Returns the parameter to its default expression.
void clearParameterValue(const Parameter& p, std::vector<double>& literals);

// `value` as source text of the parameter's type, for writing it back into the file:
// `12.5`, `30deg` (in the unit the default was written in), `(1, 2)`, `#ff8800` (with
// alpha when not opaque), `true`. Numbers are written with the fewest digits that read back
// as the same float.
std::string formatParameterValue(const Parameter& p, std::span<const double> value);

// The value of `text` when it is a plain literal of `p`'s type, as the language reads it: a
// number (with an optional minus sign), an angle with its unit, `(x, y)` of such numbers, a
// colour `#rrggbb[aa]`, `true` or `false`, with spaces and comments around it (the rest of
// the array 0). Empty for anything else (an expression, another type). The inverse of
// formatParameterValue.
std::optional<std::array<double, 4>> readParameterValue(const Parameter& p, std::string_view text);

// The type as the pages' controls name it (moire serve's, moire export's): "number", "angle",
// "vector", "color" or "bool".
const char* parameterKind(ast::Type type);

} // namespace moire
