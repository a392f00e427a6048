// The names and functions every expression can use. Semantic checks type calls against this
// table; lowering turns each into IR ops.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace moire::sema {

// Built-in names.
enum class Name { X, Y, R, Theta, Pi, Tau, E, T };
struct NameInfo {
    const char* spelling;
    bool position; // depends on where it is evaluated
    bool time;     // depends on the clock
    const char* what;
};
const NameInfo& nameInfo(Name n);
std::optional<Name> lookupName(std::string_view s);

// Names with a meaning in one context only: an easing's raw progress, the spacing of a
// family's layer (reserved everywhere), and the call that makes a layer's family a morph.
inline constexpr const char* kEasingProgressName = "u";
inline constexpr const char* kSpacingName = "spacing";
inline constexpr const char* kMorphName = "morph";

// Built-in functions.
enum class Fn {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Exp,
    Log,
    Sqrt,
    Abs,
    Floor,
    Fract,
    Round,
    Sign,
    Min,
    Max,
    Mod,
    Hypot,
    Clamp,
    Wrap,
    Smoothstep,
    Mix,
    Length,
    Rgb,
    Rgba,
    Step,
    Ramp,
    Progress,
    Select,
};
// How a function's argument and result types relate.
enum class Signature {
    Trig,      // (number | angle) -> number
    NumToNum,  // number... -> number
    SameUnit,  // all arguments number, or all angle -> that type
    SameToNum, // all arguments number, or all angle -> number (smoothstep, sign)
    Mix,       // (T, T, number) -> T, T any value type
    Length,    // vector -> number
    Color,     // numbers -> colour
    Timed,     // (timing[, T, T]) -> number, or T between the two values: ramp, progress
    Select,    // (boolean, T, T) -> T
};
struct FnInfo {
    const char* spelling;
    int numArgs;
    Signature sig;
    const char* doc; // one line, used by --help-language and the docs
};
const FnInfo& fnInfo(Fn f);
std::optional<Fn> lookupFn(std::string_view s);

// Every built-in name and function name (for suggestions and the reserved-name check).
const std::vector<std::string>& builtinNames();
const std::vector<std::string>& builtinFunctions();

} // namespace moire::sema
