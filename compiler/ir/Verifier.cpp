#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/IR.h"

#include <fmt/format.h>

namespace moire::ir {

namespace {

class Verifier {
  public:
    explicit Verifier(const Function& f)
        : f_(f), defined_(f.numValues(), false), visited_(f.blocks.size(), false) {}

    void run() {
        block(0, {});
        for (size_t b = 0; b < f_.blocks.size(); ++b)
            if (!visited_[b] && !f_.blocks[b].insts.empty())
                fail(fmt::format("block {} is not owned by any instruction", b));
    }

  private:
    [[noreturn]] void fail(const std::string& what) const {
        MOIRE_ICE("IR verifier: {} in function '{}'\n{}", what, f_.name, print(f_));
    }

    void define(ValueId v) {
        if (v >= f_.numValues()) fail(fmt::format("value %{} out of range", v));
        if (defined_[v]) fail(fmt::format("value %{} defined twice", v));
        defined_[v] = true;
        scope_.back().push_back(v);
    }

    void use(ValueId v, Type expect) const {
        if (v >= f_.numValues() || !defined_[v]) fail(fmt::format("use of undefined value %{}", v));
        if (expect != Type::None && f_.type(v) != expect)
            fail(fmt::format("%{} has type {} where {} is expected", v, typeSpelling(f_.type(v)),
                             typeSpelling(expect)));
    }

    // Runs a region and returns the values its Yield produced.
    std::vector<ValueId> block(BlockId id, const std::vector<Type>& paramTypes) {
        if (id >= f_.blocks.size()) fail(fmt::format("block {} out of range", id));
        if (visited_[id]) fail(fmt::format("block {} owned twice", id));
        visited_[id] = true;
        const Block& b = f_.blocks[id];
        scope_.emplace_back();
        if (b.params.size() != paramTypes.size())
            fail(fmt::format("block {} has {} params, expected {}", id, b.params.size(),
                             paramTypes.size()));
        for (size_t i = 0; i < b.params.size(); ++i) {
            define(b.params[i]);
            if (f_.type(b.params[i]) != paramTypes[i]) fail(fmt::format("block {} param type", id));
        }
        std::vector<ValueId> yielded;
        bool isEntry = id == 0;
        for (size_t i = 0; i < b.insts.size(); ++i) {
            const Inst& inst = b.insts[i];
            if (inst.op == Op::Yield) {
                if (isEntry) fail("yield in the entry block");
                if (i + 1 != b.insts.size()) fail("yield before the end of a block");
                for (ValueId a : inst.args) use(a, Type::None);
                yielded = inst.args;
                hasYield_ = true;
                continue;
            }
            instruction(inst);
        }
        if (!isEntry && (b.insts.empty() || b.insts.back().op != Op::Yield))
            fail(fmt::format("block {} does not end with yield", id));
        // Values defined inside a region are not visible after it.
        for (ValueId v : scope_.back()) defined_[v] = false;
        scope_.pop_back();
        return yielded;
    }

    void instruction(const Inst& inst) {
        const OpInfo& info = opInfo(inst.op);
        if (info.numArgs >= 0 && static_cast<int>(inst.args.size()) != info.numArgs)
            fail(fmt::format("{} has {} operands, expected {}", info.spelling, inst.args.size(),
                             info.numArgs));
        switch (inst.op) {
        case Op::If: {
            if (inst.args.size() != 1 || inst.regions.size() != 2) fail("malformed if");
            use(inst.args[0], Type::B);
            std::vector<Type> none;
            auto t = block(inst.regions[0], none);
            auto e = block(inst.regions[1], none);
            checkYield(inst, t);
            checkYield(inst, e);
            break;
        }
        case Op::Loop: {
            if (inst.regions.size() != 2) fail("malformed loop");
            std::vector<Type> types;
            for (ValueId a : inst.args) {
                use(a, Type::None);
                types.push_back(f_.type(a));
            }
            auto c = block(inst.regions[0], types);
            if (c.size() != 1 || f_.type(c[0]) != Type::B)
                fail("loop condition must yield one bool");
            auto next = block(inst.regions[1], types);
            if (next.size() != types.size()) fail("loop body yields the wrong number of values");
            for (size_t i = 0; i < types.size(); ++i)
                if (f_.type(next[i]) != types[i]) fail("loop body yields a wrong type");
            if (inst.results.size() != types.size()) fail("loop result count");
            for (size_t i = 0; i < types.size(); ++i)
                if (f_.type(inst.results[i]) != types[i]) fail("loop result type");
            break;
        }
        case Op::Select: {
            use(inst.args[0], Type::B);
            use(inst.args[1], Type::None);
            use(inst.args[2], f_.type(inst.args[1]));
            if (inst.results.size() != 1 || f_.type(inst.results[0]) != f_.type(inst.args[1]))
                fail("select result type");
            break;
        }
        case Op::Output:
            use(inst.args[0], Type::F);
            if (inst.iimm < 0 || inst.iimm >= f_.numOutputs) fail("output slot out of range");
            break;
        case Op::Tally:
            if (inst.iimm < 0 || inst.iimm >= kMaxTallies) fail("tally counter out of range");
            if (!inst.results.empty()) fail("tally has a result");
            break;
        case Op::Param:
        case Op::Uniform:
            // Fix: a negative slot was accepted, and the JIT reads uniforms[slot] unchecked.
            if (inst.iimm < 0)
                fail(fmt::format("{} slot {} is negative", info.spelling, inst.iimm));
            if (inst.results.size() != 1 || f_.type(inst.results[0]) != Type::F)
                fail(fmt::format("{} result type", info.spelling));
            break;
        default: {
            Type operand = Type::F;
            switch (inst.op) {
            case Op::And:
            case Op::Or:
            case Op::Not:
                operand = Type::B;
                break;
            case Op::IAdd:
            case Op::ISub:
            case Op::IMul:
            case Op::ILt:
            case Op::ILe:
            case Op::IEq:
            case Op::IToF:
                operand = Type::I;
                break;
            default:
                break;
            }
            for (ValueId a : inst.args) use(a, operand);
            if (info.result == Type::None) {
                if (!inst.results.empty()) fail(fmt::format("{} has a result", info.spelling));
            } else if (inst.results.size() != 1 || f_.type(inst.results[0]) != info.result) {
                fail(fmt::format("{} result type", info.spelling));
            }
        }
        }
        for (ValueId r : inst.results) define(r);
    }

    void checkYield(const Inst& inst, const std::vector<ValueId>& y) const {
        if (y.size() != inst.results.size()) fail("if branches yield the wrong number of values");
        for (size_t i = 0; i < y.size(); ++i)
            if (f_.type(y[i]) != f_.type(inst.results[i])) fail("if branch yields a wrong type");
    }

    const Function& f_;
    std::vector<bool> defined_;
    std::vector<bool> visited_;
    std::vector<std::vector<ValueId>> scope_;
    bool hasYield_ = false;
};

} // namespace

void verify(const Function& f) {
    Verifier(f).run();
}

} // namespace moire::ir
