#include "compiler/backend/llvm/OutlineRegions.h"

#include <cstdint>
#include <cstring>
#include <unordered_map>

namespace moire::llvmbackend {

using ir::Op;
using ir::ValueId;

size_t regionSize(const ir::Function& f, ir::BlockId region) {
    size_t n = 0;
    for (const ir::Inst& inst : f.blocks[region].insts) {
        ++n;
        for (ir::BlockId r : inst.regions) n += regionSize(f, r);
    }
    return n;
}

bool outlinable(const ir::Function& f, ir::BlockId region) {
    for (const ir::Inst& inst : f.blocks[region].insts) {
        if (inst.op == Op::Output) return false;
        for (ir::BlockId r : inst.regions)
            if (!outlinable(f, r)) return false;
    }
    return true;
}

namespace {

// outlinedArm, given the arm's ownSize. An arm that is mostly arms compiled apart (a dispatch
// between solver paths) stays in place: as a function it would cost a call and a module's
// share for a few instructions.
bool outlinedArm(const ir::Function& f, ir::BlockId region, size_t minInsts, size_t own) {
    return minInsts > 0 && own >= minInsts / 4 && regionSize(f, region) >= minInsts &&
           outlinable(f, region);
}

} // namespace

bool outlinedArm(const ir::Function& f, ir::BlockId region, size_t minInsts) {
    return minInsts > 0 && outlinedArm(f, region, minInsts, ownSize(f, region, minInsts));
}

size_t ownSize(const ir::Function& f, ir::BlockId region, size_t minInsts) {
    size_t n = 0;
    for (const ir::Inst& inst : f.blocks[region].insts) {
        ++n;
        for (ir::BlockId r : inst.regions) {
            const size_t own = ownSize(f, r, minInsts);
            if (inst.op != Op::If || !outlinedArm(f, r, minInsts, own)) n += own;
        }
    }
    return n;
}

namespace {

uint64_t bitsOf(double d) {
    uint64_t bits = 0;
    std::memcpy(&bits, &d, sizeof bits);
    return bits;
}

// Leaves whose value is not part of the structure: the caller passes them in.
bool passedIn(Op op) {
    switch (op) {
    case Op::Uniform:
    case Op::PixelX:
    case Op::PixelY:
    case Op::ImageW:
    case Op::ImageH:
        return true;
    default:
        return false;
    }
}

class KeyWriter {
  public:
    KeyWriter(const ir::Function& f, RegionSignature& out) : f_(f), out_(out) {}

    void region(ir::BlockId id) {
        const ir::Block& b = f_.blocks[id];
        out_.key += '{';
        for (ValueId p : b.params) define(p);
        for (const ir::Inst& inst : b.insts) instruction(inst);
        out_.key += '}';
    }

  private:
    void instruction(const ir::Inst& inst) {
        if (passedIn(inst.op)) {
            // Read like a value from outside: the same slot in two layers is no different.
            out_.leaves.push_back(&inst);
            for (ValueId r : inst.results) input(r);
            return;
        }
        out_.key += std::to_string(static_cast<int>(inst.op));
        // The constant's bits: -0 and NaNs are constants of their own.
        if (uint64_t bits = bitsOf(inst.imm); bits != 0) out_.key += "d" + std::to_string(bits);
        if (inst.iimm != 0) out_.key += "i" + std::to_string(inst.iimm);
        out_.key += '(';
        for (ValueId a : inst.args) use(a);
        out_.key += ')';
        for (ir::BlockId r : inst.regions) region(r);
        for (ValueId r : inst.results) define(r);
        out_.key += ';';
    }

    void define(ValueId v) {
        local_[v] = static_cast<int>(local_.size());
        out_.key += 't' + std::to_string(static_cast<int>(f_.type(v)));
    }
    void input(ValueId v) {
        auto [it, added] = inputs_.emplace(v, static_cast<int>(out_.inputs.size()));
        if (added) out_.inputs.push_back(v);
    }
    void use(ValueId v) {
        if (auto it = local_.find(v); it != local_.end()) {
            out_.key += 'l' + std::to_string(it->second) + ',';
            return;
        }
        // A constant from outside (common subexpressions share them) is made again inside:
        // part of the structure, not an argument.
        if (const ir::Inst* def = constantDef(v)) {
            out_.constants.push_back(def);
            local_[v] = static_cast<int>(local_.size());
            out_.key += 'k' + std::to_string(static_cast<int>(def->op)) + ':' +
                        std::to_string(bitsOf(def->imm)) + ':' + std::to_string(def->iimm) + ',';
            return;
        }
        input(v);
        out_.key += 'a' + std::to_string(inputs_.at(v)) + ',';
    }

    const ir::Inst* constantDef(ValueId v) {
        if (defs_.empty()) {
            defs_.assign(f_.numValues(), nullptr);
            auto scan = [&](auto& self, const ir::Block& b) -> void {
                for (const ir::Inst& inst : b.insts) {
                    for (ValueId r : inst.results) defs_[r] = &inst;
                    for (ir::BlockId r : inst.regions) self(self, f_.blocks[r]);
                }
            };
            scan(scan, f_.blocks[0]);
        }
        const ir::Inst* def = defs_[v];
        bool constant =
            def && (def->op == Op::ConstF || def->op == Op::ConstI || def->op == Op::ConstB);
        return constant ? def : nullptr;
    }

    const ir::Function& f_;
    RegionSignature& out_;
    std::vector<const ir::Inst*> defs_; // each value's instruction, found when first needed
    std::unordered_map<ValueId, int> local_, inputs_;
};

} // namespace

RegionSignature regionSignature(const ir::Function& f, ir::BlockId region) {
    RegionSignature out;
    KeyWriter(f, out).region(region);
    // The inputs' types are part of the function's signature.
    out.key += '|';
    for (ValueId v : out.inputs) out.key += std::to_string(static_cast<int>(f.type(v)));
    return out;
}

} // namespace moire::llvmbackend
