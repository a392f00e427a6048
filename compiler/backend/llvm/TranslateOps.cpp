// The IR's ops in LLVM IR: one case per op, the same code for one lane or many (a value's
// type is a float or a vector of floats; LLVM's instructions and intrinsics take either).
#include "compiler/backend/llvm/Translator.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <algorithm>
#include <llvm/Analysis/VectorUtils.h>
#include <llvm/IR/Intrinsics.h>

namespace moire::llvmbackend {

using ir::Op;
using ir::ValueId;

llvm::Constant* Translator::cf(double v) {
    return llvm::ConstantFP::get(fTy_, v);
}

llvm::Value* Translator::v(ValueId id) {
    MOIRE_CHECK(vals_[id], "LLVM: %{} used before definition", id);
    return vals_[id];
}

llvm::Value* Translator::intrinsic(llvm::Intrinsic::ID id,
                                   std::initializer_list<llvm::Value*> args) {
    llvm::Function* fn = llvm::Intrinsic::getDeclaration(&m_, id, {args.begin()[0]->getType()});
    return b_.CreateCall(fn, args);
}

bool callsLibm(Op op) {
    switch (op) {
    case Op::Exp:
    case Op::Log:
    case Op::Pow:
    case Op::Sin:
    case Op::Cos:
    case Op::Tan:
    case Op::Asin:
    case Op::Acos:
    case Op::Atan:
    case Op::Atan2:
        return true;
    default:
        return false;
    }
}

// A libm function of one or two floats (sinf, atan2f, ...), resolved in the host process.
// With lanes, glibc's vector version of it (libmvec: _ZGVbN4v_sinf for 4 SSE lanes,
// _ZGVdN8v_sinf for 8 AVX2 lanes, _ZGVeN16v_sinf for 16 AVX-512 lanes), or where that is
// missing, the scalar one lane by lane.
namespace {

// A libm function of `arity` arguments of type `ty`, declared in `m`. Kernels never read
// errno, so to them these are pure functions; saying so lets LLVM hoist and vectorise the
// calls.
llvm::FunctionCallee declareMaths(llvm::Module& m, const std::string& name, llvm::Type* ty,
                                  size_t arity) {
    std::vector<llvm::Type*> params(arity, ty);
    auto callee = m.getOrInsertFunction(name, llvm::FunctionType::get(ty, params, false));
    if (auto* fn = llvm::dyn_cast<llvm::Function>(callee.getCallee())) {
        fn->setDoesNotThrow();
        fn->setDoesNotAccessMemory();
        fn->setWillReturn();
        fn->addFnAttr(llvm::Attribute::Speculatable);
    }
    return callee;
}

} // namespace

llvm::Value* Translator::libm(const char* name, std::initializer_list<llvm::Value*> args) {
    callsLibm_ = true;
    const unsigned lanes = shape_.lanes;
    auto declare = [&](const std::string& fnName, llvm::Type* ty) {
        return declareMaths(m_, fnName, ty, args.size());
    };
    if (lanes == 1) return b_.CreateCall(declare(name, sf_), args);
    // Arguments the same in every lane (a row's or a frame's value): one scalar call, its
    // result splatted. libmvec's 16-lane sine costs about what sixteen pixels' do, and LICM
    // puts such a call on every row of every tile; the scalar function is also the one scalar
    // code calls.
    if (argsInvariant_) {
        std::vector<llvm::Value*> scalars;
        for (llvm::Value* a : args) scalars.push_back(b_.CreateExtractElement(a, uint64_t{0}));
        return b_.CreateVectorSplat(lanes, b_.CreateCall(declare(name, sf_), scalars));
    }
    if (shape_.vectorMaths && (lanes == 4 || lanes == 8 || lanes == 16)) {
        std::string mangled = lanes == 4 ? "_ZGVbN4" : lanes == 8 ? "_ZGVdN8" : "_ZGVeN16";
        mangled += args.size() == 2 ? "vv_" : "v_";
        return b_.CreateCall(declare(mangled + name, fTy_), args);
    }
    auto scalar = declare(name, sf_);
    llvm::Value* r = llvm::PoisonValue::get(fTy_);
    for (unsigned i = 0; i < lanes; ++i) {
        std::vector<llvm::Value*> laneArgs;
        for (llvm::Value* a : args) laneArgs.push_back(b_.CreateExtractElement(a, i));
        r = b_.CreateInsertElement(r, b_.CreateCall(scalar, laneArgs), i);
    }
    return r;
}

// The shared semantics' min and max (Semantics.h): b < a ? b : a, b > a ? b : a.
llvm::Value* Translator::semMin(llvm::Value* a, llvm::Value* bv) {
    return b_.CreateSelect(b_.CreateFCmpOLT(bv, a), bv, a);
}
llvm::Value* Translator::semMax(llvm::Value* a, llvm::Value* bv) {
    return b_.CreateSelect(b_.CreateFCmpOGT(bv, a), bv, a);
}
llvm::Value* Translator::floorOf(llvm::Value* a) {
    return intrinsic(llvm::Intrinsic::floor, {a});
}
// hypot without libm's call and without a division: sqrt(x^2 + y^2) on x and y scaled by a
// power of two (exact) where their squares would overflow or underflow, and scaled back.
// A division before the square root made hypot the walking solver's longest dependency
// chain (each step's distance waits for it). 0 at the origin, inf when either side is
// infinite (even with a NaN on the other), otherwise NaN with a NaN, as hypotf.
llvm::Value* Translator::hypot(llvm::Value* a, llvm::Value* bv) {
    llvm::Value* x = intrinsic(llvm::Intrinsic::fabs, {a});
    llvm::Value* y = intrinsic(llvm::Intrinsic::fabs, {bv});
    // maxnum drops a NaN operand: big is the larger of the numbers, NaN only if both are.
    llvm::Value* big = intrinsic(llvm::Intrinsic::maxnum, {x, y});
    llvm::Value* huge = b_.CreateFCmpOGT(big, cf(0x1p60));
    llvm::Value* tiny = b_.CreateFCmpOLT(big, cf(0x1p-60));
    auto pick = [&](double ifHuge, double ifTiny) {
        return b_.CreateSelect(huge, cf(ifHuge), b_.CreateSelect(tiny, cf(ifTiny), cf(1)));
    };
    llvm::Value* scale = pick(0x1p-64, 0x1p100);
    llvm::Value* xs = b_.CreateFMul(x, scale);
    llvm::Value* ys = b_.CreateFMul(y, scale);
    llvm::Value* sum =
        b_.CreateCall(llvm::Intrinsic::getDeclaration(&m_, llvm::Intrinsic::fmuladd, {fTy_}),
                      {xs, xs, b_.CreateFMul(ys, ys)});
    llvm::Value* h = b_.CreateFMul(intrinsic(llvm::Intrinsic::sqrt, {sum}), pick(0x1p64, 0x1p-100));
    llvm::Value* inf = llvm::ConstantFP::getInfinity(fTy_);
    return b_.CreateSelect(b_.CreateFCmpOEQ(big, inf), inf, h);
}

// Whether an instruction's result is the same in every lane: the pixel's row, the image size,
// uniforms and constants are; an op of such values is too. Region parameters, the results of
// `if` and `loop` and values carried in from another chunk are taken to vary.
bool Translator::laneInvariant(const ir::Inst& inst) const {
    switch (inst.op) {
    case Op::ConstF:
    case Op::ConstI:
    case Op::ConstB:
    case Op::PixelY:
    case Op::ImageW:
    case Op::ImageH:
    case Op::Uniform:
        return true;
    case Op::PixelX:
    case Op::If:
    case Op::Loop:
    case Op::Output:
    case Op::Tally:
    case Op::Yield:
        return false;
    default:
        return !inst.args.empty() && std::all_of(inst.args.begin(), inst.args.end(),
                                                 [&](ValueId a) { return invariant_[a] != 0; });
    }
}

void Translator::instruction(const ir::Inst& inst) {
    auto A = [&](int i) { return v(inst.args[i]); };
    llvm::Value* r = nullptr;
    const bool invariant = shape_.lanes > 1 && laneInvariant(inst);
    argsInvariant_ = invariant;
    switch (inst.op) {
    case Op::ConstF:
        r = cf(inst.imm);
        break;
    case Op::ConstI:
        r = llvm::ConstantInt::get(iTy_, inst.iimm);
        break;
    case Op::ConstB:
        r = llvm::ConstantInt::get(bTy_, inst.iimm != 0);
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
        // Loaded once, in the entry block (and made a vector there with lanes).
        auto it = uniformLoads_.find(inst.iimm);
        if (it == uniformLoads_.end()) {
            llvm::IRBuilder<> eb(entryInsert_);
            llvm::Value* p =
                eb.CreateConstGEP1_64(llvm::Type::getDoubleTy(ctx_), uniforms_, inst.iimm);
            llvm::Value* d = eb.CreateLoad(llvm::Type::getDoubleTy(ctx_), p);
            llvm::Value* u = eb.CreateFPTrunc(d, sf_, "u" + std::to_string(inst.iimm));
            if (shape_.lanes > 1) u = eb.CreateVectorSplat(shape_.lanes, u);
            it = uniformLoads_.emplace(inst.iimm, u).first;
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
    case Op::Detach:
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
        r = b_.CreateSelect(b_.CreateFCmpUNO(A(0), A(0)), llvm::ConstantInt::get(iTy_, 0),
                            b_.CreateFPToSI(f, iTy_));
        break;
    }
    case Op::IToF:
        r = b_.CreateSIToFP(A(0), fTy_);
        break;
    case Op::Tally:
        return; // a count for the interpreter's benchmarks; nothing to do in native code
    case Op::Output:
        output(inst);
        return;
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
    invariant_[inst.results[0]] = invariant;
}

} // namespace moire::llvmbackend
