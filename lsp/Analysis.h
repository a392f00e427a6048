// One document as the compiler sees it: the front end's result for its text, and the
// diagnostics `moire check` gives it (the compiler's, then the first frame's), so that the
// editor and the command line can never disagree.
#pragma once

#include "compiler/Compile.h"
#include "compiler/diag/Diagnostics.h"

#include <optional>
#include <string>
#include <vector>

namespace moire::lsp {

struct Analysis {
    std::string path; // the name the diagnostics give the document
    CompileResult result;
    // `moire check`'s diagnostics, in its order.
    std::vector<LocatedDiagnostic> diagnostics;
    // The first frame's values (t = 0), when the scene compiled and they could be evaluated.
    std::optional<std::vector<double>> uniforms;

    // The front end's modules and sources: null only when the compiler failed inside.
    const SceneProgram* frontEnd() const {
        return result.program ? result.program.get() : result.partial.get();
    }
    // The id of the document's own file in frontEnd()->sources.
    uint32_t userFile() const { return frontEnd()->userModule().file; }
    const std::string& text() const { return frontEnd()->sources->file(userFile()).text(); }
};

// Compiles `text` as `moire check` does. Never throws: a bug in moire comes back as one
// diagnostic saying so, with no front end.
Analysis analyze(const std::string& path, std::string text);

} // namespace moire::lsp
