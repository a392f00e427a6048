#include "compiler/ir/Builder.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::ir {

Inst& Builder::append(Op op, std::vector<ValueId> args) {
    Block& b = f_.blocks[block_];
    Inst inst;
    inst.op = op;
    inst.args = std::move(args);
    inst.loc = loc_;
    b.insts.push_back(std::move(inst));
    return b.insts.back();
}

ValueId Builder::emit(Op op, std::initializer_list<ValueId> args, double imm, int64_t iimm) {
    const OpInfo& info = opInfo(op);
    MOIRE_CHECK(info.numArgs == static_cast<int>(args.size()), "for op {}", info.spelling);
    Type t = op == Op::Select ? f_.type(*(args.begin() + 1)) : info.result;
    MOIRE_CHECK(t == Type::F || t == Type::I || t == Type::B, "op {} has no single result",
                info.spelling);
    ValueId r = f_.newValue(t);
    Inst& inst = append(op, std::vector<ValueId>(args));
    inst.imm = imm;
    inst.iimm = iimm;
    inst.results.push_back(r);
    return r;
}

void Builder::emitSink(Op op, std::initializer_list<ValueId> args, int64_t iimm) {
    Inst& inst = append(op, std::vector<ValueId>(args));
    inst.iimm = iimm;
}

ValueId Builder::smoothstep(ValueId e0, ValueId e1, ValueId v) {
    ValueId u = clamp(div(sub(v, e0), sub(e1, e0)), constF(0.0), constF(1.0));
    return mul(mul(u, u), sub(constF(3.0), mul(constF(2.0), u)));
}

ValueId Builder::pick(ValueId which, std::span<const ValueId> values) {
    ValueId v = values.back();
    for (size_t i = values.size() - 1; i-- > 0;)
        v = select(emit(Op::Eq, {which, constF(static_cast<double>(i))}), values[i], v);
    return v;
}

ValueId Builder::wrap(ValueId v, ValueId w) {
    // v - w * floor(v / w + 1/2)
    return sub(v, mul(w, floor(add(div(v, w), constF(0.5)))));
}

std::vector<ValueId> Builder::ifThenElse(ValueId cond,
                                         const std::function<std::vector<ValueId>()>& thenFn,
                                         const std::function<std::vector<ValueId>()>& elseFn) {
    BlockId outer = block_;
    BlockId thenB = f_.newBlock();
    BlockId elseB = f_.newBlock();
    block_ = thenB;
    std::vector<ValueId> t = thenFn();
    append(Op::Yield, t);
    block_ = elseB;
    std::vector<ValueId> e = elseFn();
    append(Op::Yield, e);
    block_ = outer;
    MOIRE_CHECK(t.size() == e.size(), "if branches disagree");
    Inst& inst = append(Op::If, {cond});
    inst.regions = {thenB, elseB};
    std::vector<ValueId> results;
    for (ValueId v : t) results.push_back(f_.newValue(f_.type(v)));
    f_.blocks[outer].insts.back().results = results;
    return results;
}

std::vector<ValueId> Builder::loop(const std::vector<ValueId>& inits, const LoopFn& cond,
                                   const LoopFn& body) {
    BlockId outer = block_;
    auto makeRegion = [&](const LoopFn& fn) {
        BlockId id = f_.newBlock();
        std::vector<ValueId> params;
        for (ValueId v : inits) params.push_back(f_.newValue(f_.type(v)));
        f_.blocks[id].params = params;
        block_ = id;
        std::vector<ValueId> y = fn(params);
        append(Op::Yield, y);
        return id;
    };
    BlockId condB = makeRegion(cond);
    BlockId bodyB = makeRegion(body);
    block_ = outer;
    Inst& inst = append(Op::Loop, inits);
    inst.regions = {condB, bodyB};
    std::vector<ValueId> results;
    for (ValueId v : inits) results.push_back(f_.newValue(f_.type(v)));
    f_.blocks[outer].insts.back().results = results;
    return results;
}

} // namespace moire::ir
