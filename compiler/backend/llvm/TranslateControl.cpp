// Structured control flow in LLVM IR: regions, `if` and `loop`, for one lane (branches and
// phis) and for many (the same regions run under an execution mask; see Translator.h).
#include "compiler/backend/llvm/Translator.h"
#include "compiler/diag/Diagnostics.h"

namespace moire::llvmbackend {

using ir::Op;
using ir::ValueId;

void Translator::block(ir::BlockId id) {
    for (const ir::Inst& inst : f_.blocks[id].insts) {
        if (inst.op == Op::Yield) break;
        instruction(inst);
    }
}

std::vector<llvm::Value*> Translator::yielded(ir::BlockId id) {
    std::vector<llvm::Value*> out;
    for (ValueId a : f_.blocks[id].insts.back().args) out.push_back(v(a));
    return out;
}

llvm::Type* Translator::typeOf(ValueId id) const {
    switch (f_.type(id)) {
    case ir::Type::F:
        return fTy_;
    case ir::Type::I:
        return iTy_;
    case ir::Type::B:
        return bTy_;
    default:
        MOIRE_ICE("no LLVM type for %{}", id);
    }
}

void Translator::ifInst(const ir::Inst& inst) {
    if (shape_.lanes > 1) return maskedIf(inst);
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

// `loop`. With lanes, it runs while any lane is active. A lane is active while the condition
// holds for it (and it runs the enclosing region); the body's values replace a lane's carried
// values only while it is active, so a lane that has finished keeps the values it finished
// with, which are its results, as with one lane.
void Translator::loopInst(const ir::Inst& inst) {
    const bool masked = shape_.lanes > 1;
    auto* pre = b_.GetInsertBlock();
    auto* head = llvm::BasicBlock::Create(ctx_, "loop.head", fn_);
    auto* body = llvm::BasicBlock::Create(ctx_, "loop.body", fn_);
    auto* exit = llvm::BasicBlock::Create(ctx_, "loop.exit", fn_);
    llvm::Value* outer = exec_;
    b_.CreateBr(head);
    b_.SetInsertPoint(head);
    std::vector<llvm::PHINode*> phis;
    for (size_t i = 0; i < inst.args.size(); ++i) {
        auto* phi = b_.CreatePHI(typeOf(inst.args[i]), 2);
        phi->addIncoming(v(inst.args[i]), pre);
        phis.push_back(phi);
    }
    llvm::PHINode* active = nullptr;
    if (masked) {
        active = b_.CreatePHI(bTy_, 2, "active");
        active->addIncoming(outer ? outer : llvm::ConstantInt::getTrue(bTy_), pre);
        exec_ = active;
        ++regionDepth_;
    }
    const ir::Block& cond = f_.blocks[inst.regions[0]];
    const ir::Block& bodyBlk = f_.blocks[inst.regions[1]];
    for (size_t i = 0; i < phis.size(); ++i) vals_[cond.params[i]] = phis[i];
    block(inst.regions[0]);
    llvm::Value* running = yielded(inst.regions[0])[0];
    if (masked) running = b_.CreateAnd(active, running, "running");
    b_.CreateCondBr(masked ? b_.CreateOrReduce(running) : running, body, exit);
    b_.SetInsertPoint(body);
    for (size_t i = 0; i < phis.size(); ++i) vals_[bodyBlk.params[i]] = phis[i];
    if (masked) exec_ = running;
    block(inst.regions[1]);
    auto next = yielded(inst.regions[1]);
    if (masked)
        for (size_t i = 0; i < phis.size(); ++i)
            next[i] = b_.CreateSelect(running, next[i], phis[i]);
    auto* bodyEnd = b_.GetInsertBlock();
    b_.CreateBr(head);
    for (size_t i = 0; i < phis.size(); ++i) phis[i]->addIncoming(next[i], bodyEnd);
    if (masked) {
        active->addIncoming(running, bodyEnd);
        --regionDepth_;
        exec_ = outer;
    }
    b_.SetInsertPoint(exit);
    for (size_t i = 0; i < phis.size(); ++i) vals_[inst.results[i]] = phis[i];
}

// The lanes of `mask` (nullptr: all) for which `cond` holds.
llvm::Value* Translator::andMask(llvm::Value* mask, llvm::Value* cond) {
    return mask ? b_.CreateAnd(mask, cond) : cond;
}

// A region worth running for every lane rather than branching around: no loop, no call to
// a maths function (a vector sine costs tens of instructions), and few instructions
// (counted against `budget`, shared by both arms of an `if`). Running it costs less than
// the test and the branch, and lets LLVM schedule both arms together.
bool Translator::cheapRegion(ir::BlockId id, int& budget) const {
    for (const ir::Inst& inst : f_.blocks[id].insts) {
        if (inst.op == Op::Loop || callsLibm(inst.op) || --budget < 0) return false;
        for (ir::BlockId r : inst.regions)
            if (!cheapRegion(r, budget)) return false;
    }
    return true;
}

// `if` with lanes. Each arm runs with the lanes that take it as the execution mask, and only
// when at least one lane does (a short arm runs unconditionally); each result is then the
// arm's value its lane took. An arm that did not run yields zeros, which no lane selects.
//
// Values an arm computes for lanes that do not take it are never seen, and an op has no
// effect but its result (an output is written under the mask), so running an arm for them
// is harmless; a loop inside an arm is the one thing that must not run for them (it might
// not end for values the arm was never meant to see), hence the mask.
void Translator::maskedIf(const ir::Inst& inst) {
    llvm::Value* c = v(inst.args[0]);
    llvm::Value* outer = exec_;
    llvm::Value* thenMask = andMask(outer, c);
    llvm::Value* elseMask = andMask(outer, b_.CreateNot(c));
    ++regionDepth_;
    std::vector<llvm::Value*> thenVals, elseVals;
    int budget = 32;
    if (cheapRegion(inst.regions[0], budget) && cheapRegion(inst.regions[1], budget)) {
        exec_ = thenMask;
        block(inst.regions[0]);
        thenVals = yielded(inst.regions[0]);
        exec_ = elseMask;
        block(inst.regions[1]);
        elseVals = yielded(inst.regions[1]);
    } else {
        // Runs one arm when any lane of `mask` takes it; its values, or zeros when skipped.
        auto arm = [&](ir::BlockId region, llvm::Value* mask, const char* label) {
            auto* pre = b_.GetInsertBlock();
            auto* armB = llvm::BasicBlock::Create(ctx_, label, fn_);
            auto* join = llvm::BasicBlock::Create(ctx_, std::string(label) + ".join", fn_);
            b_.CreateCondBr(b_.CreateOrReduce(mask), armB, join);
            b_.SetInsertPoint(armB);
            exec_ = mask;
            std::vector<llvm::Value*> vals;
            if (outlines(region)) {
                vals = callOutlined(region);
            } else {
                block(region);
                vals = yielded(region);
            }
            auto* armEnd = b_.GetInsertBlock();
            b_.CreateBr(join);
            b_.SetInsertPoint(join);
            for (size_t i = 0; i < vals.size(); ++i) {
                auto* phi = b_.CreatePHI(vals[i]->getType(), 2);
                phi->addIncoming(vals[i], armEnd);
                phi->addIncoming(llvm::Constant::getNullValue(vals[i]->getType()), pre);
                vals[i] = phi;
            }
            return vals;
        };
        thenVals = arm(inst.regions[0], thenMask, "then");
        elseVals = arm(inst.regions[1], elseMask, "else");
    }
    --regionDepth_;
    exec_ = outer;
    for (size_t i = 0; i < inst.results.size(); ++i)
        vals_[inst.results[i]] = b_.CreateSelect(c, thenVals[i], elseVals[i]);
}

} // namespace moire::llvmbackend
