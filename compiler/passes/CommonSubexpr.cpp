#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

#include <array>
#include <cstring>
#include <unordered_map>

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
    struct Key {
        Op op;
        std::array<ValueId, 3> args{kNoValue, kNoValue, kNoValue};
        uint64_t immBits = 0;
        int64_t iimm = 0;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = static_cast<uint64_t>(k.op) * 0x9E3779B97F4A7C15ull;
            auto mix = [&h](uint64_t v) { h = (h ^ v) * 0xFF51AFD7ED558CCDull; };
            for (ValueId a : k.args) mix(a);
            mix(k.immBits);
            mix(static_cast<uint64_t>(k.iimm));
            return static_cast<size_t>(h ^ (h >> 32));
        }
    };

    bool visit(const Inst& inst) override {
        if (!isPure(inst.op) || inst.results.size() != 1 || inst.args.size() > 3) return false;
        Key key{inst.op};
        auto& args = key.args;
        for (size_t i = 0; i < inst.args.size(); ++i) args[i] = map(inst.args[i]);
        // Commutative ops are keyed with sorted operands. (min and max are not commutative
        // under their NaN rule, so they keep their order.)
        bool commutative = inst.op == Op::Add || inst.op == Op::Mul || inst.op == Op::MulZ ||
                           inst.op == Op::Eq || inst.op == Op::Ne || inst.op == Op::And ||
                           inst.op == Op::Or || inst.op == Op::Hypot || inst.op == Op::IAdd ||
                           inst.op == Op::IMul;
        if (commutative && args[0] > args[1]) std::swap(args[0], args[1]);
        std::memcpy(&key.immBits, &inst.imm, sizeof key.immBits);
        key.iimm = inst.iimm;
        for (auto it = scopes_.rbegin(); it != scopes_.rend(); ++it) {
            auto found = it->find(key);
            if (found != it->end()) {
                bind(inst.results[0], found->second);
                ++merged;
                return true;
            }
        }
        scopes_.back().emplace(key, copy(inst)[0]);
        return true;
    }

  public:
    size_t merged = 0;

  private:
    void enterRegion() override { scopes_.emplace_back(); }
    void leaveRegion() override { scopes_.pop_back(); }

    std::vector<std::unordered_map<Key, ValueId, KeyHash>> scopes_{1};
};

} // namespace

Function eliminateCommonSubexpressions(const Function& f, Check check, size_t* merged) {
    Cse cse(f);
    Function out = cse.run(check);
    if (merged) *merged = cse.merged;
    return out;
}

} // namespace moire::passes
