#include "compiler/backend/llvm/ChunkDriver.h"

#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/diag/Diagnostics.h"

#include <algorithm>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Verifier.h>
#include <llvm/Support/raw_ostream.h>

namespace moire::llvmbackend {

void emitChunkDriver(llvm::Module& m, const std::string& name, const ir::Function& kernel,
                     const std::vector<llvm::Function*>& chunks, int numSlots, bool wholeStrip) {
    llvm::LLVMContext& ctx = m.getContext();
    llvm::IRBuilder<> b(ctx);
    auto* i32 = llvm::Type::getInt32Ty(ctx);
    auto* i64 = llvm::Type::getInt64Ty(ctx);
    auto* f32 = llvm::Type::getFloatTy(ctx);
    auto* ptr = llvm::PointerType::get(ctx, 0);
    auto* fnTy = llvm::FunctionType::get(llvm::Type::getVoidTy(ctx),
                                         {ptr, i32, i32, i32, i32, i32, i32, ptr, i64}, false);
    auto* fn = llvm::Function::Create(fnTy, llvm::Function::ExternalLinkage, name, m);
    fn->addFnAttr(llvm::Attribute::NoUnwind);
    auto arg = [&](int i) { return fn->getArg(i); };
    auto block = [&](const char* n) { return llvm::BasicBlock::Create(ctx, n, fn); };
    auto *entry = block("entry"), *yHead = block("y.head"), *yBody = block("y.body"),
         *sHead = block("strip.head"), *sBody = block("strip.body"), *yLatch = block("y.latch"),
         *exit = block("exit");

    b.SetInsertPoint(entry);
    llvm::Value* carry =
        b.CreateAlloca(f32, llvm::ConstantInt::get(i32, std::max(1, numSlots) * kStrip), "carry");
    llvm::Value* stripOut =
        wholeStrip ? b.CreateAlloca(f32, llvm::ConstantInt::get(i32, kernel.numOutputs * kStrip),
                                    "strip.out")
                   : nullptr;
    b.CreateBr(yHead);

    b.SetInsertPoint(yHead);
    auto* y = b.CreatePHI(i32, 2, "y");
    y->addIncoming(arg(4), entry);
    b.CreateCondBr(b.CreateICmpSLT(y, arg(6)), yBody, exit);

    b.SetInsertPoint(yBody);
    llvm::Value* rowOffset = b.CreateMul(b.CreateSExt(b.CreateSub(y, arg(4)), i64), arg(8));
    llvm::Value* row = b.CreateGEP(f32, arg(7), rowOffset, "row");
    llvm::Value* yNext = b.CreateAdd(y, llvm::ConstantInt::get(i32, 1));
    b.CreateBr(sHead);

    b.SetInsertPoint(sHead);
    auto* xs = b.CreatePHI(i32, 2, "xs");
    xs->addIncoming(arg(3), yBody);
    b.CreateCondBr(b.CreateICmpSLT(xs, arg(5)), sBody, yLatch);

    b.SetInsertPoint(sBody);
    llvm::Value* xsNext = b.CreateAdd(xs, llvm::ConstantInt::get(i32, kStrip));
    llvm::Value* xe = b.CreateSelect(b.CreateICmpSLT(xsNext, arg(5)), xsNext, arg(5));
    llvm::Value* out = b.CreateGEP(f32, row,
                                   b.CreateMul(b.CreateSExt(b.CreateSub(xs, arg(3)), i64),
                                               llvm::ConstantInt::get(i64, kernel.numOutputs)));
    for (llvm::Function* chunk : chunks)
        b.CreateCall(chunk, {arg(0), arg(1), arg(2), xs, y, xe, yNext, wholeStrip ? stripOut : out,
                             arg(8), carry});
    if (wholeStrip) {
        llvm::Value* bytes = b.CreateMul(b.CreateSExt(b.CreateSub(xe, xs), i64),
                                         llvm::ConstantInt::get(i64, 4 * kernel.numOutputs));
        b.CreateMemCpy(out, llvm::MaybeAlign(4), stripOut, llvm::MaybeAlign(4), bytes);
    }
    xs->addIncoming(xsNext, sBody);
    b.CreateBr(sHead);

    b.SetInsertPoint(yLatch);
    y->addIncoming(yNext, yLatch);
    b.CreateBr(yHead);

    b.SetInsertPoint(exit);
    b.CreateRetVoid();
    std::string err;
    llvm::raw_string_ostream os(err);
    if (llvm::verifyFunction(*fn, &os)) MOIRE_ICE("LLVM rejected the chunk driver: {}", os.str());
}

} // namespace moire::llvmbackend
