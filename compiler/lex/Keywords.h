// The words the language reserves, in one list. The parser reads the declaration keywords,
// the lexer's hints know the built-in value names, and the checks refuse every one of them
// (with the built-in functions and `spacing`) as the name of a field, family, timing, easing,
// parameter or let: `field timing = 3` is as wrong as `field layer = 3`.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace moire {

// What begins a declaration: scene, camera, layer, field, family, timing, easing, param.
const std::vector<std::string>& declarationKeywords();

// A declaration keyword, or `let` (which begins a binding in a family's body).
inline constexpr const char* kLetKeyword = "let";
bool isKeyword(std::string_view word);

// The spellings of the built-in values, in the order of sema::Name (sema/Builtins.h gives
// them their meaning).
inline constexpr const char* kBuiltinValueNames[] = {"x", "y", "r", "theta", "pi", "tau", "e", "t"};
bool isBuiltinValueName(std::string_view word);

// The units a number may carry (`30deg`, `0.5rad`), as the lexer reads them.
inline constexpr const char* kUnitNames[] = {"deg", "rad"};

} // namespace moire
