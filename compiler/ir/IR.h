// The moire IR: typed SSA with structured control flow.
//
// A Function is a tree of Blocks. Block 0 is the entry. An `If` owns two blocks (then,
// else) and a `Loop` two (cond, body); each ends with a `Yield`. Blocks have parameters
// (a Loop's carried values) and may use any value defined earlier in an enclosing block.
// There are no gotos, so every backend (interpreter, LLVM, GLSL) translates the same tree
// op by op, and later passes see loops as loops.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/ir/IdList.h"

#include <cstdint>
#include <string>
#include <vector>

namespace moire::ir {

enum class Op : uint8_t {
#define MOIRE_OP(name, spelling, nargs, type, flags) name,
#include "compiler/ir/Ops.def"
#undef MOIRE_OP
};
constexpr int kNumOps = 0
#define MOIRE_OP(name, spelling, nargs, type, flags) +1
#include "compiler/ir/Ops.def"
#undef MOIRE_OP
    ;

enum class Type : uint8_t { F, I, B, None, Multi };
const char* typeSpelling(Type t);

namespace flags {
enum : uint8_t { Pure = 1, Leaf = 2, Control = 4, Sink = 8 };
}

struct OpInfo {
    const char* spelling;
    int numArgs;
    Type result;
    uint8_t flags;
};
const OpInfo& opInfo(Op op);
inline const char* spelling(Op op) {
    return opInfo(op).spelling;
}
inline bool isPure(Op op) {
    return opInfo(op).flags & flags::Pure;
}

// Counters a kernel can bump with `tally` (read back from the interpreter).
constexpr int kMaxTallies = 4;

using ValueId = uint32_t;
using BlockId = uint32_t;
constexpr ValueId kNoValue = UINT32_MAX;

struct Inst {
    Op op{};
    IdList args;
    IdList results;   // one for ordinary ops; several for If / Loop; none for sinks
    IdList regions;   // If: then, else. Loop: cond, body.
    double imm = 0.0; // ConstF
    int64_t iimm = 0; // ConstI/B value, slot, exponent or independent index
    SourceLoc loc;

    ValueId result() const { return results.empty() ? kNoValue : results[0]; }
};

struct Block {
    std::vector<ValueId> params;
    std::vector<Inst> insts;
};

struct Function {
    std::string name;
    std::vector<Block> blocks{Block{}}; // blocks[0] is the entry
    std::vector<Type> valueTypes;
    int numOutputs = 0;

    ValueId newValue(Type t) {
        valueTypes.push_back(t);
        return static_cast<ValueId>(valueTypes.size() - 1);
    }
    BlockId newBlock() {
        blocks.emplace_back();
        return static_cast<BlockId>(blocks.size() - 1);
    }
    Type type(ValueId v) const { return valueTypes.at(v); }
    size_t numValues() const { return valueTypes.size(); }
    // Instructions in all blocks (for statistics and op-coverage checks).
    size_t instCount() const;
};

// `moire compile --dump=ir`
std::string print(const Function& f);
// Checks the structural invariants (types, arity, dominance, yields); throws InternalError.
void verify(const Function& f);
// A hash of everything that decides the generated code; literal values read through
// Param/Uniform are not part of it, so editing a number keeps the hash.
uint64_t structuralHash(const Function& f);

} // namespace moire::ir
