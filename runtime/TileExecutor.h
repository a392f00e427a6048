// The CPU tile executor: runs a compiled kernel over an image in square tiles on every core.
#pragma once

#include "compiler/backend/Backend.h"
#include "runtime/Image.h"

#include <functional>

namespace moire {

struct ExecOptions {
    int threads = 0; // 0: one per hardware thread
    int tileSize = 64;
    // Called from the calling thread with the fraction of tiles done, about ten times a second.
    std::function<void(double)> progress;
};

// Evaluates `kernel` at every pixel of a width x height image.
Image runKernel(const CompiledKernel& kernel, const KernelFrame& frame,
                const ExecOptions& options = {});

} // namespace moire
