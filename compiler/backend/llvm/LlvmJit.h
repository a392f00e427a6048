// The LLVM backend: translates the IR op by op to LLVM IR in single precision, optimises it,
// and compiles it with the ORC LLJIT into a tile function for the host CPU. Kernels are
// cached by their structural hash, so a scene whose numbers change is not recompiled.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/backend/llvm/ObjectStore.h"

#include <cstddef>
#include <memory>
#include <string>

namespace moire {

class LlvmJitBackend : public Backend {
  public:
    static constexpr size_t kDefaultChunkInsts = 600;

    // LLVM's optimisation of a kernel: Auto, Lean for code in lanes and O2 for scalar code;
    // or one of them for every kernel (moire_pipeline_bench weighs them).
    enum class Pipeline { Auto, O2, O1, Lean };

    struct Options {
        // A kernel of more than `chunkInsts` instructions is compiled as chunks of about that
        // size (backend/llvm/KernelChunks.h), so compile time stays linear in the kernel's size.
        size_t chunkInsts = kDefaultChunkInsts;
        // Chunks are compiled on this many threads at once (0: one per hardware thread).
        int compileThreads = 0;
        // Compile chunked kernels as before (one module on one thread, each chunk looping to
        // the tile's edge, so vectorised with a remainder loop and an epilogue): for
        // moire_compile_bench to compare against. Kernels too small to chunk are the same
        // either way.
        bool classicChunks = false;
        // The vector width given to each chunk's pixel loop as a hint, so the vectoriser does
        // not cost every width (LlvmTranslate.h): kWidestFloatVector, the width its cost model
        // picks for these loops; 0, no hint.
        static constexpr int kWidestFloatVector = -1;
        int chunkVectorWidth = kWidestFloatVector;
        // Pixels per step of the tile function (LlvmTranslate.h): kHostLanes, the floats in
        // the host's widest vector register (16 with AVX-512, 8 with AVX2, 4 with SSE); 1,
        // scalar code (which LLVM's loop vectoriser may still widen where the kernel has no
        // control flow); or 4, 8 or 16.
        static constexpr int kHostLanes = -1;
        int lanes = kHostLanes;
        Pipeline pipeline = Pipeline::Auto;
        // With lanes, an arm of an `if` of at least this many instructions is compiled as a
        // function of its own, once for all arms of the same structure (OutlineRegions.h):
        // the default scene's two walking layers share their solver's code. 0: never.
        static constexpr size_t kDefaultOutlineInsts = 64;
        size_t outlineInsts = kDefaultOutlineInsts;
        // Instruction selection and register allocation at LLVM's -O1 instead of -O2.
        bool codegenLess = false;
        // Object code kept between runs (ObjectStore.h); none: every kernel is compiled.
        std::shared_ptr<ObjectStore> objects;
    };

    explicit LlvmJitBackend(size_t chunkInsts = kDefaultChunkInsts);
    explicit LlvmJitBackend(const Options& options);
    ~LlvmJitBackend() override;

    std::string name() const override { return "jit"; }
    std::unique_ptr<CompiledKernel> compile(const ir::Function& kernel) override;

    // The optimised LLVM IR of a kernel, as text (`moire compile --dump=llvm`).
    std::string dumpLlvm(const ir::Function& kernel);

    // How many kernels were actually compiled (cache misses), for tests and benchmarks.
    int compileCount() const;
    // Modules whose object code came from `Options::objects` instead of being compiled.
    int storeHits() const;
    // Time spent in LLVM's optimisation and in its code generation, summed over the
    // modules compiled (on every thread), for benchmarks.
    struct Seconds {
        double optimise = 0, codegen = 0;
    };
    Seconds llvmSeconds() const;
    // Whether the JIT computes `op` with a call to a libm function (with lanes, to its libmvec
    // version: within 4 ulp, where the scalar functions are within 1).
    static bool callsLibm(ir::Op op);
    // Pixels per step of the tile functions this backend makes (Options::lanes, resolved).
    unsigned lanes() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace moire
