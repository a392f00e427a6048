#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

#include <cstring>
#include <map>
#include <tuple>

namespace moire::passes {

using namespace ir;

namespace {

// Value numbering: a pure instruction identical to one already visible (same op, operands
// and immediates) is replaced by it. A value defined inside a region is visible only there,
// so the table is a stack of scopes.
class Cse : public Rewriter {
  public:
    using Rewriter::Rewriter;

  private:
    using Key = std::tuple<Op, std::vector<ValueId>, uint64_t, int64_t>;

    bool visit(const Inst& inst) override {
        if (!isPure(inst.op) || inst.results.size() != 1) return false;
        std::vector<ValueId> args;
        for (ValueId a : inst.args) args.push_back(map(a));
        // Commutative ops are keyed with sorted operands. (min and max are not commutative
        // under their NaN rule, so they keep their order.)
        bool commutative = inst.op == Op::Add || inst.op == Op::Mul || inst.op == Op::MulZ ||
                           inst.op == Op::Eq || inst.op == Op::Ne || inst.op == Op::And ||
                           inst.op == Op::Or || inst.op == Op::Hypot || inst.op == Op::IAdd ||
                           inst.op == Op::IMul;
        if (commutative && args[0] > args[1]) std::swap(args[0], args[1]);
        uint64_t immBits;
        std::memcpy(&immBits, &inst.imm, sizeof immBits);
        Key key{inst.op, args, immBits, inst.iimm};
        for (auto it = scopes_.rbegin(); it != scopes_.rend(); ++it) {
            auto found = it->find(key);
            if (found != it->end()) {
                bind(inst.results[0], found->second);
                return true;
            }
        }
        std::vector<ValueId> res = copy(inst);
        scopes_.back().emplace(std::move(key), res[0]);
        return true;
    }
    void enterRegion() override { scopes_.emplace_back(); }
    void leaveRegion() override { scopes_.pop_back(); }

    std::vector<std::map<Key, ValueId>> scopes_{1};
};

} // namespace

Function eliminateCommonSubexpressions(const Function& f) {
    return Cse(f).run();
}

} // namespace moire::passes
