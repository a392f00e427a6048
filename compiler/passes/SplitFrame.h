// Splits a scene function into the per-frame program and the per-pixel kernel.
//
// Everything that does not depend on the pixel (literals, the clock, camera maths, layer
// parameters, background colour) moves to the frame program, which the runtime evaluates
// once per frame; what the kernel needs of it arrives as uniform slots. So a scene whose
// numbers change gets new uniforms and keeps its compiled kernel.
//
// Output slots [0, numKernelOutputs) of the scene are per-pixel outputs; higher slots are
// frame settings (image size, ...) and become frame outputs after the uniforms.
#pragma once

#include "compiler/ir/IR.h"

namespace moire::passes {

struct FrameSplit {
    ir::Function frame;  // outputs: uniforms [0, numUniforms), then settings
    ir::Function kernel; // outputs: the per-pixel slots
    int numUniforms = 0;
    int numSettings = 0;
    // Optional settings that depend on the pixel, left out (the frame outputs 0 there).
    std::vector<int> perPixelSettings;
};

// Settings from `firstOptional` on (the values the frame checks) may depend on the pixel:
// such a value cannot be known per frame, and is left out. Any other setting that does is a
// bug.
FrameSplit splitFrame(const ir::Function& scene, int numKernelOutputs, int firstOptional = 1 << 30);

} // namespace moire::passes
