#include "compiler/ir/Semantics.h"
#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

#include <cmath>
#include <optional>
#include <unordered_map>

namespace moire::passes {

using namespace ir;

namespace {

class Folder : public Rewriter {
  public:
    using Rewriter::Rewriter;

  private:
    std::optional<double> constant(ValueId newValue) const {
        auto it = consts_.find(newValue);
        if (it == consts_.end()) return std::nullopt;
        return it->second;
    }
    ValueId makeConst(Type t, double v) {
        ValueId r = t == Type::F   ? b_.constF(v)
                    : t == Type::I ? b_.constI(static_cast<int64_t>(v))
                                   : b_.constB(v != 0.0);
        consts_[r] = v;
        return r;
    }
    bool is(std::optional<double> c, double v) const { return c && *c == v; }
    // The exact constant, sign of zero included.
    bool isExactly(std::optional<double> c, double v) const {
        return is(c, v) && std::signbit(*c) == std::signbit(v);
    }

    bool visit(const Inst& inst) override {
        b_.setLoc(inst.loc);
        switch (inst.op) {
        case Op::ConstF:
            bind(inst.results[0], makeConst(Type::F, inst.imm));
            return true;
        case Op::ConstI:
            bind(inst.results[0], makeConst(Type::I, static_cast<double>(inst.iimm)));
            return true;
        case Op::ConstB:
            bind(inst.results[0], makeConst(Type::B, static_cast<double>(inst.iimm)));
            return true;
        case Op::If: {
            auto c = constant(map(inst.args[0]));
            if (!c) return false;
            auto y = inlineBlock(inst.regions[*c != 0.0 ? 0 : 1]);
            for (size_t i = 0; i < y.size(); ++i) bind(inst.results[i], y[i]);
            return true;
        }
        default:
            break;
        }
        if (!isPure(inst.op) || inst.results.size() != 1) return false;

        std::vector<ValueId> args;
        std::vector<std::optional<double>> c;
        bool allConst = true;
        for (ValueId a : inst.args) {
            args.push_back(map(a));
            c.push_back(constant(args.back()));
            allConst = allConst && c.back().has_value();
        }
        ValueId res = inst.results[0];
        Type rt = src_.type(res);
        if (allConst && !args.empty()) {
            double v[3] = {0, 0, 0};
            for (size_t i = 0; i < c.size(); ++i) v[i] = *c[i];
            double out;
            if (isFloatOp(inst.op))
                out = evalFloat<double>(inst.op, v, inst.iimm);
            else if (isCompareOp(inst.op))
                out = evalCompare<double>(inst.op, v[0], v[1]);
            else
                switch (inst.op) {
                case Op::Select:
                    out = v[0] != 0.0 ? v[1] : v[2];
                    break;
                case Op::And:
                    out = v[0] != 0.0 && v[1] != 0.0;
                    break;
                case Op::Or:
                    out = v[0] != 0.0 || v[1] != 0.0;
                    break;
                case Op::Not:
                    out = v[0] == 0.0;
                    break;
                case Op::IAdd:
                    out = static_cast<int32_t>(static_cast<int64_t>(v[0]) +
                                               static_cast<int64_t>(v[1]));
                    break;
                case Op::ISub:
                    out = static_cast<int32_t>(static_cast<int64_t>(v[0]) -
                                               static_cast<int64_t>(v[1]));
                    break;
                case Op::IMul:
                    out = static_cast<int32_t>(static_cast<int64_t>(v[0]) *
                                               static_cast<int64_t>(v[1]));
                    break;
                case Op::ILt:
                    out = v[0] < v[1];
                    break;
                case Op::ILe:
                    out = v[0] <= v[1];
                    break;
                case Op::IEq:
                    out = v[0] == v[1];
                    break;
                case Op::FToI:
                    out = semFToI(v[0]);
                    break;
                case Op::IToF:
                    out = v[0];
                    break;
                default:
                    return false;
                }
            bind(res, makeConst(rt, out));
            return true;
        }
        // Identities that hold for every input, inf and NaN included.
        auto forward = [&](ValueId to) {
            bind(res, to);
            return true;
        };
        switch (inst.op) {
        // Fix: x + 0 and x - (-0) were folded to x, but they turn x = -0 into +0, which div,
        // atan2 and pow tell apart (1 / (x + 0) is +inf at x = -0, 1 / x is -inf). Only the
        // exact identities x + (-0) = x and x - (+0) = x are applied.
        case Op::Add:
            if (isExactly(c[1], -0.0)) return forward(args[0]);
            if (isExactly(c[0], -0.0)) return forward(args[1]);
            break;
        case Op::Sub:
            if (isExactly(c[1], 0.0)) return forward(args[0]);
            break;
        case Op::Mul:
            if (is(c[1], 1.0)) return forward(args[0]);
            if (is(c[0], 1.0)) return forward(args[1]);
            break;
        case Op::MulZ:
            // The zero rule: an exact zero factor wins over anything, inf and NaN included.
            if (is(c[0], 0.0) || is(c[1], 0.0)) {
                bind(res, makeConst(Type::F, 0.0));
                return true;
            }
            // mulz(x, 1) is +0 where x is -0: the one identity here that is exact only up to
            // the sign of a zero. mulz is the chain-rule product, so this is the tangent of
            // an independent variable times a slope, where a zero's sign means nothing;
            // folding it saves one op per chain-rule step.
            if (is(c[1], 1.0)) return forward(args[0]);
            if (is(c[0], 1.0)) return forward(args[1]);
            break;
        case Op::Div:
            if (is(c[1], 1.0)) return forward(args[0]);
            break;
        case Op::Select:
            if (c[0]) return forward(*c[0] != 0.0 ? args[1] : args[2]);
            if (args[1] == args[2]) return forward(args[1]);
            break;
        case Op::Min:
        case Op::Max:
            if (args[0] == args[1]) return forward(args[0]);
            break;
        case Op::PowI:
            if (inst.iimm == 1) return forward(args[0]);
            break;
        case Op::And:
            if (is(c[0], 1.0)) return forward(args[1]);
            if (is(c[1], 1.0)) return forward(args[0]);
            break;
        case Op::Or:
            if (is(c[0], 0.0)) return forward(args[1]);
            if (is(c[1], 0.0)) return forward(args[0]);
            break;
        default:
            break;
        }
        return false;
    }

    std::unordered_map<ValueId, double> consts_;
};

} // namespace

Function constantFold(const Function& f, Check check) {
    return Folder(f).run(check);
}

} // namespace moire::passes
