// Stage (f): a tiny render (two 8 x 8 windows of the frame at t = 0.5) on the interpreter
// (double) and on the LLVM JIT (single precision), compared by RenderCompare.h's rule: the two
// must draw the same picture unless the scene is ill-conditioned in single precision.
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "fuzz/FuzzSupport.h"
#include "fuzz/RenderCompare.h"
#include "runtime/FrameEval.h"

#include <cstdio>
#include <cstdlib>

namespace {
using namespace moire;

constexpr int kNudgeUlps = 4;

// One JIT for the whole run, as the command line keeps one per process; started afresh now and
// then so that the kernels it has compiled (it keeps every one) do not fill the memory.
LlvmJitBackend& jit() {
    static std::unique_ptr<LlvmJitBackend> backend;
    if (!backend || backend->compileCount() >= 256) {
        backend.reset();
        backend = std::make_unique<LlvmJitBackend>();
    }
    return *backend;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("render", [&] {
        CompileResult r = compileScene("fuzz.moire", text);
        if (!r.program) return;
        FrameValues fv;
        std::string diagnostics;
        if (!evaluateFrame(*r.program, FrameRequest{0.5}, fv, diagnostics)) return;
        auto run = [&](const CompiledKernel& k, const std::vector<double>& uniforms) {
            return fuzz::renderWindows(k, uniforms, fv.width, fv.height);
        };

        InterpBackend interp;
        auto reference = interp.compile(r.program->kernel);
        auto compiled = jit().compile(r.program->kernel);
        if (compiled->numOutputs() != reference->numOutputs())
            fuzz::finding("the backends disagree on the number of outputs");
        const size_t stride = reference->numOutputs();
        if (stride < 4) fuzz::finding("a kernel without RGBA");

        std::vector<float> want = run(*reference, fv.uniforms);
        std::vector<float> got = run(*compiled, fv.uniforms);
        static const bool verbose = std::getenv("MOIRE_FUZZ_VERBOSE") != nullptr;
        if (verbose)
            std::fprintf(stderr, "render: %dx%d, JIT off %.3f\n", fv.width, fv.height,
                         fuzz::offFraction(want, got, 4, stride));
        if (fuzz::offFraction(want, got, 4, stride) <= fuzz::kOffFraction) return;
        std::vector<float> rounded = run(*reference, fuzz::floatUniforms(fv.uniforms, 0));
        std::vector<float> nudged = run(*reference, fuzz::floatUniforms(fv.uniforms, kNudgeUlps));
        if (verbose)
            std::fprintf(stderr, "render: float-rounded off %.3f, nudged off %.3f\n",
                         fuzz::offFraction(want, rounded, 4, stride),
                         fuzz::offFraction(want, nudged, 4, stride));
        if (fuzz::judge(want, got, rounded, nudged, 4, stride, fuzz::beyondFloat(fv.uniforms)) ==
            fuzz::Verdict::Differ)
            fuzz::finding("the JIT draws another picture than the interpreter: " +
                          std::to_string(fuzz::offFraction(want, got, 4, stride) * 100) +
                          "% of the samples differ by more than " + std::to_string(fuzz::kOffBy));
    });
    return 0;
}
