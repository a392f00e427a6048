// The verifier accepts well-formed IR and rejects each kind of malformed IR: every case
// below starts from the same valid function and breaks one invariant of IR.h.
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"

#include <doctest/doctest.h>
#include <functional>
#include <tuple>

using namespace moire;
using namespace moire::ir;

namespace {

using Vals = std::vector<ValueId>;

// out0 = (if u0 < u1 then u0 * u1 else -u0) + sum of 3 steps of a loop.
struct Valid {
    Function f;
    ValueId u0, u1, product, sum;
    BlockId thenB, condB;
    Valid() {
        f.name = "valid";
        f.numOutputs = 1;
        Builder b(f);
        u0 = b.uniform(0);
        u1 = b.uniform(1);
        ValueId r = b.ifThenElse(
            b.lt(u0, u1),
            [&] {
                thenB = b.block();
                product = b.mul(u0, u1);
                return Vals{product};
            },
            [&] { return Vals{b.neg(u0)}; })[0];
        auto loop = b.loop(
            {b.constI(0), r},
            [&](std::span<const ValueId> p) {
                condB = b.block();
                return Vals{b.emit(Op::ILt, {p[0], b.constI(3)})};
            },
            [&](std::span<const ValueId> p) {
                return Vals{b.emit(Op::IAdd, {p[0], b.constI(1)}), b.add(p[1], u1)};
            });
        sum = loop[1];
        b.output(0, sum);
    }
    Inst& entryInst(Op op) {
        for (Inst& inst : f.blocks[0].insts)
            if (inst.op == op) return inst;
        FAIL("no such op");
        return f.blocks[0].insts[0];
    }
};

} // namespace

TEST_CASE("the verifier accepts well-formed IR") {
    Valid v;
    CHECK_NOTHROW(verify(v.f));
}

TEST_CASE("the verifier rejects malformed IR") {
    // What is broken, the verifier's reason, how.
    const std::tuple<const char*, const char*, std::function<void(Valid&)>> breaks[] = {
        {"operand out of range", "use of undefined value %1000",
         [](Valid& v) { v.entryInst(Op::Output).args[0] = 1000; }},
        {"use before definition", "use of undefined value",
         [](Valid& v) {
             std::swap(v.f.blocks[0].insts[0], v.f.blocks[0].insts[2]);
         }}, // lt before uniforms
        {"operand of the wrong type", "has type b where f is expected",
         [](Valid& v) { v.entryInst(Op::Output).args[0] = v.entryInst(Op::Lt).results[0]; }},
        {"wrong operand count", "mul has 1 operands, expected 2",
         [](Valid& v) { v.f.blocks[v.thenB].insts[0].args.pop_back(); }},
        {"result of the wrong type", "mul result type",
         [](Valid& v) { v.f.valueTypes[v.product] = Type::B; }},
        {"yield in the entry block", "yield in the entry block",
         [](Valid& v) {
             Inst y;
             y.op = Op::Yield;
             v.f.blocks[0].insts.insert(v.f.blocks[0].insts.begin(), y);
         }},
        {"region without a yield", "does not end with yield",
         [](Valid& v) { v.f.blocks[v.thenB].insts.pop_back(); }},
        {"value used outside its region", "use of undefined value",
         [](Valid& v) { v.entryInst(Op::Output).args[0] = v.product; }},
        {"loop condition yielding a float", "loop condition must yield one bool",
         [](Valid& v) {
             v.f.blocks[v.condB].insts.back().args[0] = v.f.blocks[v.condB].params[1];
         }},
        {"loop body yielding too few values", "loop body yields the wrong number of values",
         [](Valid& v) { v.f.blocks.back().insts.back().args.pop_back(); }},
        {"if branches yielding different types", "if branch yields a wrong type",
         [](Valid& v) {
             v.f.blocks[v.thenB].insts.back().args[0] = v.entryInst(Op::Lt).results[0];
         }},
        {"output slot out of range", "output slot out of range",
         [](Valid& v) { v.entryInst(Op::Output).iimm = 1; }},
        {"value defined twice", "defined twice",
         [](Valid& v) { v.f.blocks[v.thenB].insts[0].results[0] = v.u0; }},
        {"negative uniform slot", "slot -1 is negative",
         [](Valid& v) { v.f.blocks[0].insts[0].iimm = -1; }},
        {"block owned twice", "owned twice",
         [](Valid& v) { v.entryInst(Op::If).regions[1] = v.thenB; }},
        {"block owned by nothing", "is not owned by any instruction",
         [](Valid& v) {
             v.f.blocks.emplace_back();
             Inst y;
             y.op = Op::Yield;
             v.f.blocks.back().insts.push_back(y);
         }},
    };
    for (const auto& [what, reason, breakIt] : breaks) {
        std::string name = what;
        CAPTURE(name);
        Valid v;
        breakIt(v);
        CHECK_THROWS_WITH_AS(verify(v.f), doctest::Contains(reason), InternalError);
    }
}
