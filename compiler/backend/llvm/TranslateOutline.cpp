// Arms of `if`s run as functions of their own (OutlineRegions.h says why). With lanes only:
// the function takes the arm's execution mask and the values the arm reads, and returns what
// the arm yields; its body is the same translation the arm would have had in place.
#include "compiler/backend/llvm/Translator.h"
#include "compiler/diag/Diagnostics.h"

#include <fmt/format.h>
#include <llvm/IR/Verifier.h>
#include <llvm/Support/raw_ostream.h>

namespace moire::llvmbackend {

using ir::ValueId;

bool Translator::outlines(ir::BlockId region) const {
    return outliner_ && outlinedArm(f_, region, outliner_->minInsts);
}

std::vector<llvm::Value*> Translator::callOutlined(ir::BlockId region) {
    RegionSignature sig = regionSignature(f_, region);
    // Leaves inside the arm are the caller's to evaluate (in an outlined arm, the enclosing
    // arm's caller has, and they arrived as arguments).
    for (const ir::Inst* leaf : sig.leaves)
        if (!vals_[leaf->results[0]]) instruction(*leaf);
    // Which inputs are the same in every lane is part of the function: its body computes
    // those once for all lanes (Translator::laneInvariant).
    std::vector<char> invariant;
    std::string key = sig.key + '|';
    for (ValueId v : sig.inputs) {
        invariant.push_back(invariant_[v]);
        key += invariant_[v] ? '1' : '0';
    }
    llvm::FunctionType* type = armType(region, sig);
    std::string name;
    if (auto it = outliner_->names.find(key); it != outliner_->names.end()) {
        name = it->second;
    } else {
        name = fmt::format("{}.arm{}", outliner_->prefix, outliner_->names.size());
        outliner_->names.emplace(key, name);
        // Its nested arms are counted apart: each finds its own module.
        size_t own = ownSize(f_, region, outliner_->minInsts);
        Translator(f_, outliner_->moduleFor(own), shape_, outliner_)
            .runRegion(name, region, sig, invariant);
    }
    llvm::FunctionCallee callee = m_.getOrInsertFunction(name, type);
    if (auto* fn = llvm::dyn_cast<llvm::Function>(callee.getCallee())) fn->setDoesNotThrow();
    std::vector<llvm::Value*> args{exec_};
    for (ValueId v : sig.inputs)
        args.push_back(invariant_[v] ? b_.CreateExtractElement(this->v(v), uint64_t{0})
                                     : this->v(v));
    llvm::Value* call = b_.CreateCall(callee, args);
    std::vector<llvm::Value*> out;
    for (unsigned i = 0; i < type->getReturnType()->getStructNumElements(); ++i)
        out.push_back(b_.CreateExtractValue(call, i));
    return out;
}

// An outlined arm's type, in this translator's context: (mask, inputs...) -> {yields...}, an
// input the same in every lane as a scalar.
llvm::FunctionType* Translator::armType(ir::BlockId region, const RegionSignature& sig) {
    std::vector<llvm::Type*> params{bTy_}, results;
    for (ValueId v : sig.inputs)
        params.push_back(invariant_[v] ? typeOf(v)->getScalarType() : typeOf(v));
    for (ValueId a : f_.blocks[region].insts.back().args) results.push_back(typeOf(a));
    return llvm::FunctionType::get(llvm::StructType::get(ctx_, results), params, false);
}

// The body of an outlined arm: the arm's translation under the mask it is given.
void Translator::runRegion(const std::string& name, ir::BlockId region, const RegionSignature& sig,
                           const std::vector<char>& invariant) {
    for (size_t k = 0; k < sig.inputs.size(); ++k) invariant_[sig.inputs[k]] = invariant[k];
    llvm::FunctionType* type = armType(region, sig);
    fn_ = llvm::Function::Create(type, llvm::Function::ExternalLinkage, name, m_);
    fn_->addFnAttr(llvm::Attribute::NoUnwind);
    entry_ = llvm::BasicBlock::Create(ctx_, "entry", fn_);
    b_.SetInsertPoint(entry_);
    exec_ = fn_->getArg(0);
    regionDepth_ = 1;
    for (size_t k = 0; k < sig.inputs.size(); ++k) {
        llvm::Value* arg = fn_->getArg(static_cast<unsigned>(k + 1));
        vals_[sig.inputs[k]] = invariant[k] ? b_.CreateVectorSplat(shape_.lanes, arg) : arg;
    }
    for (const ir::Inst* constant : sig.constants) instruction(*constant);
    block(region);
    std::vector<llvm::Value*> vals = yielded(region);
    llvm::Value* ret = llvm::UndefValue::get(type->getReturnType());
    for (unsigned i = 0; i < vals.size(); ++i) ret = b_.CreateInsertValue(ret, vals[i], i);
    b_.CreateRet(ret);
    std::string err;
    llvm::raw_string_ostream os(err);
    if (llvm::verifyFunction(*fn_, &os)) MOIRE_ICE("LLVM rejected an outlined arm: {}", os.str());
}

} // namespace moire::llvmbackend
