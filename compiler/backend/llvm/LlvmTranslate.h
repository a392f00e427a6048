// IR -> LLVM IR. Private to the LLVM backend.
#pragma once

#include "compiler/ir/IR.h"

#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <memory>
#include <string>

namespace moire::llvmbackend {

// The generated function has the signature
//   void NAME(const double* uniforms, i32 imageW, i32 imageH, i32 x0, i32 y0, i32 x1, i32 y1,
//             float* out, i64 rowStride)
// and evaluates the kernel for every pixel of the tile [x0, x1) x [y0, y1).
using TileFn = void (*)(const double*, int32_t, int32_t, int32_t, int32_t, int32_t, int32_t, float*,
                        int64_t);

// A kernel of more than `chunkInsts` instructions is compiled in chunks (KernelChunks.h).
std::unique_ptr<llvm::Module> translate(const ir::Function& kernel, const std::string& name,
                                        llvm::LLVMContext& ctx, size_t chunkInsts);

} // namespace moire::llvmbackend
