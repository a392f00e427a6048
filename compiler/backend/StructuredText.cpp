#include "compiler/backend/StructuredText.h"

#include "compiler/diag/Diagnostics.h"

#include <fmt/format.h>

namespace moire::backend {

using ir::Op;
using ir::ValueId;

std::string StructuredText::v(ValueId id) const {
    return fmt::format("v{}", id);
}

void StructuredText::line(int depth, const std::string& text) {
    out_ += std::string(syntax_.indent * depth, ' ') + text + "\n";
}

void StructuredText::define(int depth, ValueId id, const std::string& expr) {
    line(depth, fmt::format("{} {} = {};", constant(f_.type(id)), v(id), expr));
}

std::string StructuredText::expression(const ir::Inst& inst) const {
    std::string s;
    for (const char* p = form(inst); *p; ++p) {
        if (*p == '$' && p[1] >= '0' && p[1] <= '2') {
            s += v(inst.args.at(p[1] - '0'));
            ++p;
        } else if (*p == '$' && p[1] == 'i') {
            s += std::to_string(inst.iimm);
            ++p;
        } else {
            s += *p;
        }
    }
    return s;
}

void StructuredText::block(ir::BlockId id, int depth) {
    for (const ir::Inst& inst : f_.blocks[id].insts) {
        if (inst.op == Op::Yield) break;
        instruction(inst, depth);
    }
}

void StructuredText::instruction(const ir::Inst& inst, int depth) {
    if (special(inst, depth)) return;
    switch (inst.op) {
    case Op::ConstF:
        define(depth, inst.results[0], floatLiteral(inst.imm));
        return;
    case Op::ConstI:
        define(depth, inst.results[0], intLiteral(inst.iimm));
        return;
    case Op::ConstB:
        define(depth, inst.results[0], inst.iimm ? "true" : "false");
        return;
    case Op::Output:
        line(depth, fmt::format("{} = {};", output(inst.iimm), v(inst.args[0])));
        return;
    case Op::PowI:
        define(depth, inst.results[0], powi(inst, depth));
        return;
    case Op::Tally:
        return; // counted by the interpreter only
    case Op::If: {
        for (ValueId r : inst.results)
            line(depth, fmt::format("{} {};", variable(f_.type(r)), v(r)));
        line(depth, fmt::format("if ({}) {{", v(inst.args[0])));
        branch(inst, inst.regions[0], depth + 1);
        line(depth, "} else {");
        branch(inst, inst.regions[1], depth + 1);
        line(depth, "}");
        return;
    }
    case Op::Loop:
        loop(inst, depth);
        return;
    case Op::Yield:
        MOIRE_ICE("stray yield");
    default:
        define(depth, inst.results[0], expression(inst));
        return;
    }
}

// x^n by the same binary exponentiation as Semantics.h's semPowI.
std::string StructuredText::powi(const ir::Inst& inst, int depth) {
    int64_t n = inst.iimm;
    std::string base =
        n < 0 ? fmt::format("({} / {})", syntax_.one, v(inst.args[0])) : v(inst.args[0]);
    uint64_t e = static_cast<uint64_t>(n < 0 ? -n : n);
    if (e == 0) return syntax_.one;
    const std::string decl = constant(ir::Type::F);
    std::string acc;
    std::string cur = fmt::format("p{}", inst.results[0]);
    line(depth, fmt::format("{} {} = {};", decl, cur, base));
    int step = 0;
    while (e) {
        if (e & 1) acc = acc.empty() ? cur : fmt::format("({} * {})", acc, cur);
        e >>= 1;
        if (e) {
            std::string next = fmt::format("p{}_{}", inst.results[0], ++step);
            line(depth, fmt::format("{} {} = {} * {};", decl, next, cur, cur));
            cur = next;
        }
    }
    return acc;
}

std::vector<ValueId> StructuredText::yields(ir::BlockId b) const {
    return f_.blocks[b].insts.back().args;
}

void StructuredText::branch(const ir::Inst& inst, ir::BlockId region, int depth) {
    block(region, depth);
    std::vector<ValueId> y = yields(region);
    for (size_t i = 0; i < y.size(); ++i)
        line(depth, fmt::format("{} = {};", v(inst.results[i]), v(y[i])));
}

void StructuredText::loop(const ir::Inst& inst, int depth) {
    const int id = loops_++;
    auto carried = [&](size_t i) { return fmt::format("l{}_{}", id, i); };
    for (size_t i = 0; i < inst.args.size(); ++i)
        line(depth, fmt::format("{} {} = {};", variable(f_.type(inst.args[i])), carried(i),
                                v(inst.args[i])));
    line(depth, syntax_.loop);
    const ir::Block& cond = f_.blocks[inst.regions[0]];
    const ir::Block& body = f_.blocks[inst.regions[1]];
    for (size_t i = 0; i < cond.params.size(); ++i) define(depth + 1, cond.params[i], carried(i));
    block(inst.regions[0], depth + 1);
    line(depth + 1, fmt::format("if (!{}) break;", v(yields(inst.regions[0])[0])));
    for (size_t i = 0; i < body.params.size(); ++i) define(depth + 1, body.params[i], carried(i));
    block(inst.regions[1], depth + 1);
    // The next values are variables of their own (the body's parameters are copies of the
    // carried variables), so they are all read before any carried variable is written.
    std::vector<ValueId> next = yields(inst.regions[1]);
    for (size_t i = 0; i < next.size(); ++i)
        line(depth + 1, fmt::format("{} = {};", carried(i), v(next[i])));
    line(depth, "}");
    for (size_t i = 0; i < inst.results.size(); ++i) define(depth, inst.results[i], carried(i));
}

} // namespace moire::backend
