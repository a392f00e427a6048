// Runs a small kernel built in a test at one pixel on a named backend, with the uniforms the
// test chooses: how the tests of the per-pixel maths (Characters_test, RatioView_test) hold
// every backend to the same numbers. A backend that cannot run here skips (Skip.h).
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/ir/Builder.h"
#include "compiler/passes/AutoDiff.h"
#include "compiler/passes/Simplify.h"
#include "tests/support/Support.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace moire::test {

class KernelProbe {
  public:
    // Builds the kernel with `body`, which writes `numOutputs` outputs. With `derive`, the
    // body may take derivatives (Op::DerivX, DerivY) of values it marks independent
    // (Op::Indep), and the AD pass resolves them as the compiler does (Compile.cpp: simplify,
    // AD, simplify) before a backend sees the kernel.
    KernelProbe(int numOutputs, const std::function<void(ir::Builder&)>& body,
                bool derive = false) {
        f_.name = "probe";
        f_.numOutputs = numOutputs;
        ir::Builder b(f_);
        body(b);
        ir::verify(f_);
        if (derive) f_ = passes::simplify(passes::autoDiff(passes::simplify(f_)));
    }
    // Compiles it on `backend`; false (after a skip note) where that backend cannot run here.
    bool use(const std::string& backend) {
        kernel_.reset(); // before the backend that owns its code
        backend_ = makeBackendOrSkip(backend);
        if (!backend_) return false;
        kernel_ = backend_->compile(f_);
        return true;
    }
    std::vector<double> run(const std::vector<double>& uniforms) const {
        std::vector<float> out(static_cast<size_t>(f_.numOutputs));
        KernelFrame frame;
        frame.uniforms = uniforms.data();
        frame.imageW = 1;
        frame.imageH = 1;
        kernel_->runTile(frame, TileRect{0, 0, 1, 1}, out.data(), out.size());
        return {out.begin(), out.end()};
    }

  private:
    ir::Function f_;
    std::unique_ptr<Backend> backend_;
    std::unique_ptr<CompiledKernel> kernel_; // compiled by backend_
};

// The backends these tests hold to the same expectations: the reference interpreter, the JIT
// and the GPU (each skipped where it cannot run).
inline const std::vector<std::string>& probeBackends() {
    static const std::vector<std::string> names = {"interp", "jit", "vulkan"};
    return names;
}

} // namespace moire::test
