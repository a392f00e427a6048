#include "compiler/passes/Rewriter.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::passes {

using namespace ir;

Rewriter::Rewriter(const Function& src) : src_(src), b_(dst_), vmap_(src.numValues(), kNoValue) {
    dst_.name = src.name;
    dst_.numOutputs = src.numOutputs;
}

ValueId Rewriter::map(ValueId v) {
    MOIRE_CHECK(v < vmap_.size(), "rewriter: %{} out of range", v);
    if (vmap_[v] == kNoValue) vmap_[v] = mapMissing(v);
    return vmap_[v];
}

ValueId Rewriter::mapMissing(ValueId v) {
    MOIRE_ICE("rewriter: %{} has no mapping", v);
}

Function Rewriter::run(Check check) {
    b_.setBlock(0);
    dst_.blocks[0].insts.reserve(src_.blocks[0].insts.size());
    for (const Inst& inst : src_.blocks[0].insts)
        if (!visit(inst)) copy(inst);
    finish();
    if (check == Check::Verify) verify(dst_);
    return std::move(dst_);
}

std::vector<ValueId> Rewriter::inlineBlock(BlockId b) {
    const Block& blk = src_.blocks[b];
    std::vector<ValueId> yielded;
    for (const Inst& inst : blk.insts) {
        if (inst.op == Op::Yield) {
            for (ValueId a : inst.args) yielded.push_back(map(a));
            break;
        }
        if (!visit(inst)) copy(inst);
    }
    return yielded;
}

IdList Rewriter::copy(const Inst& inst) {
    b_.setLoc(inst.loc);
    if (inst.op == Op::If) {
        auto region = [&](BlockId r) {
            return [this, r] {
                enterRegion();
                auto y = inlineBlock(r);
                leaveRegion();
                return y;
            };
        };
        auto res =
            b_.ifThenElse(map(inst.args[0]), region(inst.regions[0]), region(inst.regions[1]));
        for (size_t i = 0; i < res.size(); ++i) bind(inst.results[i], res[i]);
        return res;
    }
    if (inst.op == Op::Loop) {
        std::vector<ValueId> inits;
        for (ValueId a : inst.args) inits.push_back(map(a));
        auto region = [&](BlockId r) {
            return [this, r](std::span<const ValueId> params) {
                enterRegion();
                const Block& blk = src_.blocks[r];
                for (size_t i = 0; i < params.size(); ++i) bind(blk.params[i], params[i]);
                auto y = inlineBlock(r);
                leaveRegion();
                return y;
            };
        };
        auto res = b_.loop(inits, region(inst.regions[0]), region(inst.regions[1]));
        for (size_t i = 0; i < res.size(); ++i) bind(inst.results[i], res[i]);
        return res;
    }
    Inst c;
    c.op = inst.op;
    c.imm = inst.imm;
    c.iimm = inst.iimm;
    c.loc = inst.loc;
    c.regions = inst.regions;
    c.args.reserve(inst.args.size());
    for (ValueId a : inst.args) c.args.push_back(map(a));
    c.results.reserve(inst.results.size());
    for (ValueId r : inst.results) {
        ValueId nr = dst_.newValue(src_.type(r));
        c.results.push_back(nr);
        bind(r, nr);
    }
    auto& insts = dst_.blocks[b_.block()].insts;
    insts.push_back(std::move(c));
    return insts.back().results;
}

} // namespace moire::passes
