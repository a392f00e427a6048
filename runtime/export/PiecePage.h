// The page `moire export` writes: one self-contained HTML file that draws a compiled scene
// with WebGL2, its clock and its parameters under the picture (docs/export.md).
//
// The page carries the scene as the compiler left it, translated twice: the pixel kernel as a
// GLSL ES 3.00 fragment shader (glsl::emitGlsl, Dialect::WebGl) and the frame program as
// JavaScript (js::emitFrameJs), with the literal table and what the page must know of the
// frame program's outputs (how many are uniforms, which settings to check). Its HTML and
// script are plain files (runtime/export/page/), built into the binary.
#pragma once

#include "compiler/Compile.h"

#include <string>

namespace moire {

struct PieceOptions {
    std::string title;         // the scene's name, shown as the page's title
    int width = 0, height = 0; // the canvas, in pixels
    double time = 0.0;         // the clock when the page opens
    bool playing = true;       // whether the clock runs when the page opens
    double loop = 0.0;         // the clock's span: it wraps here (0: it runs on)
    bool moves = false;        // whether the picture changes with the clock at all
};

// The page's HTML. `program` must be compiled in the render mode without layer fields.
std::string piecePage(const SceneProgram& program, const PieceOptions& options);

} // namespace moire
