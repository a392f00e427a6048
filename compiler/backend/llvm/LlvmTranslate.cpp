#include "compiler/backend/llvm/LlvmTranslate.h"

#include "compiler/backend/llvm/ChunkDriver.h"
#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/backend/llvm/Translator.h"
#include "compiler/diag/Diagnostics.h"

#include <algorithm>
#include <llvm/Analysis/VectorUtils.h>
#include <llvm/IR/Verifier.h>
#include <llvm/Support/raw_ostream.h>

namespace moire::llvmbackend {

using ir::Op;
using ir::ValueId;

Translator::Translator(const ir::Function& f, llvm::Module& m, TranslatorShape shape,
                       Outliner* outliner)
    : f_(f), m_(m), ctx_(m.getContext()), b_(ctx_), vals_(f.numValues(), nullptr),
      invariant_(f.numValues(), 0), shape_(shape), outliner_(outliner) {
    sf_ = llvm::Type::getFloatTy(ctx_);
    si32_ = llvm::Type::getInt32Ty(ctx_);
    i64_ = llvm::Type::getInt64Ty(ctx_);
    llvm::Type* i1 = llvm::Type::getInt1Ty(ctx_);
    auto lanes = [&](llvm::Type* t) -> llvm::Type* {
        return shape_.lanes > 1 ? llvm::FixedVectorType::get(t, shape_.lanes) : t;
    };
    fTy_ = lanes(sf_);
    iTy_ = lanes(si32_);
    bTy_ = lanes(i1);
}

llvm::Function* Translator::run(const std::string& name, const Chunk* chunk, bool wholeStrip,
                                bool external, unsigned vectorWidth) {
    const unsigned lanes = shape_.lanes;
    auto* ptr = llvm::PointerType::get(ctx_, 0);
    std::vector<llvm::Type*> params = {ptr, si32_, si32_, si32_, si32_, si32_, si32_, ptr, i64_};
    if (chunk) params.push_back(ptr);
    auto* fnTy = llvm::FunctionType::get(llvm::Type::getVoidTy(ctx_), params, false);
    fn_ = llvm::Function::Create(fnTy,
                                 chunk && !external ? llvm::Function::InternalLinkage
                                                    : llvm::Function::ExternalLinkage,
                                 name, m_);
    auto arg = [&](int i) { return fn_->getArg(i); };
    uniforms_ = arg(0);
    fn_->addParamAttr(0, llvm::Attribute::NoAlias);
    fn_->addParamAttr(0, llvm::Attribute::ReadOnly);
    fn_->addParamAttr(7, llvm::Attribute::NoAlias);
    fn_->addFnAttr(llvm::Attribute::NoUnwind);
    if (chunk) {
        // Inlined back into the tile function, the chunks would be one huge function again.
        fn_->addFnAttr(llvm::Attribute::NoInline);
        fn_->addParamAttr(9, llvm::Attribute::NoAlias);
        carry_ = arg(9);
    }
    MOIRE_CHECK(lanes == 1 || kStrip % lanes == 0, "LLVM: {} lanes do not divide a strip", lanes);

    entry_ = llvm::BasicBlock::Create(ctx_, "entry", fn_);
    auto* yHead = llvm::BasicBlock::Create(ctx_, "y.head", fn_);
    auto* yBody = llvm::BasicBlock::Create(ctx_, "y.body", fn_);
    auto* xHead = llvm::BasicBlock::Create(ctx_, "x.head", fn_);
    auto* xBody = llvm::BasicBlock::Create(ctx_, "x.body", fn_);
    auto* yLatch = llvm::BasicBlock::Create(ctx_, "y.latch", fn_);
    auto* exit = llvm::BasicBlock::Create(ctx_, "exit", fn_);

    auto splat = [&](llvm::Value* x) { return lanes > 1 ? b_.CreateVectorSplat(lanes, x) : x; };
    b_.SetInsertPoint(entry_);
    imageW_ = splat(b_.CreateSIToFP(arg(1), sf_, "imageW"));
    imageH_ = splat(b_.CreateSIToFP(arg(2), sf_, "imageH"));
    if (lanes > 1)
        for (int k = 0; k < f_.numOutputs; ++k)
            outSlots_.push_back(b_.CreateAlloca(fTy_, nullptr, "out" + std::to_string(k)));
    auto* entryEnd = b_.CreateBr(yHead);
    entryInsert_ = entryEnd; // uniforms are loaded before this branch

    b_.SetInsertPoint(yHead);
    auto* y = b_.CreatePHI(si32_, 2, "y");
    y->addIncoming(arg(4), entry_);
    b_.CreateCondBr(b_.CreateICmpSLT(y, arg(6)), yBody, exit);

    b_.SetInsertPoint(yBody);
    pixelY_ = splat(b_.CreateFAdd(b_.CreateSIToFP(y, sf_), llvm::ConstantFP::get(sf_, 0.5), "py"));
    llvm::Value* rowOffset = b_.CreateMul(b_.CreateSExt(b_.CreateSub(y, arg(4)), i64_), arg(8));
    row_ = b_.CreateGEP(sf_, arg(7), rowOffset, "row");
    b_.CreateBr(xHead);

    b_.SetInsertPoint(xHead);
    wholeStrip = chunk && wholeStrip;
    // Whole strips count lanes from 0 (no overflow: x0 + kStrip fits), so that the trip
    // count is the constant kStrip; otherwise x runs from x0 to x1.
    auto* x = b_.CreatePHI(si32_, 2, wholeStrip ? "lane" : "x");
    x->addIncoming(wholeStrip ? b_.getInt32(0) : static_cast<llvm::Value*>(arg(3)), yBody);
    llvm::Value* xEnd = wholeStrip ? b_.getInt32(kStrip) : static_cast<llvm::Value*>(arg(5));
    b_.CreateCondBr(b_.CreateICmpSLT(x, xEnd), xBody, yLatch);

    b_.SetInsertPoint(xBody);
    llvm::Value* px = wholeStrip ? b_.CreateNSWAdd(arg(3), x, "x") : x;
    llvm::Value* pxf = b_.CreateSIToFP(px, sf_);
    if (lanes == 1) {
        pixelX_ = b_.CreateFAdd(pxf, cf(0.5), "px");
    } else {
        // Lane i is the pixel x + i; its centre, x + i + 1/2, is exact in float (x < 2^24).
        std::vector<llvm::Constant*> offsets, index;
        for (unsigned i = 0; i < lanes; ++i) {
            offsets.push_back(llvm::ConstantFP::get(sf_, i + 0.5));
            index.push_back(b_.getInt32(i));
        }
        pixelX_ = b_.CreateFAdd(splat(pxf), llvm::ConstantVector::get(offsets), "px");
        // The lanes still inside the tile: i < x1 - x (all of them in a whole strip).
        if (!wholeStrip) {
            llvm::Value* left = b_.CreateSub(arg(5), x);
            tail_ = b_.CreateICmpSGT(splat(left), llvm::ConstantVector::get(index), "inside");
            wholeRun_ = b_.CreateICmpSGE(left, b_.getInt32(static_cast<int>(lanes)), "whole");
        }
        exec_ = tail_;
    }
    pixelBase_ = b_.CreateMul(b_.CreateSExt(b_.CreateSub(px, arg(3)), i64_),
                              llvm::ConstantInt::get(i64_, f_.numOutputs));
    beginOutputs(chunk);
    if (chunk) {
        lane_ = wholeStrip ? b_.CreateZExt(x, i64_) : b_.CreateSExt(b_.CreateSub(x, arg(3)), i64_);
        for (const ir::Inst* leaf : chunk->rematerialise) instruction(*leaf);
        for (auto [value, slot] : chunk->loads) vals_[value] = loadCarry(value, slot);
        const auto& insts = f_.blocks[0].insts;
        for (size_t i = chunk->begin; i < chunk->end && insts[i].op != Op::Yield; ++i) {
            instruction(insts[i]);
            for (ValueId r : insts[i].results) {
                auto it = chunk->stores.find(r);
                if (it != chunk->stores.end()) storeCarry(r, it->second);
            }
        }
    } else {
        block(0);
    }
    flushOutputs();
    auto* xNext = wholeStrip ? b_.CreateNSWAdd(x, b_.getInt32(lanes))
                             : b_.CreateAdd(x, llvm::ConstantInt::get(si32_, lanes));
    x->addIncoming(xNext, b_.GetInsertBlock());
    auto* backEdge = b_.CreateBr(xHead);
    if (lanes > 1) {
        // Already in lanes: the vectoriser has nothing to do but spend time finding that out.
        loopMetadata(backEdge, "llvm.loop.vectorize.enable", 0);
    } else if (wholeStrip && vectorWidth > 1 && !callsLibm_) {
        // Not where the chunk calls libm: libmvec has 4- and 8-lane versions only, and a wider
        // hint would call the scalar function once per lane; the cost model weighs that.
        loopMetadata(backEdge, "llvm.loop.vectorize.width", vectorWidth);
    }

    b_.SetInsertPoint(yLatch);
    auto* yNext = b_.CreateAdd(y, llvm::ConstantInt::get(si32_, 1));
    y->addIncoming(yNext, yLatch);
    b_.CreateBr(yHead);

    b_.SetInsertPoint(exit);
    b_.CreateRetVoid();

    std::string err;
    llvm::raw_string_ostream os(err);
    if (llvm::verifyFunction(*fn_, &os)) MOIRE_ICE("LLVM rejected the kernel: {}", os.str());
    return fn_;
}

// Loop metadata on the back edge, e.g. llvm.loop.vectorize.width (a distinct,
// self-referencing node, as LLVM's loop metadata must be).
void Translator::loopMetadata(llvm::BranchInst* backEdge, const char* key, unsigned value) {
    llvm::Metadata* hint[] = {llvm::MDString::get(ctx_, key),
                              llvm::ConstantAsMetadata::get(b_.getInt32(value))};
    auto self = llvm::MDNode::getTemporary(ctx_, std::nullopt);
    llvm::Metadata* ops[] = {self.get(), llvm::MDNode::get(ctx_, hint)};
    llvm::MDNode* loop = llvm::MDNode::getDistinct(ctx_, ops);
    loop->replaceOperandWith(0, loop);
    backEdge->setMetadata(llvm::LLVMContext::MD_loop, loop);
}

// A carried value is one 32-bit word per pixel of the strip: a float, an int, or a bool
// widened to an int. With lanes, a run's words are neighbours: one vector load or store.
llvm::Value* Translator::carrySlot(ValueId v, int slot) {
    llvm::Type* word = f_.type(v) == ir::Type::F ? sf_ : si32_;
    llvm::Value* at = b_.CreateAdd(lane_, llvm::ConstantInt::get(i64_, int64_t{slot} * kStrip));
    return b_.CreateGEP(word, carry_, at);
}
void Translator::storeCarry(ValueId v, int slot) {
    llvm::Value* x = vals_[v];
    if (f_.type(v) == ir::Type::B) x = b_.CreateZExt(x, iTy_);
    b_.CreateAlignedStore(x, carrySlot(v, slot), llvm::Align(4));
}
llvm::Value* Translator::loadCarry(ValueId v, int slot) {
    llvm::Value* p = carrySlot(v, slot);
    if (f_.type(v) == ir::Type::F) return b_.CreateAlignedLoad(fTy_, p, llvm::Align(4));
    llvm::Value* x = b_.CreateAlignedLoad(iTy_, p, llvm::Align(4));
    return f_.type(v) == ir::Type::B ? b_.CreateICmpNE(x, llvm::ConstantInt::get(iTy_, 0)) : x;
}

// With lanes, outputs are stored once per run of pixels, interleaved as the image holds
// them (pixel-major): one vector store, masked at the tile's right edge. Where the function
// does not write every slot unconditionally (a chunk writes only its own; a slot written
// inside an `if`), the run's old values are loaded first, so the lanes and slots it leaves
// alone keep what they held, as with one lane.
void Translator::beginOutputs(const Chunk* chunk) {
    if (shape_.lanes == 1 || f_.numOutputs == 0) return;
    // Slots written at the top level (every lane), and anywhere (in a region too).
    std::vector<char> always(f_.numOutputs, 0);
    bool any = false;
    auto scan = [&](auto& self, ir::BlockId id, size_t begin, size_t end) -> void {
        const auto& insts = f_.blocks[id].insts;
        for (size_t i = begin; i < end && i < insts.size(); ++i) {
            if (insts[i].op == Op::Output) {
                any = true;
                if (id == 0) always[insts[i].iimm] = 1;
            }
            for (ir::BlockId r : insts[i].regions) self(self, r, 0, f_.blocks[r].insts.size());
        }
    };
    scan(scan, 0, chunk ? chunk->begin : 0, chunk ? chunk->end : f_.blocks[0].insts.size());
    writesOutputs_ = any;
    if (!any || std::find(always.begin(), always.end(), 0) == always.end()) return;
    const unsigned lanes = shape_.lanes, n = static_cast<unsigned>(f_.numOutputs);
    auto* runTy = llvm::FixedVectorType::get(sf_, lanes * n);
    llvm::Value* at = b_.CreateGEP(sf_, row_, pixelBase_);
    llvm::Value* old = nullptr;
    if (tail_)
        old = b_.CreateMaskedLoad(runTy, at, llvm::Align(4), runMask(),
                                  llvm::Constant::getNullValue(runTy));
    else
        old = b_.CreateAlignedLoad(runTy, at, llvm::Align(4));
    for (unsigned k = 0; k < n; ++k)
        b_.CreateStore(b_.CreateShuffleVector(old, llvm::createStrideMask(k, n, lanes)),
                       outSlots_[k]);
}

// The tail mask with each lane's bit repeated for each of its output slots.
llvm::Value* Translator::runMask() {
    return b_.CreateShuffleVector(tail_, llvm::createReplicatedMask(f_.numOutputs, shape_.lanes));
}

void Translator::output(const ir::Inst& inst) {
    llvm::Value* x = v(inst.args[0]);
    if (shape_.lanes == 1) {
        llvm::Value* idx = b_.CreateAdd(pixelBase_, llvm::ConstantInt::get(i64_, inst.iimm));
        b_.CreateStore(x, b_.CreateGEP(sf_, row_, idx));
        return;
    }
    llvm::AllocaInst* slot = outSlots_[inst.iimm];
    // Inside a region, only the lanes that run it write.
    if (regionDepth_ > 0 && exec_) x = b_.CreateSelect(exec_, x, b_.CreateLoad(fTy_, slot));
    b_.CreateStore(x, slot);
}

void Translator::flushOutputs() {
    if (shape_.lanes == 1 || !writesOutputs_) return;
    const unsigned lanes = shape_.lanes, n = static_cast<unsigned>(f_.numOutputs);
    std::vector<llvm::Value*> slots;
    for (llvm::AllocaInst* slot : outSlots_) slots.push_back(b_.CreateLoad(fTy_, slot));
    llvm::Value* run = n == 1 ? slots[0]
                              : b_.CreateShuffleVector(llvm::concatenateVectors(b_, slots),
                                                       llvm::createInterleaveMask(lanes, n));
    llvm::Value* at = b_.CreateGEP(sf_, row_, pixelBase_);
    if (!tail_) {
        b_.CreateAlignedStore(run, at, llvm::Align(4));
        return;
    }
    // Every run but the last of a tile's row is whole: a plain store there, and the masked
    // one (with its mask widened to every output slot) only at the tile's edge.
    llvm::Function* fn = b_.GetInsertBlock()->getParent();
    auto* whole = llvm::BasicBlock::Create(ctx_, "store.whole", fn);
    auto* edge = llvm::BasicBlock::Create(ctx_, "store.edge", fn);
    auto* stored = llvm::BasicBlock::Create(ctx_, "stored", fn);
    b_.CreateCondBr(wholeRun_, whole, edge);
    b_.SetInsertPoint(whole);
    b_.CreateAlignedStore(run, at, llvm::Align(4));
    b_.CreateBr(stored);
    b_.SetInsertPoint(edge);
    b_.CreateMaskedStore(run, at, llvm::Align(4), runMask());
    b_.CreateBr(stored);
    b_.SetInsertPoint(stored);
}

std::vector<OwnedModule> translate(const ir::Function& kernel, const std::string& name,
                                   const TranslateOptions& options) {
    std::vector<OwnedModule> out;
    auto newModule = [&](const std::string& moduleName) -> llvm::Module& {
        OwnedModule& om = out.emplace_back();
        om.ctx = std::make_unique<llvm::LLVMContext>();
        om.module = std::make_unique<llvm::Module>(moduleName, *om.ctx);
        return *om.module;
    };
    TranslatorShape shape{.lanes = std::max(1u, options.lanes), .vectorMaths = options.vectorMaths};
    // Arms as functions: with lanes only (a call in a scalar pixel loop would keep LLVM's
    // vectoriser from it), packed into modules of their own (Translator.h: Outliner).
    const bool outline = shape.lanes > 1 && options.outlineInsts > 0 && options.separateModules;
    Outliner outliner{.prefix = name,
                      .minInsts = options.outlineInsts,
                      .binInsts = options.chunkInsts,
                      .newModule = newModule,
                      .names = {},
                      .bins = {}};
    Outliner* arms = outline ? &outliner : nullptr;
    ChunkPlan plan = planChunks(kernel, options.chunkInsts, outline ? options.outlineInsts : 0);
    if (plan.chunks.size() == 1) {
        Translator(kernel, newModule(name), shape, arms).run(name);
        return out;
    }
    bool split = options.separateModules, whole = options.wholeStrips;
    llvm::Module& driver = newModule(name);
    std::vector<llvm::Function*> chunks;
    for (size_t c = 0; c < plan.chunks.size(); ++c) {
        std::string chunkName = name + ".chunk" + std::to_string(c);
        llvm::Function* fn =
            Translator(kernel, split ? newModule(chunkName) : driver, shape, arms)
                .run(chunkName, &plan.chunks[c], whole, split, options.chunkVectorWidth);
        // In a module of its own, the driver calls the chunk through a declaration.
        if (split) {
            llvm::LLVMContext& ctx = driver.getContext();
            llvm::Type *ptr = llvm::PointerType::get(ctx, 0), *i32 = llvm::Type::getInt32Ty(ctx);
            auto* fnTy = llvm::FunctionType::get(
                llvm::Type::getVoidTy(ctx),
                {ptr, i32, i32, i32, i32, i32, i32, ptr, llvm::Type::getInt64Ty(ctx), ptr}, false);
            fn = llvm::Function::Create(fnTy, llvm::Function::ExternalLinkage, chunkName, driver);
            fn->addFnAttr(llvm::Attribute::NoUnwind);
        }
        chunks.push_back(fn);
    }
    emitChunkDriver(driver, name, kernel, chunks, plan.numSlots, whole);
    return out;
}

} // namespace moire::llvmbackend
