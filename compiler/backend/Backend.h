// What every backend provides: a kernel compiled from one IR function that evaluates a
// rectangle of pixels. The CPU tile executor in runtime/ drives it; tests run the same body
// against every backend that is available.
#pragma once

#include "compiler/ir/IR.h"

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>

namespace moire {

struct TileRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0; // half-open pixel rectangle
};

struct KernelFrame {
    const double* uniforms = nullptr; // the frame program's outputs
    int imageW = 0, imageH = 0;
};

// A backend that cannot run here (no Vulkan driver or device, a bad device index) or whose
// device failed while running (lost, out of memory). `what()` is one line for the user; the
// command line reports it as an error, tests skip the backend with it.
class BackendError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

class CompiledKernel {
  public:
    virtual ~CompiledKernel() = default;
    // Writes `numOutputs()` floats per pixel: out[(y - tile.y0) * rowStride + (x - tile.x0) * n +
    // k].
    virtual void runTile(const KernelFrame& frame, TileRect tile, float* out,
                         size_t rowStride) const = 0;
    virtual int numOutputs() const = 0;
    // True for a GPU kernel: it wants as large a rectangle per call as it can get (it splits
    // it to its device's limits and runs the pixels in parallel itself), so the executor
    // hands it the frame in a few horizontal bands from one thread instead of 64 x 64 tiles
    // from every core. runTile stays correct for any rectangle, from any thread.
    virtual bool wholeFrame() const { return false; }
};

class Backend {
  public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    virtual std::unique_ptr<CompiledKernel> compile(const ir::Function& kernel) = 0;
};

} // namespace moire
