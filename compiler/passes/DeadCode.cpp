#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

namespace moire::passes {

using namespace ir;

namespace {

class Dce : public Rewriter {
  public:
    explicit Dce(const Function& f)
        : Rewriter(f), live_(f.numValues(), false), sinks_(f.blocks.size(), -1) {
        analyse();
    }

  private:
    bool isLive(const Inst& inst) const {
        if (opInfo(inst.op).flags & flags::Sink) return true;
        // Fix: an if or loop whose results are unused was dropped with everything in it,
        // including an output written inside one of its regions.
        for (BlockId r : inst.regions)
            if (hasSink(r)) return true;
        for (ValueId r : inst.results)
            if (live_[r]) return true;
        return false;
    }
    // Whether block `b`, or a region nested in it, writes an output (memoised).
    bool hasSink(BlockId b) const {
        if (sinks_[b] < 0) {
            sinks_[b] = 0;
            for (const Inst& inst : src_.blocks[b].insts) {
                if (opInfo(inst.op).flags & flags::Sink) sinks_[b] = 1;
                for (BlockId r : inst.regions)
                    if (hasSink(r)) sinks_[b] = 1;
            }
        }
        return sinks_[b] == 1;
    }
    bool markArgs(const std::vector<ValueId>& args) {
        bool changed = false;
        for (ValueId a : args)
            if (!live_[a]) live_[a] = changed = true;
        return changed;
    }

    // Backward liveness to a fixed point. A live If or Loop keeps all its yields (regions
    // are not pruned slot by slot). Uses are visited before definitions, an If or Loop
    // before its regions, so one sweep settles everything but loops' back edges; sweeping
    // the blocks in their numbering took a sweep per If or Loop in a chain of them.
    bool sweep(BlockId b) {
        bool changed = false;
        const auto& insts = src_.blocks[b].insts;
        for (auto it = insts.rbegin(); it != insts.rend(); ++it) {
            const Inst& inst = *it;
            if (inst.op == Op::Yield) continue;
            if (isLive(inst)) {
                changed |= markArgs(inst.args);
                for (BlockId r : inst.regions)
                    changed |= markArgs(src_.blocks[r].insts.back().args);
            }
            // Every region is swept, as every block was before, whether its owner is live.
            for (auto r = inst.regions.rbegin(); r != inst.regions.rend(); ++r)
                changed |= sweep(*r);
        }
        return changed;
    }
    void analyse() {
        while (sweep(0)) {
        }
    }

    bool visit(const Inst& inst) override {
        if (inst.op == Op::Yield) return false;
        bool removable = isPure(inst.op) || inst.op == Op::If || inst.op == Op::Loop ||
                         inst.op == Op::Indep || inst.op == Op::Detach || inst.op == Op::DerivX ||
                         inst.op == Op::DerivY || (opInfo(inst.op).flags & flags::Leaf);
        return removable && !isLive(inst);
    }

    std::vector<bool> live_;
    mutable std::vector<int8_t> sinks_; // per block: -1 unknown, 0 no output inside, 1 has one
};

} // namespace

Function eliminateDeadCode(const Function& f, Check check) {
    return Dce(f).run(check);
}

Function simplify(const Function& f) {
    Function cur;
    for (int round = 0; round < 5; ++round) {
        size_t merged = 0;
        cur = eliminateDeadCode(
            eliminateCommonSubexpressions(constantFold(round ? cur : f, Check::Trust), Check::Trust,
                                          &merged),
            Check::Trust);
        if (merged == 0) break;
    }
    verify(cur);
    return cur;
}

} // namespace moire::passes
