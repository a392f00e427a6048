// Every name the language gives a meaning to, gathered from the tables the front end checks
// against: the lexer's keywords and units, the checker's built-in names, functions and block
// properties, the views, and the standard library's families, fields and easings (read from
// the embedded library itself). `moire names` prints them; the editor packages' highlighting
// is generated from that output (scripts/gen-editor-names.mjs), so no package keeps a list
// of its own.
#pragma once

#include <string>
#include <vector>

namespace moire {

struct BlockNames {
    std::string kind;                    // scene, camera, layer, family, timing
    std::vector<std::string> properties; // in the order of their table
};

struct FamilyNames {
    std::string name;
    std::vector<std::string> params;
    bool builtin = false; // implemented by the compiler (the lattices)
};

struct LanguageNames {
    std::vector<std::string> keywords;   // declaration keywords and `let`
    std::vector<BlockNames> blocks;      // the blocks that take `name = value` properties
    std::vector<std::string> properties; // every block's properties, each once
    std::vector<FamilyNames> families;   // the standard library's, in its order
    std::vector<std::string> functions;  // built-in functions, and `morph`
    std::vector<std::string> fields;     // the standard library's fields
    std::vector<std::string> easings;    // the standard library's easings
    std::vector<std::string> constants;  // pi, tau, e
    std::vector<std::string> variables;  // x, y, r, theta, t; u (easings); spacing (families)
    std::vector<std::string> words;      // bare words some properties take: modes, views, true
    std::vector<std::string> units;      // deg, rad
};

LanguageNames languageNames();

} // namespace moire
