#include "compiler/ir/IR.h"

#include <fmt/format.h>

namespace moire::ir {

namespace {

std::string valueList(const std::vector<ValueId>& vs) {
    std::string s;
    for (size_t i = 0; i < vs.size(); ++i) s += fmt::format("{}%{}", i ? ", " : "", vs[i]);
    return s;
}

void printBlock(std::string& out, const Function& f, BlockId id, int depth);

void printInst(std::string& out, const Function& f, const Inst& inst, int depth) {
    std::string pad(depth * 2, ' ');
    out += pad;
    if (!inst.results.empty()) out += valueList(inst.results) + " = ";
    out += spelling(inst.op);
    switch (inst.op) {
    case Op::ConstF:
        out += fmt::format(" {}", inst.imm);
        break;
    case Op::ConstI:
        out += fmt::format(" {}", inst.iimm);
        break;
    case Op::ConstB:
        out += inst.iimm ? " true" : " false";
        break;
    case Op::Param:
    case Op::Uniform:
    case Op::Output:
    case Op::Tally:
        out += fmt::format(" [{}]", inst.iimm);
        break;
    case Op::PowI:
    case Op::Indep:
        out += fmt::format(" {}", inst.iimm);
        break;
    default:
        break;
    }
    if (!inst.args.empty())
        out += (inst.op == Op::PowI || inst.op == Op::Indep || inst.op == Op::Output ? ", " : " ") +
               valueList(inst.args);
    if (inst.results.size() == 1 && inst.regions.empty())
        out += fmt::format(" : {}", typeSpelling(f.type(inst.results[0])));
    if (inst.op == Op::If) {
        out += " then";
        printBlock(out, f, inst.regions[0], depth);
        out += " else";
        printBlock(out, f, inst.regions[1], depth);
    } else if (inst.op == Op::Loop) {
        out += " cond";
        printBlock(out, f, inst.regions[0], depth);
        out += " body";
        printBlock(out, f, inst.regions[1], depth);
    }
    out += "\n";
}

void printBlock(std::string& out, const Function& f, BlockId id, int depth) {
    const Block& b = f.blocks[id];
    if (!b.params.empty()) out += "(" + valueList(b.params) + ")";
    out += " {\n";
    for (const Inst& inst : b.insts) printInst(out, f, inst, depth + 1);
    out += std::string(depth * 2, ' ') + "}";
}

} // namespace

std::string print(const Function& f) {
    std::string out =
        fmt::format("func {} (outputs {}, values {})", f.name, f.numOutputs, f.numValues());
    printBlock(out, f, 0, 0);
    return out + "\n";
}

} // namespace moire::ir
