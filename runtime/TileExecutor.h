// The executor: runs a compiled kernel over an image, in square tiles on every core for a CPU
// kernel, or in a few whole-width bands from the calling thread for a GPU kernel
// (CompiledKernel::wholeFrame).
#pragma once

#include "compiler/backend/Backend.h"
#include "runtime/Image.h"

#include <functional>

namespace moire {

struct ExecOptions {
    int threads = 0;   // 0: one per hardware thread (CPU kernels)
    int tileSize = 64; // CPU kernels
    // Called from the calling thread with the fraction done: about ten times a second for a
    // CPU kernel, after each of sixteen bands for a GPU kernel; 1.0 at the end.
    std::function<void(double)> progress;
    // Asked between tiles (between bands for a GPU kernel), from any worker thread: once it
    // says true the frame is abandoned and runKernel returns an empty image (width 0). The
    // viewer drops a frame this way when a newer one is wanted.
    std::function<bool()> cancelled;
};

// Evaluates `kernel` at every pixel of a width x height image.
Image runKernel(const CompiledKernel& kernel, const KernelFrame& frame,
                const ExecOptions& options = {});

} // namespace moire
