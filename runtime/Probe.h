// Evaluating a scene at chosen world points rather than over an image: the kernel outputs
// (colour, and each layer's index, distance and gradient) at (x, y). Tests use it to hold
// backends and families to independent expectations; tools can use it to show values.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/Compile.h"

#include <memory>
#include <vector>

namespace moire {

class Prober {
  public:
    // `program` must be compiled in CompileOptions::Mode::Probe (and usually with layerFields).
    // With `backend` null the reference interpreter evaluates the kernel in double precision;
    // otherwise the backend's compiled kernel does (in its own precision).
    Prober(const SceneProgram& program, Backend* backend);

    // All kernel outputs at world point (x, y), at clock time t.
    std::vector<double> at(double x, double y, double t = 0.0);

    // Replaces the value of the scene's literal `slot` (its numbers in source order; see
    // SceneProgram::literals) for the following calls, so that one compiled program can be
    // probed at many parameter settings: the kernel's structure does not depend on them.
    void setLiteral(int slot, double value);
    double literal(int slot) const { return literals_.at(slot); }

  private:
    const SceneProgram& program_;
    std::vector<double> literals_;
    std::unique_ptr<CompiledKernel> compiled_;
    Interpreter frame_;
    std::unique_ptr<Interpreter> exact_;
    std::vector<double> regs_;
};

} // namespace moire
