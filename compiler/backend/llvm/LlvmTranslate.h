// IR -> LLVM IR. Private to the LLVM backend.
#pragma once

#include "compiler/ir/IR.h"

#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <memory>
#include <string>
#include <vector>

namespace moire::llvmbackend {

// The generated function has the signature
//   void NAME(const double* uniforms, i32 imageW, i32 imageH, i32 x0, i32 y0, i32 x1, i32 y1,
//             float* out, i64 rowStride)
// and evaluates the kernel for every pixel of the tile [x0, x1) x [y0, y1).
using TileFn = void (*)(const double*, int32_t, int32_t, int32_t, int32_t, int32_t, int32_t, float*,
                        int64_t);

// A module with the context it lives in (declared first, so destroyed last).
struct OwnedModule {
    std::unique_ptr<llvm::LLVMContext> ctx;
    std::unique_ptr<llvm::Module> module;
};

struct TranslateOptions {
    // A kernel of more than `chunkInsts` instructions is compiled in chunks (KernelChunks.h).
    size_t chunkInsts = 600;
    // Chunks run whole strips (a constant trip count: the vectoriser emits the pixel body once).
    bool wholeStrips = true;
    // Each chunk in a module (and context) of its own, so chunks can be compiled in parallel.
    bool separateModules = true;
    // The vector width (pixels per SIMD iteration) the pixel loop of a whole-strip chunk is
    // given as a hint (not where the chunk calls libm); 0 leaves the choice to the vectoriser's
    // cost model.
    unsigned chunkVectorWidth = 0;
    // Pixels per step of the tile function's own translation (Translator.h): 1, scalar
    // values (the vectoriser may widen straight-line kernels); 4, 8 or 16, vectors of that many
    // pixels, with `if` and `loop` run under masks.
    unsigned lanes = 1;
    // Lane-wide libm calls go to glibc's libmvec (loaded in the process; 4, 8 or 16 lanes);
    // otherwise each lane calls the scalar function.
    bool vectorMaths = false;
    // With lanes (and separate modules), an arm of an `if` of at least this many instructions
    // is compiled as a function of its own, once for all arms of its structure
    // (OutlineRegions.h); 0: never.
    // The arms are packed into modules of up to `chunkInsts` instructions (Translator.h).
    size_t outlineInsts = 0;
};

// Whether the translation computes `op` with a call to a libm function (with lanes, to its
// libmvec version: within 4 ulp, where the scalar functions are within 1).
bool callsLibm(ir::Op op);

// The module of tile function NAME; for a chunked kernel, the driver's module first, then one
// per chunk where options.separateModules; then the outlined arms' modules.
std::vector<OwnedModule> translate(const ir::Function& kernel, const std::string& name,
                                   const TranslateOptions& options);

} // namespace moire::llvmbackend
