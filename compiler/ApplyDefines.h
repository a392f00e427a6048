// Puts `-D` values (compiler/Defines.h) into the scene's parsed module before it is checked:
// a param's default, or a named layer's property (set, or added when the layer has none).
#pragma once

#include "compiler/Defines.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/parse/Ast.h"

#include <vector>

namespace moire {

// Reads each value from the command line (a source of its own, so diagnostics point into
// it), numbering its literals after the scene's and appending them to `literals`. A target
// the scene does not have, or a value that does not parse, is reported to `diags`.
void applyDefines(const Defines& defines, SourceManager& sm, ast::Module& scene,
                  std::vector<double>& literals, DiagEngine& diags);

} // namespace moire
