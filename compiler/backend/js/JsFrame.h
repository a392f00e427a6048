// The frame program as JavaScript, for the page `moire export` writes: the IR translated op by
// op, as the interpreter runs it (JavaScript's numbers are doubles, as the interpreter's are),
// so that the page computes each frame's uniforms and settings itself while its clock runs
// and its sliders move.
//
// The translation is one expression that evaluates to a function
//     (literals, time, out) => void
// writing the frame program's outputs into `out` (an array of numFrameOutputs numbers) from
// the literal table `literals` and the clock `time` in seconds. It needs nothing else.
#pragma once

#include "compiler/ir/IR.h"

#include <string>

namespace moire::js {

// The function's source. The ops that cannot be in a frame program (the pixel's inputs, the
// kernel's uniforms, the AD markers) raise an internal error: a frame program holding one is
// a bug upstream.
std::string emitFrameJs(const ir::Function& frame);

// Why `op` cannot be translated, or null when it can.
const char* refusal(ir::Op op);

} // namespace moire::js
