#include "compiler/ir/IR.h"

#include "compiler/diag/Diagnostics.h"

#include <fmt/format.h>

namespace moire::ir {

namespace {
using namespace flags;
constexpr Type F = Type::F, I = Type::I, B = Type::B, None = Type::None, Multi = Type::Multi;
constexpr OpInfo kOps[] = {
#define MOIRE_OP(name, spelling, nargs, type, fl) {spelling, nargs, type, fl},
#include "compiler/ir/Ops.def"
#undef MOIRE_OP
};
static_assert(sizeof(kOps) / sizeof(kOps[0]) == kNumOps);
} // namespace

const OpInfo& opInfo(Op op) {
    return kOps[static_cast<int>(op)];
}

const char* typeSpelling(Type t) {
    switch (t) {
    case Type::F:
        return "f";
    case Type::I:
        return "i";
    case Type::B:
        return "b";
    case Type::None:
        return "none";
    case Type::Multi:
        return "multi";
    }
    return "?";
}

size_t Function::instCount() const {
    size_t n = 0;
    for (const Block& b : blocks) n += b.insts.size();
    return n;
}

namespace {
// FNV-1a over the printed-structure fields; stable across runs and platforms.
struct Hasher {
    uint64_t h = 1469598103934665603ull;
    void bytes(const void* p, size_t n) {
        auto c = static_cast<const unsigned char*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
    }
    template <class T>
    void pod(const T& v) {
        bytes(&v, sizeof v);
    }
};
} // namespace

uint64_t structuralHash(const Function& f) {
    Hasher h;
    h.pod(f.numOutputs);
    h.pod(f.blocks.size());
    for (const Block& b : f.blocks) {
        h.pod(b.params.size());
        for (ValueId p : b.params) h.pod(p);
        h.pod(b.insts.size());
        for (const Inst& inst : b.insts) {
            h.pod(inst.op);
            for (ValueId a : inst.args) h.pod(a);
            for (ValueId r : inst.results) h.pod(r);
            for (BlockId r : inst.regions) h.pod(r);
            h.pod(inst.imm);
            h.pod(inst.iimm);
        }
    }
    for (Type t : f.valueTypes) h.pod(t);
    return h.h;
}

} // namespace moire::ir
