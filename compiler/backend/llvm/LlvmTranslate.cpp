#include "compiler/backend/llvm/LlvmTranslate.h"

#include "compiler/backend/llvm/ChunkDriver.h"
#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <llvm/IR/Intrinsics.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Verifier.h>
#include <llvm/Support/raw_ostream.h>
#include <unordered_map>

namespace moire::llvmbackend {

using ir::Op;
using ir::ValueId;

namespace {

class Translator {
  public:
    Translator(const ir::Function& f, llvm::Module& m)
        : f_(f), m_(m), ctx_(m.getContext()), b_(ctx_), vals_(f.numValues(), nullptr) {
        fTy_ = llvm::Type::getFloatTy(ctx_);
        i32_ = llvm::Type::getInt32Ty(ctx_);
        i64_ = llvm::Type::getInt64Ty(ctx_);
    }

    // The tile function of the whole kernel, or with `chunk`, the function of one chunk: the
    // same loop over the tile's pixels, with a tenth parameter, the strip's carry buffer.
    // With `wholeStrip`, a chunk runs kStrip pixels from x0 whatever x1 is: a constant trip
    // count that the vectoriser divides exactly, so it emits neither a scalar remainder loop
    // nor a vectorised epilogue, each as big as the body (the driver clips the outputs).
    //
    // With `vectorWidth`, a whole-strip chunk's pixel loop carries that width as a hint. The
    // vectoriser then plans that one width instead of costing every width the target offers,
    // which was a third of LLVM's optimisation time for a kernel of 1,000 layers; the driver
    // passes the width its cost model picks for these loops (the widest float vector).
    llvm::Function* run(const std::string& name, const Chunk* chunk = nullptr,
                        bool wholeStrip = false, bool external = false, unsigned vectorWidth = 0) {
        auto* ptr = llvm::PointerType::get(ctx_, 0);
        std::vector<llvm::Type*> params = {ptr, i32_, i32_, i32_, i32_, i32_, i32_, ptr, i64_};
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

        entry_ = llvm::BasicBlock::Create(ctx_, "entry", fn_);
        auto* yHead = llvm::BasicBlock::Create(ctx_, "y.head", fn_);
        auto* yBody = llvm::BasicBlock::Create(ctx_, "y.body", fn_);
        auto* xHead = llvm::BasicBlock::Create(ctx_, "x.head", fn_);
        auto* xBody = llvm::BasicBlock::Create(ctx_, "x.body", fn_);
        auto* yLatch = llvm::BasicBlock::Create(ctx_, "y.latch", fn_);
        auto* exit = llvm::BasicBlock::Create(ctx_, "exit", fn_);

        b_.SetInsertPoint(entry_);
        imageW_ = b_.CreateSIToFP(arg(1), fTy_, "imageW");
        imageH_ = b_.CreateSIToFP(arg(2), fTy_, "imageH");
        auto* entryEnd = b_.CreateBr(yHead);
        entryInsert_ = entryEnd; // uniforms are loaded before this branch

        b_.SetInsertPoint(yHead);
        auto* y = b_.CreatePHI(i32_, 2, "y");
        y->addIncoming(arg(4), entry_);
        b_.CreateCondBr(b_.CreateICmpSLT(y, arg(6)), yBody, exit);

        b_.SetInsertPoint(yBody);
        pixelY_ = b_.CreateFAdd(b_.CreateSIToFP(y, fTy_), cf(0.5), "py");
        llvm::Value* rowOffset = b_.CreateMul(b_.CreateSExt(b_.CreateSub(y, arg(4)), i64_), arg(8));
        row_ = b_.CreateGEP(fTy_, arg(7), rowOffset, "row");
        b_.CreateBr(xHead);

        b_.SetInsertPoint(xHead);
        wholeStrip = chunk && wholeStrip;
        // Whole strips count lanes from 0 (no overflow: x0 + kStrip fits), so that the trip
        // count is the constant kStrip; otherwise x runs from x0 to x1.
        auto* x = b_.CreatePHI(i32_, 2, wholeStrip ? "lane" : "x");
        x->addIncoming(wholeStrip ? b_.getInt32(0) : static_cast<llvm::Value*>(arg(3)), yBody);
        llvm::Value* xEnd = wholeStrip ? b_.getInt32(kStrip) : static_cast<llvm::Value*>(arg(5));
        b_.CreateCondBr(b_.CreateICmpSLT(x, xEnd), xBody, yLatch);

        b_.SetInsertPoint(xBody);
        llvm::Value* px = wholeStrip ? b_.CreateNSWAdd(arg(3), x, "x") : x;
        pixelX_ = b_.CreateFAdd(b_.CreateSIToFP(px, fTy_), cf(0.5), "px");
        pixelBase_ = b_.CreateMul(b_.CreateSExt(b_.CreateSub(px, arg(3)), i64_),
                                  llvm::ConstantInt::get(i64_, f_.numOutputs));
        if (chunk) {
            lane_ =
                wholeStrip ? b_.CreateZExt(x, i64_) : b_.CreateSExt(b_.CreateSub(x, arg(3)), i64_);
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
        auto* xNext = wholeStrip ? b_.CreateNSWAdd(x, b_.getInt32(1))
                                 : b_.CreateAdd(x, llvm::ConstantInt::get(i32_, 1));
        x->addIncoming(xNext, b_.GetInsertBlock());
        auto* backEdge = b_.CreateBr(xHead);
        // Not where the chunk calls libm: libmvec has 4- and 8-lane versions only, and a wider
        // hint would call the scalar function once per lane; the cost model weighs that.
        if (wholeStrip && vectorWidth > 1 && !callsLibm_) hintVectorWidth(backEdge, vectorWidth);

        b_.SetInsertPoint(yLatch);
        auto* yNext = b_.CreateAdd(y, llvm::ConstantInt::get(i32_, 1));
        y->addIncoming(yNext, yLatch);
        b_.CreateBr(yHead);

        b_.SetInsertPoint(exit);
        b_.CreateRetVoid();

        std::string err;
        llvm::raw_string_ostream os(err);
        if (llvm::verifyFunction(*fn_, &os)) MOIRE_ICE("LLVM rejected the kernel: {}", os.str());
        return fn_;
    }

  private:
    // Loop metadata on the back edge: llvm.loop.vectorize.width (a distinct, self-referencing
    // node, as LLVM's loop metadata must be).
    void hintVectorWidth(llvm::BranchInst* backEdge, unsigned width) {
        llvm::Metadata* hint[] = {
            llvm::MDString::get(ctx_, "llvm.loop.vectorize.width"),
            llvm::ConstantAsMetadata::get(llvm::ConstantInt::get(i32_, width))};
        auto self = llvm::MDNode::getTemporary(ctx_, std::nullopt);
        llvm::Metadata* ops[] = {self.get(), llvm::MDNode::get(ctx_, hint)};
        llvm::MDNode* loop = llvm::MDNode::getDistinct(ctx_, ops);
        loop->replaceOperandWith(0, loop);
        backEdge->setMetadata(llvm::LLVMContext::MD_loop, loop);
    }

    // A carried value is one 32-bit word per pixel of the strip: a float, an int, or a bool
    // widened to an int.
    llvm::Value* carrySlot(ValueId v, int slot) {
        llvm::Type* word = f_.type(v) == ir::Type::F ? fTy_ : i32_;
        llvm::Value* at = b_.CreateAdd(lane_, llvm::ConstantInt::get(i64_, int64_t{slot} * kStrip));
        return b_.CreateGEP(word, carry_, at);
    }
    void storeCarry(ValueId v, int slot) {
        llvm::Value* x = vals_[v];
        if (f_.type(v) == ir::Type::B) x = b_.CreateZExt(x, i32_);
        b_.CreateStore(x, carrySlot(v, slot));
    }
    llvm::Value* loadCarry(ValueId v, int slot) {
        llvm::Value* p = carrySlot(v, slot);
        if (f_.type(v) == ir::Type::F) return b_.CreateLoad(fTy_, p);
        llvm::Value* x = b_.CreateLoad(i32_, p);
        return f_.type(v) == ir::Type::B ? b_.CreateICmpNE(x, llvm::ConstantInt::get(i32_, 0)) : x;
    }

    llvm::Constant* cf(double v) { return llvm::ConstantFP::get(fTy_, v); }
    llvm::Value* v(ValueId id) {
        MOIRE_CHECK(vals_[id], "LLVM: %{} used before definition", id);
        return vals_[id];
    }

    llvm::Value* intrinsic(llvm::Intrinsic::ID id, std::initializer_list<llvm::Value*> args) {
        llvm::Function* fn = llvm::Intrinsic::getDeclaration(&m_, id, {fTy_});
        return b_.CreateCall(fn, args);
    }
    // A libm function of one or two floats (sinf, atan2f, ...), resolved in the host process.
    llvm::Value* libm(const char* name, std::initializer_list<llvm::Value*> args) {
        callsLibm_ = true;
        std::vector<llvm::Type*> params(args.size(), fTy_);
        auto callee = m_.getOrInsertFunction(name, llvm::FunctionType::get(fTy_, params, false));
        if (auto* fn = llvm::dyn_cast<llvm::Function>(callee.getCallee())) {
            // Kernels never read errno, so to them these are pure functions; saying so lets
            // LLVM hoist and vectorise the calls.
            fn->setDoesNotThrow();
            fn->setDoesNotAccessMemory();
            fn->setWillReturn();
        }
        return b_.CreateCall(callee, args);
    }
    // The shared semantics' min and max (Semantics.h): b < a ? b : a, b > a ? b : a.
    llvm::Value* semMin(llvm::Value* a, llvm::Value* bv) {
        return b_.CreateSelect(b_.CreateFCmpOLT(bv, a), bv, a);
    }
    llvm::Value* semMax(llvm::Value* a, llvm::Value* bv) {
        return b_.CreateSelect(b_.CreateFCmpOGT(bv, a), bv, a);
    }
    llvm::Value* floorOf(llvm::Value* a) { return intrinsic(llvm::Intrinsic::floor, {a}); }
    // hypot without libm's call: big * sqrt(1 + (small / big)^2), which neither overflows
    // nor underflows; 0 at the origin and inf when either side is infinite, as hypotf.
    llvm::Value* hypot(llvm::Value* a, llvm::Value* bv) {
        llvm::Value* x = intrinsic(llvm::Intrinsic::fabs, {a});
        llvm::Value* y = intrinsic(llvm::Intrinsic::fabs, {bv});
        llvm::Value* big = intrinsic(llvm::Intrinsic::maxnum, {x, y});
        llvm::Value* small = intrinsic(llvm::Intrinsic::minnum, {x, y});
        llvm::Value* q = b_.CreateFDiv(small, big);
        llvm::Value* h = b_.CreateFMul(
            big, intrinsic(llvm::Intrinsic::sqrt, {b_.CreateFAdd(cf(1), b_.CreateFMul(q, q))}));
        llvm::Value* inf = llvm::ConstantFP::getInfinity(fTy_);
        h = b_.CreateSelect(b_.CreateFCmpOEQ(big, cf(0)), cf(0), h);
        // Fix: maxnum/minnum drop a NaN operand, so hypot(a, NaN) came out as |a| sqrt(2)
        // instead of NaN (Semantics.h: std::hypot). NaN unless the other side is infinite.
        h = b_.CreateSelect(b_.CreateFCmpUNO(x, y), llvm::ConstantFP::getNaN(fTy_), h);
        return b_.CreateSelect(b_.CreateFCmpOEQ(big, inf), inf, h);
    }

    void block(ir::BlockId id) {
        for (const ir::Inst& inst : f_.blocks[id].insts) {
            if (inst.op == Op::Yield) break;
            instruction(inst);
        }
    }
    std::vector<llvm::Value*> yielded(ir::BlockId id) {
        std::vector<llvm::Value*> out;
        for (ValueId a : f_.blocks[id].insts.back().args) out.push_back(v(a));
        return out;
    }
    llvm::Type* typeOf(ValueId id) const {
        switch (f_.type(id)) {
        case ir::Type::F:
            return fTy_;
        case ir::Type::I:
            return i32_;
        case ir::Type::B:
            return llvm::Type::getInt1Ty(ctx_);
        default:
            MOIRE_ICE("no LLVM type for %{}", id);
        }
    }

    void instruction(const ir::Inst& inst) {
        auto A = [&](int i) { return v(inst.args[i]); };
        llvm::Value* r = nullptr;
        switch (inst.op) {
        case Op::ConstF:
            r = cf(inst.imm);
            break;
        case Op::ConstI:
            r = llvm::ConstantInt::get(i32_, inst.iimm);
            break;
        case Op::ConstB:
            r = llvm::ConstantInt::getBool(ctx_, inst.iimm != 0);
            break;
        case Op::PixelX:
            r = pixelX_;
            break;
        case Op::PixelY:
            r = pixelY_;
            break;
        case Op::ImageW:
            r = imageW_;
            break;
        case Op::ImageH:
            r = imageH_;
            break;
        case Op::Uniform: {
            auto it = uniformLoads_.find(inst.iimm);
            if (it == uniformLoads_.end()) {
                llvm::IRBuilder<> eb(entryInsert_);
                llvm::Value* p =
                    eb.CreateConstGEP1_64(llvm::Type::getDoubleTy(ctx_), uniforms_, inst.iimm);
                llvm::Value* d = eb.CreateLoad(llvm::Type::getDoubleTy(ctx_), p);
                it = uniformLoads_
                         .emplace(inst.iimm,
                                  eb.CreateFPTrunc(d, fTy_, "u" + std::to_string(inst.iimm)))
                         .first;
            }
            r = it->second;
            break;
        }
        case Op::Time:
        case Op::Param:
            MOIRE_ICE("'{}' belongs to the frame program, not the kernel", ir::spelling(inst.op));
        case Op::DerivX:
        case Op::DerivY:
            MOIRE_ICE("derivative markers must be removed by the AD pass");
        case Op::Indep:
            r = A(0);
            break;
        case Op::Add:
            r = b_.CreateFAdd(A(0), A(1));
            break;
        case Op::Sub:
            r = b_.CreateFSub(A(0), A(1));
            break;
        case Op::Mul:
            r = b_.CreateFMul(A(0), A(1));
            break;
        case Op::MulZ: {
            llvm::Value* zero =
                b_.CreateOr(b_.CreateFCmpOEQ(A(0), cf(0)), b_.CreateFCmpOEQ(A(1), cf(0)));
            r = b_.CreateSelect(zero, cf(0), b_.CreateFMul(A(0), A(1)));
            break;
        }
        case Op::Div:
            r = b_.CreateFDiv(A(0), A(1));
            break;
        case Op::Neg:
            r = b_.CreateFNeg(A(0));
            break;
        case Op::Abs:
            r = intrinsic(llvm::Intrinsic::fabs, {A(0)});
            break;
        case Op::Sign:
            r = b_.CreateSelect(b_.CreateFCmpOGT(A(0), cf(0)), cf(1),
                                b_.CreateSelect(b_.CreateFCmpOLT(A(0), cf(0)), cf(-1), cf(0)));
            break;
        case Op::Floor:
            r = floorOf(A(0));
            break;
        case Op::Round:
            r = floorOf(b_.CreateFAdd(A(0), cf(0.5)));
            break;
        case Op::Fract:
            r = b_.CreateFSub(A(0), floorOf(A(0)));
            break;
        case Op::Mod:
            r = b_.CreateFSub(A(0), b_.CreateFMul(A(1), floorOf(b_.CreateFDiv(A(0), A(1)))));
            break;
        case Op::Min:
            r = semMin(A(0), A(1));
            break;
        case Op::Max:
            r = semMax(A(0), A(1));
            break;
        case Op::Sqrt:
            r = intrinsic(llvm::Intrinsic::sqrt, {semMax(A(0), cf(0))});
            break;
        case Op::Exp:
            r = libm("expf", {A(0)});
            break;
        case Op::Log:
            r = libm("logf", {semMax(A(0), cf(ir::kTiny))});
            break;
        case Op::Pow:
            r = libm("powf", {A(0), A(1)});
            break;
        case Op::PowI: {
            // The same binary exponentiation as semPowI.
            int64_t n = inst.iimm;
            llvm::Value* base = n < 0 ? b_.CreateFDiv(cf(1), A(0)) : A(0);
            uint64_t e = static_cast<uint64_t>(n < 0 ? -n : n);
            llvm::Value* acc = nullptr;
            while (e) {
                if (e & 1) acc = acc ? b_.CreateFMul(acc, base) : base;
                e >>= 1;
                if (e) base = b_.CreateFMul(base, base);
            }
            r = acc ? acc : cf(1);
            break;
        }
        case Op::Sin:
            r = libm("sinf", {A(0)});
            break;
        case Op::Cos:
            r = libm("cosf", {A(0)});
            break;
        case Op::Tan:
            r = libm("tanf", {A(0)});
            break;
        case Op::Asin:
            r = libm("asinf", {semMin(semMax(A(0), cf(-1)), cf(1))});
            break;
        case Op::Acos:
            r = libm("acosf", {semMin(semMax(A(0), cf(-1)), cf(1))});
            break;
        case Op::Atan:
            r = libm("atanf", {A(0)});
            break;
        case Op::Atan2:
            r = libm("atan2f", {A(0), A(1)});
            break;
        case Op::Hypot:
            r = hypot(A(0), A(1));
            break;
        case Op::Select:
            r = b_.CreateSelect(A(0), A(1), A(2));
            break;
        case Op::Lt:
            r = b_.CreateFCmpOLT(A(0), A(1));
            break;
        case Op::Le:
            r = b_.CreateFCmpOLE(A(0), A(1));
            break;
        case Op::Gt:
            r = b_.CreateFCmpOGT(A(0), A(1));
            break;
        case Op::Ge:
            r = b_.CreateFCmpOGE(A(0), A(1));
            break;
        case Op::Eq:
            r = b_.CreateFCmpOEQ(A(0), A(1));
            break;
        case Op::Ne:
            r = b_.CreateFCmpUNE(A(0), A(1));
            break;
        case Op::And:
            r = b_.CreateAnd(A(0), A(1));
            break;
        case Op::Or:
            r = b_.CreateOr(A(0), A(1));
            break;
        case Op::Not:
            r = b_.CreateNot(A(0));
            break;
        case Op::IAdd:
            r = b_.CreateAdd(A(0), A(1));
            break;
        case Op::ISub:
            r = b_.CreateSub(A(0), A(1));
            break;
        case Op::IMul:
            r = b_.CreateMul(A(0), A(1));
            break;
        case Op::ILt:
            r = b_.CreateICmpSLT(A(0), A(1));
            break;
        case Op::ILe:
            r = b_.CreateICmpSLE(A(0), A(1));
            break;
        case Op::IEq:
            r = b_.CreateICmpEQ(A(0), A(1));
            break;
        case Op::FToI: {
            const double lim = static_cast<double>(ir::kIntClamp);
            llvm::Value* f = semMin(semMax(floorOf(A(0)), cf(-lim)), cf(lim));
            r = b_.CreateSelect(b_.CreateFCmpUNO(A(0), A(0)), llvm::ConstantInt::get(i32_, 0),
                                b_.CreateFPToSI(f, i32_));
            break;
        }
        case Op::IToF:
            r = b_.CreateSIToFP(A(0), fTy_);
            break;
        case Op::Tally:
            return; // a count for the interpreter's benchmarks; nothing to do in native code
        case Op::Output: {
            llvm::Value* idx = b_.CreateAdd(pixelBase_, llvm::ConstantInt::get(i64_, inst.iimm));
            b_.CreateStore(A(0), b_.CreateGEP(fTy_, row_, idx));
            return;
        }
        case Op::If:
            ifInst(inst);
            return;
        case Op::Loop:
            loopInst(inst);
            return;
        case Op::Yield:
            MOIRE_ICE("stray yield");
        }
        MOIRE_CHECK(r, "LLVM: op '{}' produced nothing", ir::spelling(inst.op));
        vals_[inst.results[0]] = r;
    }

    void ifInst(const ir::Inst& inst) {
        auto* thenB = llvm::BasicBlock::Create(ctx_, "then", fn_);
        auto* elseB = llvm::BasicBlock::Create(ctx_, "else", fn_);
        auto* merge = llvm::BasicBlock::Create(ctx_, "endif", fn_);
        b_.CreateCondBr(v(inst.args[0]), thenB, elseB);
        b_.SetInsertPoint(thenB);
        block(inst.regions[0]);
        auto thenVals = yielded(inst.regions[0]);
        auto* thenEnd = b_.GetInsertBlock();
        b_.CreateBr(merge);
        b_.SetInsertPoint(elseB);
        block(inst.regions[1]);
        auto elseVals = yielded(inst.regions[1]);
        auto* elseEnd = b_.GetInsertBlock();
        b_.CreateBr(merge);
        b_.SetInsertPoint(merge);
        for (size_t i = 0; i < inst.results.size(); ++i) {
            auto* phi = b_.CreatePHI(typeOf(inst.results[i]), 2);
            phi->addIncoming(thenVals[i], thenEnd);
            phi->addIncoming(elseVals[i], elseEnd);
            vals_[inst.results[i]] = phi;
        }
    }

    void loopInst(const ir::Inst& inst) {
        auto* pre = b_.GetInsertBlock();
        auto* head = llvm::BasicBlock::Create(ctx_, "loop.head", fn_);
        auto* body = llvm::BasicBlock::Create(ctx_, "loop.body", fn_);
        auto* exit = llvm::BasicBlock::Create(ctx_, "loop.exit", fn_);
        b_.CreateBr(head);
        b_.SetInsertPoint(head);
        std::vector<llvm::PHINode*> phis;
        for (size_t i = 0; i < inst.args.size(); ++i) {
            auto* phi = b_.CreatePHI(typeOf(inst.args[i]), 2);
            phi->addIncoming(v(inst.args[i]), pre);
            phis.push_back(phi);
        }
        const ir::Block& cond = f_.blocks[inst.regions[0]];
        const ir::Block& bodyBlk = f_.blocks[inst.regions[1]];
        for (size_t i = 0; i < phis.size(); ++i) vals_[cond.params[i]] = phis[i];
        block(inst.regions[0]);
        llvm::Value* c = yielded(inst.regions[0])[0];
        b_.CreateCondBr(c, body, exit);
        b_.SetInsertPoint(body);
        for (size_t i = 0; i < phis.size(); ++i) vals_[bodyBlk.params[i]] = phis[i];
        block(inst.regions[1]);
        auto next = yielded(inst.regions[1]);
        auto* bodyEnd = b_.GetInsertBlock();
        b_.CreateBr(head);
        for (size_t i = 0; i < phis.size(); ++i) phis[i]->addIncoming(next[i], bodyEnd);
        b_.SetInsertPoint(exit);
        for (size_t i = 0; i < phis.size(); ++i) vals_[inst.results[i]] = phis[i];
    }

    const ir::Function& f_;
    llvm::Module& m_;
    llvm::LLVMContext& ctx_;
    llvm::IRBuilder<> b_;
    std::vector<llvm::Value*> vals_;
    llvm::Type *fTy_, *i32_, *i64_;
    llvm::Function* fn_ = nullptr;
    llvm::BasicBlock* entry_ = nullptr;
    llvm::Instruction* entryInsert_ = nullptr;
    llvm::Value *uniforms_ = nullptr, *imageW_ = nullptr, *imageH_ = nullptr;
    llvm::Value *pixelX_ = nullptr, *pixelY_ = nullptr, *row_ = nullptr, *pixelBase_ = nullptr;
    std::unordered_map<int64_t, llvm::Value*> uniformLoads_;
    llvm::Value *carry_ = nullptr, *lane_ = nullptr;
    bool callsLibm_ = false;
};

} // namespace

std::vector<OwnedModule> translate(const ir::Function& kernel, const std::string& name,
                                   const TranslateOptions& options) {
    std::vector<OwnedModule> out;
    auto newModule = [&](const std::string& moduleName) -> llvm::Module& {
        OwnedModule& om = out.emplace_back();
        om.ctx = std::make_unique<llvm::LLVMContext>();
        om.module = std::make_unique<llvm::Module>(moduleName, *om.ctx);
        return *om.module;
    };
    ChunkPlan plan = planChunks(kernel, options.chunkInsts);
    if (plan.chunks.size() == 1) {
        Translator(kernel, newModule(name)).run(name);
        return out;
    }
    bool split = options.separateModules, whole = options.wholeStrips;
    llvm::Module& driver = newModule(name);
    std::vector<llvm::Function*> chunks;
    for (size_t c = 0; c < plan.chunks.size(); ++c) {
        std::string chunkName = name + ".chunk" + std::to_string(c);
        llvm::Function* fn =
            Translator(kernel, split ? newModule(chunkName) : driver)
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
