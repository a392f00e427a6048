// Rendering a compiled scene: choose a backend, evaluate the frame, run the kernel.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/Image.h"
#include "runtime/TileExecutor.h"

#include <memory>
#include <string>
#include <vector>

namespace moire {

// Names accepted by --backend, in order of preference.
const std::vector<std::string>& backendNames();

struct BackendOptions {
    int device = -1; // vulkan: the physical device (-1: the first discrete GPU, else the first)
    bool cacheKernels = false; // jit: keep object code on disk between runs (JitCache.h)
};
// Creates a backend by name; returns null for an unknown name. Throws BackendError when the
// backend cannot run here (vulkan: no driver, no usable device, no device `options.device`).
std::unique_ptr<Backend> makeBackend(const std::string& name, const BackendOptions& options = {});

// Renders one frame of `program` whose frame values are `frame`; the image has the kernel's
// outputs as channels (RGBA first).
Image renderFrame(const SceneProgram& program, Backend& backend, const FrameValues& frame,
                  const ExecOptions& options = {});

} // namespace moire
