// A scene's parameters as the page sees them (a JSON list it builds its sliders from) and the
// values its sliders send, read and checked against the declaration (Parameters.h).
#pragma once

#include "compiler/Parameters.h"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace moire::serve {

// One parameter for the page: {"name", "type", "components", "min", "max", "step" (null when
// not declared), "unit" ("deg" or "rad" for an angle, else null), "label" (the `unit` word
// written in the declaration, or ""), "value" (its components:
// radians for an angle, straight sRGB 0..1 for a colour, 0 or 1 for a boolean), "set" (a
// slider's value replaces the default)}.
nlohmann::json parameterJson(const Parameter& p, const std::vector<double>& value, bool set);

// The value a slider message carries for `p`: a number (number, angle: in radians), true or
// false (boolean), [x, y] (vector), "#rrggbb" or "#rrggbbaa" or [r, g, b, a] in 0..1 (colour),
// or a list of the components of any type. Throws RequestError (Session.h) with the reason
// when it is of the wrong shape or checkParameterValue refuses it (out of range, say).
std::vector<double> parameterValueFromJson(const Parameter& p, const nlohmann::json& value);

} // namespace moire::serve
