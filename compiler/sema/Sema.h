// Semantic checks: names, arity, types and units, and which expressions may depend on the
// position or the clock. The result points into the checked modules, annotated in place.
#pragma once

#include "compiler/diag/Diagnostics.h"
#include "compiler/parse/Ast.h"

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace moire::sema {

struct CheckedFamily {
    const ast::Decl* decl = nullptr;
    const ast::Expr* phase = nullptr;
    std::optional<int> first; // lowest member index, when the family excludes some
};

struct CheckedLayer {
    const ast::Decl* decl = nullptr;
    const CheckedFamily* family = nullptr;     // a named family, or null
    const ast::Expr* anonymousPhase = nullptr; // `family = <expression>`
    // One entry per parameter of the family: the layer's value, or null for the default.
    std::vector<const ast::Expr*> args;
    const ast::Expr* prop(std::string_view name) const {
        const ast::Property* p = decl->prop(name);
        return p ? p->value.get() : nullptr;
    }
};

struct CheckedScene {
    const ast::Decl* scene = nullptr;
    const ast::Decl* camera = nullptr;
    std::vector<CheckedLayer> layers;
    std::unordered_map<const ast::Decl*, CheckedFamily> families;
    std::unordered_map<std::string, const ast::Decl*> familyByName;
};

// One property a block accepts.
struct PropertySpec {
    const char* name;
    ast::Type type;
    bool positionFree; // may not depend on x, y
    bool timeFree;     // may not depend on t
    const char* doc;
};
const std::vector<PropertySpec>& sceneProperties();
const std::vector<PropertySpec>& cameraProperties();
const std::vector<PropertySpec>& layerProperties(); // `family` is listed with type Error

// Checks the standard library modules and the user's module together. Errors go to
// `diags`; the result is meaningful only when no error was reported.
CheckedScene check(const std::vector<ast::Module*>& modules, DiagEngine& diags);

} // namespace moire::sema
