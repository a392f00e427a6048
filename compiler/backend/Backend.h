// What every backend provides: a kernel compiled from one IR function that evaluates a
// rectangle of pixels. The CPU tile executor in runtime/ drives it; tests run the same body
// against every backend that is available.
#pragma once

#include "compiler/ir/IR.h"

#include <cstddef>
#include <memory>
#include <string>

namespace moire {

struct TileRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0; // half-open pixel rectangle
};

struct KernelFrame {
    const double* uniforms = nullptr; // the frame program's outputs
    int imageW = 0, imageH = 0;
};

class CompiledKernel {
  public:
    virtual ~CompiledKernel() = default;
    // Writes `numOutputs()` floats per pixel: out[(y - tile.y0) * rowStride + (x - tile.x0) * n +
    // k].
    virtual void runTile(const KernelFrame& frame, TileRect tile, float* out,
                         size_t rowStride) const = 0;
    virtual int numOutputs() const = 0;
};

class Backend {
  public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    virtual std::unique_ptr<CompiledKernel> compile(const ir::Function& kernel) = 0;
};

} // namespace moire
