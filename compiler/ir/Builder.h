// Building IR. Lowering and the per-pixel pipeline (layers, compositing, the camera) are
// written against this API once; every backend then runs what it builds.
#pragma once

#include "compiler/ir/IR.h"

#include <functional>
#include <initializer_list>
#include <span>

namespace moire::ir {

class Builder {
  public:
    explicit Builder(Function& f) : f_(f) {}

    Function& function() { return f_; }
    BlockId block() const { return block_; }
    void setBlock(BlockId b) { block_ = b; }
    // Source location attached to the instructions built from now on.
    void setLoc(SourceLoc loc) { loc_ = loc; }
    SourceLoc loc() const { return loc_; }

    // Generic form: appends `op` with `args`; the result type comes from the op table
    // (Select takes its operand's type).
    ValueId emit(Op op, std::initializer_list<ValueId> args, double imm = 0.0, int64_t iimm = 0);
    void emitSink(Op op, std::initializer_list<ValueId> args, int64_t iimm);

    // Leaves
    ValueId constF(double v) { return emit(Op::ConstF, {}, v); }
    ValueId constI(int64_t v) { return emit(Op::ConstI, {}, 0.0, v); }
    ValueId constB(bool v) { return emit(Op::ConstB, {}, 0.0, v ? 1 : 0); }
    ValueId param(int slot) { return emit(Op::Param, {}, 0.0, slot); }
    ValueId uniform(int slot) { return emit(Op::Uniform, {}, 0.0, slot); }
    ValueId leaf(Op op) { return emit(op, {}); }

    // Arithmetic shorthands
    ValueId add(ValueId a, ValueId b) { return emit(Op::Add, {a, b}); }
    ValueId sub(ValueId a, ValueId b) { return emit(Op::Sub, {a, b}); }
    ValueId mul(ValueId a, ValueId b) { return emit(Op::Mul, {a, b}); }
    ValueId div(ValueId a, ValueId b) { return emit(Op::Div, {a, b}); }
    ValueId neg(ValueId a) { return emit(Op::Neg, {a}); }
    ValueId min(ValueId a, ValueId b) { return emit(Op::Min, {a, b}); }
    ValueId max(ValueId a, ValueId b) { return emit(Op::Max, {a, b}); }
    ValueId abs(ValueId a) { return emit(Op::Abs, {a}); }
    ValueId floor(ValueId a) { return emit(Op::Floor, {a}); }
    ValueId round(ValueId a) { return emit(Op::Round, {a}); }
    ValueId sqrt(ValueId a) { return emit(Op::Sqrt, {a}); }
    ValueId sin(ValueId a) { return emit(Op::Sin, {a}); }
    ValueId cos(ValueId a) { return emit(Op::Cos, {a}); }
    ValueId hypot(ValueId a, ValueId b) { return emit(Op::Hypot, {a, b}); }
    ValueId select(ValueId c, ValueId a, ValueId b) { return emit(Op::Select, {c, a, b}); }
    ValueId lt(ValueId a, ValueId b) { return emit(Op::Lt, {a, b}); }
    ValueId gt(ValueId a, ValueId b) { return emit(Op::Gt, {a, b}); }
    ValueId le(ValueId a, ValueId b) { return emit(Op::Le, {a, b}); }
    ValueId powi(ValueId a, int64_t n) { return emit(Op::PowI, {a}, 0.0, n); }

    // Composite helpers, expanded into ops (so backends need nothing extra).
    ValueId clamp(ValueId v, ValueId lo, ValueId hi) { return min(max(v, lo), hi); }
    // smoothstep(e0, e1, v) = u^2 (3 - 2u), u = clamp((v - e0) / (e1 - e0), 0, 1)
    ValueId smoothstep(ValueId e0, ValueId e1, ValueId v);
    // mix(a, b, u) = a + (b - a) u
    ValueId mix(ValueId a, ValueId b, ValueId u) { return add(a, mul(sub(b, a), u)); }
    // wrap(v, w): v moved by a multiple of w into [-w/2, w/2)
    ValueId wrap(ValueId v, ValueId w);
    // values[which] for a whole `which` in [0, size), by a chain of selects; the last value
    // where `which` is none of them. For a list indexed by a value of the kernel (a loop's
    // counter, a morph's member).
    ValueId pick(ValueId which, std::span<const ValueId> values);
    // Replaces NaN by `fallback` (NaN != NaN).
    ValueId denan(ValueId v, ValueId fallback) { return select(emit(Op::Ne, {v, v}), fallback, v); }

    // Structured control flow. The callbacks build the regions and return what they yield.
    std::vector<ValueId> ifThenElse(ValueId cond,
                                    const std::function<std::vector<ValueId>()>& thenFn,
                                    const std::function<std::vector<ValueId>()>& elseFn);
    using LoopFn = std::function<std::vector<ValueId>(std::span<const ValueId>)>;
    // while (cond(carried)) carried = body(carried); returns the final carried values.
    std::vector<ValueId> loop(const std::vector<ValueId>& inits, const LoopFn& cond,
                              const LoopFn& body);

    void output(int slot, ValueId v) { emitSink(Op::Output, {v}, slot); }

  private:
    Inst& append(Op op, std::vector<ValueId> args);

    Function& f_;
    BlockId block_ = 0;
    SourceLoc loc_;
};

} // namespace moire::ir
