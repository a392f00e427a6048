#include "lsp/Analysis.h"

#include "runtime/FrameEval.h"

#include <fmt/format.h>

namespace moire::lsp {

Analysis analyze(const std::string& path, std::string text) {
    Analysis a;
    a.path = path;
    try {
        a.result = compileScene(path, std::move(text));
        a.diagnostics = a.result.diagnosticList;
        // `moire check` also evaluates the first frame (CheckJson.cpp): a size or a zoom out
        // of range is found there.
        if (a.result.program) {
            FrameValues frame;
            std::string rendered;
            std::vector<LocatedDiagnostic> frameDiags;
            if (evaluateFrame(*a.result.program, FrameRequest{}, frame, rendered, &frameDiags))
                a.uniforms = std::move(frame.uniforms);
            a.diagnostics.insert(a.diagnostics.end(), frameDiags.begin(), frameDiags.end());
        }
    } catch (const std::exception& e) {
        a.result = CompileResult{};
        LocatedDiagnostic d;
        d.id = "InternalError";
        d.message = fmt::format("internal error: {} (please report this with the scene)", e.what());
        d.rendered = "moire: " + d.message + "\n";
        a.diagnostics = {d};
    }
    return a;
}

} // namespace moire::lsp
