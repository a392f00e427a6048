#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

namespace moire::passes {

using namespace ir;

namespace {

class Dce : public Rewriter {
public:
    explicit Dce(const Function& f) : Rewriter(f), live_(f.numValues(), false) { analyse(); }

private:
    bool isLive(const Inst& inst) const {
        if (opInfo(inst.op).flags & flags::Sink) return true;
        for (ValueId r : inst.results)
            if (live_[r]) return true;
        return false;
    }
    bool markArgs(const std::vector<ValueId>& args) {
        bool changed = false;
        for (ValueId a : args)
            if (!live_[a]) live_[a] = changed = true;
        return changed;
    }

    // Backward liveness to a fixed point. A live If or Loop keeps all its yields (regions
    // are not pruned slot by slot).
    void analyse() {
        for (bool changed = true; changed;) {
            changed = false;
            for (const Block& blk : src_.blocks) {
                for (auto it = blk.insts.rbegin(); it != blk.insts.rend(); ++it) {
                    const Inst& inst = *it;
                    if (inst.op == Op::Yield || !isLive(inst)) continue;
                    changed |= markArgs(inst.args);
                    for (BlockId r : inst.regions) changed |= markArgs(src_.blocks[r].insts.back().args);
                }
            }
        }
    }

    bool visit(const Inst& inst) override {
        if (inst.op == Op::Yield) return false;
        bool removable = isPure(inst.op) || inst.op == Op::If || inst.op == Op::Loop ||
                         inst.op == Op::Indep || inst.op == Op::DerivX || inst.op == Op::DerivY ||
                         (opInfo(inst.op).flags & flags::Leaf);
        return removable && !isLive(inst);
    }

    std::vector<bool> live_;
};

} // namespace

Function eliminateDeadCode(const Function& f) { return Dce(f).run(); }

Function simplify(const Function& f) {
    Function cur = eliminateDeadCode(eliminateCommonSubexpressions(constantFold(f)));
    for (int round = 0; round < 4; ++round) {
        size_t before = cur.instCount();
        cur = eliminateDeadCode(eliminateCommonSubexpressions(constantFold(cur)));
        if (cur.instCount() >= before) break;
    }
    return cur;
}

} // namespace moire::passes
