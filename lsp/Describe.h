// The words hover and completion show for a name: a signature or declaration line, and the
// one-line meaning from the tables the checks read (sema/Builtins.h, sema/Properties.h,
// sema/Views.h) or, for what a .moire file declares, the comment above its declaration.
#pragma once

#include "compiler/Compile.h"
#include "compiler/sema/Builtins.h"
#include "compiler/sema/Properties.h"

#include <string>
#include <string_view>

namespace moire::lsp {

struct Description {
    std::string signature; // shown as code
    std::string meaning;   // one line or a comment, as prose
};

Description describeFunction(const sema::FnInfo& fn);
Description describeBuiltinName(const sema::NameInfo& name);
// `block` names the table the property is from ("layer", "scene", "timing"...).
Description describeProperty(const sema::PropertySpec& spec, const char* block);
// A declaration of the scene or the library: its first line as written, and the comment
// lines just above it.
Description describeDecl(const SceneProgram& program, const ast::Decl& decl);
// A family's parameter, as a layer sets it.
Description describeParam(const SceneProgram& program, const ast::Decl& family, int index);
// A top-level `param`: its declaration as written (value, range, step and unit), its type and
// what its range, step and unit do, and the comment above it.
Description describeSceneParam(const SceneProgram& program, const ast::Decl& param);
// `in`, `step` or `unit` after a param's value.
Description describeParamClause(std::string_view word);

// The table of properties of a block of that kind (null for field, family and easing, which
// have none but the family body's).
const std::vector<sema::PropertySpec>* propertyTable(ast::DeclKind kind);

// "a number", "an angle (write deg or rad)"... with units.
std::string typeWithUnits(ast::Type t);

} // namespace moire::lsp
