// The values the viewer's panel gives a scene's parameters (`param drift = 1.2 in 0 .. 5`), kept
// apart from the build they apply to: a value per parameter or none (the default stands). They
// reach the picture as a copy of the literal table (setParameterValue), never as a new kernel:
// a parameter is a uniform.
#pragma once

#include "compiler/Parameters.h"

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace moire::view {

using ParamValue = std::array<double, 4>; // a parameter's components; the rest 0
// One entry per parameter of a build (SceneProgram::parameters' order): the value set, if any.
using ParamSet = std::vector<std::optional<ParamValue>>;

// The value of `text` when it is a plain literal of `p`'s type (readParameterValue).
inline std::optional<ParamValue> readLiteral(const Parameter& p, std::string_view text) {
    return readParameterValue(p, text);
}

// `value` as the literal a write-back puts in the file (formatParameterValue).
std::string literalText(const Parameter& p, const ParamValue& value);

// `value` moved to the nearest value the parameter can hold and the file can say exactly: on
// the declared step (counted from the range's start, in the unit the default is written in),
// in the declared range, and read back from its own literal, so that the value on screen is
// the value a write-back puts in the file, bit for bit, and the picture does not move when
// the written file reloads.
ParamValue snapParamValue(const Parameter& p, ParamValue value);

// The parameter's default as the source writes it (its valueRange in `source`); empty when
// the range is not within the text.
std::string_view defaultText(const Parameter& p, std::string_view source);

// Sets each value of `set` in `literals` (a copy of the build's literal table).
void applyParams(std::span<const Parameter> params, const ParamSet& set,
                 std::vector<double>& literals);

// The values of `set` (for `from`, declared in `fromSource`) that still hold for the
// parameters `to` of a new build of `toSource`: matched by name, of the same type, within the
// new range, and only where the file did not change the default's text (an edit of that
// default is newer than the panel's value).
ParamSet carryParams(std::span<const Parameter> from, const ParamSet& set,
                     std::string_view fromSource, std::span<const Parameter> to,
                     std::string_view toSource);

} // namespace moire::view
