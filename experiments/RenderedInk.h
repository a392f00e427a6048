// The ink a scene draws, as the filter experiments read it: the scene compiled and rendered
// on a backend, each pixel's ink taken as 1 - red (black strokes on white paper), row by row.
// A scene that does not compile or evaluate ends the program (status 2) with its diagnostics.
#pragma once

#include "runtime/output/Render.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace moire::exp {

inline std::vector<double> renderedInk(Backend& backend, const std::string& name,
                                       const std::string& text) {
    CompileResult compiled = compileScene(name, text);
    if (!compiled.program) {
        std::fprintf(stderr, "%s", compiled.diagnostics.c_str());
        std::exit(2);
    }
    FrameValues fv;
    std::string diags;
    if (!evaluateFrame(*compiled.program, FrameRequest{}, fv, diags)) {
        std::fprintf(stderr, "%s", diags.c_str());
        std::exit(2);
    }
    Image img = renderFrame(*compiled.program, backend, fv);
    std::vector<double> out(size_t(img.width) * img.height);
    for (int py = 0; py < img.height; ++py)
        for (int px = 0; px < img.width; ++px)
            out[size_t(py) * img.width + px] = 1.0 - img.at(px, py, 0);
    return out;
}

} // namespace moire::exp
