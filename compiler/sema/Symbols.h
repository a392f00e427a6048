// The scene's own names and where they are, for an editor (go to definition, find references,
// rename): the declarations of the user's fields, families, timings, easings, layers, family
// parameters and lets, and every reference the checks resolved to them.
//
// Built from the parsed modules after the checks, whether or not they found errors: a name
// they did not resolve has no reference, and when the scene did not parse (the checks do not
// run) the table lists the declarations the parser read, with no references.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/parse/Ast.h"

#include <string>
#include <string_view>
#include <vector>

namespace moire::sema {

// Param is a family's parameter; SceneParam a top-level `param` declaration.
enum class SymbolKind : uint8_t { Field, Family, Timing, Easing, Layer, Param, Let, SceneParam };
const char* symbolKindName(SymbolKind k); // "field", "family", ... "parameter", "let", "param"

struct Symbol {
    SymbolKind kind;
    std::string name;
    SourceRange declaration;             // its name where it is declared (maybe the library's)
    const ast::Decl* decl;               // its declaration; for a parameter or let, the family's
    int index = -1;                      // a parameter's or let's index in its family
    std::vector<SourceRange> references; // names in the user's module that refer to it, in order
};

struct SymbolTable {
    // The user's declarations in source order, then the library's that the user's module
    // names (circles, cubic_in_out...), in the order first named.
    std::vector<Symbol> symbols;

    // The symbol declared or referred to at `loc`, or null.
    const Symbol* at(SourceLoc loc) const;
    // The user's or library's symbol of that kind and name, or null (parameters and lets:
    // the first of that name).
    const Symbol* find(SymbolKind kind, std::string_view name) const;
};

// The symbols of `modules.back()`, the user's module (the others are the library's).
SymbolTable collectSymbols(const std::vector<const ast::Module*>& modules);

} // namespace moire::sema
