// `-D name=value` from the command line: values that replace a parameter's default or a named
// layer's property before the scene is checked, as if written there. A value is read as an
// expression of the language from the command line itself, so a diagnostic about it points
// into the command line (`<command line>:1:12: error: ...`).
#pragma once

#include <string>
#include <vector>

namespace moire {

struct Define {
    std::string target;      // `name` (a parameter) or `layer.property`
    std::string value;       // the expression's text
    size_t targetOffset = 0; // where `target` begins in Defines::commandLine
    size_t valueOffset = 0;  // where `value` begins in Defines::commandLine
};

struct Defines {
    std::string commandLine; // the command's arguments joined by spaces, as diagnostics show it
    std::vector<Define> list;
    bool empty() const { return list.empty(); }
};

} // namespace moire
