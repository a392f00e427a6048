#include "compiler/passes/AutoDiff.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/Semantics.h"

#include <array>

namespace moire::passes {

using namespace ir;

namespace {

constexpr int kDims = 2;
using Tangent = std::array<ValueId, kDims>; // kNoValue: structurally zero

bool isZero(const Tangent& t) {
    return t[0] == kNoValue && t[1] == kNoValue;
}

// Ops whose derivative is zero wherever it exists (piecewise constant), or whose result is
// not a float.
bool hasNoDerivative(Op op) {
    switch (op) {
    case Op::Sign:
    case Op::Floor:
    case Op::Round:
    case Op::ConstF:
    case Op::ConstI:
    case Op::ConstB:
    case Op::PixelX:
    case Op::PixelY:
    case Op::ImageW:
    case Op::ImageH:
    case Op::Time:
    case Op::Param:
    case Op::Uniform:
    case Op::FToI:
    case Op::IToF:
    case Op::Detach: // by definition
        return true;
    default:
        return isCompareOp(op) || opInfo(op).result == Type::B || opInfo(op).result == Type::I;
    }
}

class AutoDiff {
  public:
    explicit AutoDiff(const Function& f) : f_(f), b_(g_) {
        g_.name = f.name;
        g_.numOutputs = f.numOutputs;
        g_.blocks.clear();
        needT_.assign(f.numValues(), false);
        hasT_.assign(f.numValues(), false);
        vmap_.assign(f.numValues(), kNoValue);
        tmap_.assign(f.numValues(), Tangent{kNoValue, kNoValue});
    }

    Function run() {
        analyse();
        g_.blocks.emplace_back();
        b_.setBlock(0);
        emitBlockBody(0);
        return std::move(g_);
    }

  private:
    // ---- analysis -------------------------------------------------------------------
    template <class Fn>
    void forEachInst(Fn&& fn) {
        for (const Block& blk : f_.blocks)
            for (const Inst& inst : blk.insts) fn(inst);
    }
    // Program order, a region's instructions before the If or Loop owning them: a forward
    // analysis then settles in one sweep but for loops' back edges. (Block order took a
    // sweep per If or Loop in a chain of them, quadratic in the number of layers.)
    template <class Fn>
    void forward(BlockId b, Fn& fn) {
        for (const Inst& inst : f_.blocks[b].insts) {
            for (BlockId r : inst.regions) forward(r, fn);
            fn(inst);
        }
    }
    // The reverse: uses before definitions, an If or Loop before its regions.
    template <class Fn>
    void backward(BlockId b, Fn& fn) {
        const auto& insts = f_.blocks[b].insts;
        for (auto it = insts.rbegin(); it != insts.rend(); ++it) {
            fn(*it);
            for (auto r = it->regions.rbegin(); r != it->regions.rend(); ++r) backward(*r, fn);
        }
    }
    const Inst& yieldOf(BlockId b) const { return f_.blocks[b].insts.back(); }

    static bool mark(std::vector<bool>& set, ValueId v) {
        if (set[v]) return false;
        set[v] = true;
        return true;
    }

    void analyse() {
        // hasT: forward, to a fixed point (loops carry tangents around their back edge).
        for (bool changed = true; changed;) {
            changed = false;
            auto step = [&](const Inst& inst) {
                if (inst.op == Op::Indep) {
                    changed |= mark(hasT_, inst.results[0]);
                } else if (inst.op == Op::If) {
                    for (size_t i = 0; i < inst.results.size(); ++i)
                        if (hasT_[yieldOf(inst.regions[0]).args[i]] ||
                            hasT_[yieldOf(inst.regions[1]).args[i]])
                            changed |= mark(hasT_, inst.results[i]);
                } else if (inst.op == Op::Loop) {
                    const Block& cond = f_.blocks[inst.regions[0]];
                    const Block& body = f_.blocks[inst.regions[1]];
                    for (size_t i = 0; i < inst.results.size(); ++i) {
                        if (hasT_[inst.args[i]] || hasT_[yieldOf(inst.regions[1]).args[i]]) {
                            changed |= mark(hasT_, inst.results[i]);
                            changed |= mark(hasT_, cond.params[i]);
                            changed |= mark(hasT_, body.params[i]);
                        }
                    }
                } else if (!inst.results.empty() && !hasNoDerivative(inst.op) &&
                           inst.op != Op::DerivX && inst.op != Op::DerivY) {
                    size_t first = inst.op == Op::Select ? 1 : 0;
                    for (size_t i = first; i < inst.args.size(); ++i)
                        if (hasT_[inst.args[i]]) changed |= mark(hasT_, inst.results[0]);
                }
            };
            forward(0, step);
        }
        // needT: backward from the derivative markers, to a fixed point.
        forEachInst([&](const Inst& inst) {
            if (inst.op == Op::DerivX || inst.op == Op::DerivY) needT_[inst.args[0]] = true;
        });
        for (bool changed = true; changed;) {
            changed = false;
            auto step = [&](const Inst& inst) {
                if (inst.op == Op::If) {
                    for (size_t i = 0; i < inst.results.size(); ++i) {
                        if (!needT_[inst.results[i]]) continue;
                        changed |= mark(needT_, yieldOf(inst.regions[0]).args[i]);
                        changed |= mark(needT_, yieldOf(inst.regions[1]).args[i]);
                    }
                } else if (inst.op == Op::Loop) {
                    const Block& cond = f_.blocks[inst.regions[0]];
                    const Block& body = f_.blocks[inst.regions[1]];
                    for (size_t i = 0; i < inst.results.size(); ++i) {
                        if (!needT_[inst.results[i]] && !needT_[cond.params[i]] &&
                            !needT_[body.params[i]])
                            continue;
                        changed |= mark(needT_, inst.results[i]);
                        changed |= mark(needT_, cond.params[i]);
                        changed |= mark(needT_, body.params[i]);
                        changed |= mark(needT_, inst.args[i]);
                        changed |= mark(needT_, yieldOf(inst.regions[1]).args[i]);
                    }
                } else if (inst.results.size() == 1 && needT_[inst.results[0]] &&
                           !hasNoDerivative(inst.op)) {
                    for (ValueId a : inst.args)
                        if (f_.type(a) == Type::F) changed |= mark(needT_, a);
                }
            };
            backward(0, step);
        }
        // Fix: the result of a derivative marker never gets a tangent, so a derivative of a
        // derivative came out as a silent 0. The pass is first order: refuse instead.
        forEachInst([&](const Inst& inst) {
            if ((inst.op == Op::DerivX || inst.op == Op::DerivY) && needT_[inst.results[0]] &&
                hasT_[inst.args[0]])
                MOIRE_ICE("AD: a derivative of a derivative (%{}) is not supported",
                          inst.results[0]);
        });
    }

    bool wantT(ValueId v) const { return needT_[v] && hasT_[v]; }

    // ---- emission helpers ------------------------------------------------------------
    ValueId v(ValueId old) const {
        MOIRE_CHECK(vmap_[old] != kNoValue, "AD: %{} used before definition", old);
        return vmap_[old];
    }
    Tangent t(ValueId old) const { return wantT(old) ? tmap_[old] : Tangent{kNoValue, kNoValue}; }
    ValueId zero() { return b_.constF(0.0); }
    ValueId orZero(ValueId x) { return x == kNoValue ? zero() : x; }

    // g * d, with the zero rule: an exact zero factor contributes nothing.
    Tangent scale(ValueId g, const Tangent& d) {
        Tangent r{kNoValue, kNoValue};
        for (int k = 0; k < kDims; ++k)
            if (d[k] != kNoValue) r[k] = b_.emit(Op::MulZ, {g, d[k]});
        return r;
    }
    Tangent plus(const Tangent& p, const Tangent& q) {
        Tangent r;
        for (int k = 0; k < kDims; ++k)
            r[k] = p[k] == kNoValue ? q[k] : q[k] == kNoValue ? p[k] : b_.add(p[k], q[k]);
        return r;
    }
    Tangent negate(const Tangent& p) {
        Tangent r{kNoValue, kNoValue};
        for (int k = 0; k < kDims; ++k)
            if (p[k] != kNoValue) r[k] = b_.neg(p[k]);
        return r;
    }
    Tangent divide(const Tangent& p, ValueId d) {
        Tangent r{kNoValue, kNoValue};
        for (int k = 0; k < kDims; ++k)
            if (p[k] != kNoValue) r[k] = b_.div(p[k], d);
        return r;
    }
    Tangent choose(ValueId cond, const Tangent& p, const Tangent& q) {
        Tangent r{kNoValue, kNoValue};
        for (int k = 0; k < kDims; ++k)
            if (p[k] != kNoValue || q[k] != kNoValue)
                r[k] = b_.select(cond, orZero(p[k]), orZero(q[k]));
        return r;
    }

    // ---- the rules -------------------------------------------------------------------
    // Returns the tangent of `inst`'s result; `res` is the new result value.
    Tangent rule(const Inst& inst, ValueId res) {
        auto A = [&](int i) { return v(inst.args[i]); };
        auto dA = [&](int i) { return t(inst.args[i]); };
        switch (inst.op) {
        // d(a + b) = da + db
        case Op::Add:
            return plus(dA(0), dA(1));
        // d(a - b) = da - db
        case Op::Sub:
            return plus(dA(0), negate(dA(1)));
        // d(a b) = a db + b da
        case Op::Mul:
        case Op::MulZ:
            return plus(scale(A(0), dA(1)), scale(A(1), dA(0)));
        // d(a / b) = (da - (a/b) db) / b
        case Op::Div:
            return divide(plus(dA(0), negate(scale(res, dA(1)))), A(1));
        // d(-a) = -da
        case Op::Neg:
            return negate(dA(0));
        // d|a| = sign(a) da   (sign(0) = 0: no slope at the kink)
        case Op::Abs:
            return scale(b_.emit(Op::Sign, {A(0)}), dA(0));
        // d fract(a) = da   (away from the integer jumps)
        case Op::Fract:
            return dA(0);
        // d mod(a, b) = da - floor(a / b) db
        case Op::Mod:
            return plus(dA(0), negate(scale(b_.floor(b_.div(A(0), A(1))), dA(1))));
        // d min(a, b) = db where b < a, else da   (the same tie rule as the value)
        case Op::Min:
            return choose(b_.lt(A(1), A(0)), dA(1), dA(0));
        // d max(a, b) = db where b > a, else da
        case Op::Max:
            return choose(b_.gt(A(1), A(0)), dA(1), dA(0));
        // d sqrt(a) = da / (2 sqrt(a)) for a > 0, else 0; sqrt(a) floored at kSqrtFloor
        case Op::Sqrt: {
            ValueId k = b_.div(b_.constF(0.5), b_.max(res, b_.constF(kSqrtFloor)));
            return scale(b_.select(b_.gt(A(0), b_.constF(0.0)), k, zero()), dA(0));
        }
        // d exp(a) = exp(a) da
        case Op::Exp:
            return scale(res, dA(0));
        // d log(a) = da / a for a > kTiny (the clamp's flat region has no slope)
        case Op::Log: {
            ValueId k = b_.div(b_.constF(1.0), A(0));
            return scale(b_.select(b_.gt(A(0), b_.constF(kTiny)), k, zero()), dA(0));
        }
        // d a^b = b a^(b-1) da + a^b log(a) db
        // Fix: both factors are chain-rule products, so they take the zero rule too. With a
        // plain multiply, d(x^y)/dx at x = 0, y = 0 was 0 * pow(0, -1) = 0 * inf = NaN
        // (the slope of x^0 is 0), and a^b log(a) at a = inf, b < 0 was 0 * inf.
        case Op::Pow: {
            Tangent r{kNoValue, kNoValue};
            if (!isZero(dA(0))) {
                ValueId k = b_.emit(Op::MulZ,
                                    {A(1), b_.emit(Op::Pow, {A(0), b_.sub(A(1), b_.constF(1.0))})});
                r = scale(k, dA(0));
            }
            if (!isZero(dA(1)))
                r = plus(r, scale(b_.emit(Op::MulZ, {res, b_.emit(Op::Log, {A(0)})}), dA(1)));
            return r;
        }
        // d a^n = n a^(n-1) da
        case Op::PowI: {
            if (inst.iimm == 0) return {kNoValue, kNoValue};
            ValueId k =
                b_.mul(b_.constF(static_cast<double>(inst.iimm)), b_.powi(A(0), inst.iimm - 1));
            return scale(k, dA(0));
        }
        // d sin(a) = cos(a) da
        case Op::Sin:
            return scale(b_.cos(A(0)), dA(0));
        // d cos(a) = -sin(a) da
        case Op::Cos:
            return scale(b_.neg(b_.sin(A(0))), dA(0));
        // d tan(a) = (1 + tan(a)^2) da
        case Op::Tan:
            return scale(b_.add(b_.constF(1.0), b_.mul(res, res)), dA(0));
        // d asin(a) = da / sqrt(1 - a^2) for |a| < 1, else 0 (the clamp is flat there)
        // d acos(a) = -da / sqrt(1 - a^2)
        case Op::Asin:
        case Op::Acos: {
            ValueId s =
                b_.sqrt(b_.max(b_.sub(b_.constF(1.0), b_.mul(A(0), A(0))), b_.constF(kTiny)));
            ValueId k = b_.div(b_.constF(inst.op == Op::Asin ? 1.0 : -1.0), s);
            ValueId inside = b_.lt(b_.abs(A(0)), b_.constF(1.0));
            return scale(b_.select(inside, k, zero()), dA(0));
        }
        // d atan(a) = da / (1 + a^2)
        case Op::Atan:
            return scale(b_.div(b_.constF(1.0), b_.add(b_.constF(1.0), b_.mul(A(0), A(0)))), dA(0));
        // d atan2(y, x) = (x dy - y dx) / (x^2 + y^2), the denominator floored at kTiny
        case Op::Atan2: {
            ValueId den = b_.max(b_.add(b_.mul(A(0), A(0)), b_.mul(A(1), A(1))), b_.constF(kTiny));
            return divide(plus(scale(A(1), dA(0)), negate(scale(A(0), dA(1)))), den);
        }
        // d hypot(a, b) = (a da + b db) / hypot(a, b), the denominator floored at kTiny
        case Op::Hypot: {
            ValueId den = b_.max(res, b_.constF(kTiny));
            return divide(plus(scale(A(0), dA(0)), scale(A(1), dA(1))), den);
        }
        // d select(c, a, b) = select(c, da, db)
        case Op::Select:
            return choose(A(0), dA(1), dA(2));
        default:
            MOIRE_ICE("AD: no rule for op '{}'", spelling(inst.op));
        }
    }

    // ---- the walk ----------------------------------------------------------------------
    void emitBlockBody(BlockId old) {
        for (const Inst& inst : f_.blocks[old].insts) emitInst(inst);
    }

    std::vector<ValueId> withTangents(const std::vector<ValueId>& olds,
                                      const std::vector<ValueId>& slots, bool zeroFill) {
        std::vector<ValueId> out;
        for (ValueId o : olds) out.push_back(v(o));
        for (size_t i = 0; i < slots.size(); ++i) {
            if (!wantT(slots[i])) continue;
            Tangent d = t(olds[i]);
            for (int k = 0; k < kDims; ++k) out.push_back(zeroFill ? orZero(d[k]) : d[k]);
        }
        return out;
    }

    void emitInst(const Inst& inst) {
        b_.setLoc(inst.loc);
        switch (inst.op) {
        case Op::Yield:
            return; // handled by the enclosing region
        case Op::DerivX:
        case Op::DerivY: {
            Tangent d = t(inst.args[0]);
            ValueId x = d[inst.op == Op::DerivX ? 0 : 1];
            // A copy keeps the marker's result a distinct value.
            vmap_[inst.results[0]] = x == kNoValue ? zero() : x;
            return;
        }
        case Op::Detach:
            // The value itself, without a tangent: the marker goes with the pass.
            vmap_[inst.results[0]] = v(inst.args[0]);
            return;
        case Op::Indep: {
            ValueId r = v(inst.args[0]);
            vmap_[inst.results[0]] = r;
            if (wantT(inst.results[0])) {
                Tangent d{kNoValue, kNoValue};
                MOIRE_CHECK(inst.iimm >= 0 && inst.iimm < kDims, "indep index");
                d[inst.iimm] = b_.constF(1.0);
                tmap_[inst.results[0]] = d;
            }
            return;
        }
        case Op::If: {
            const Inst& yt = yieldOf(inst.regions[0]);
            const Inst& ye = yieldOf(inst.regions[1]);
            auto branch = [&](BlockId region, const Inst& y) {
                return [&, region] {
                    emitBlockBody(region);
                    return withTangents(y.args, inst.results, true);
                };
            };
            std::vector<ValueId> res = b_.ifThenElse(v(inst.args[0]), branch(inst.regions[0], yt),
                                                     branch(inst.regions[1], ye));
            bindResults(inst.results, res);
            return;
        }
        case Op::Loop: {
            const Block& cond = f_.blocks[inst.regions[0]];
            const Block& body = f_.blocks[inst.regions[1]];
            std::vector<ValueId> inits = withTangents(inst.args, inst.results, true);
            auto region = [&](const Block& blk, BlockId id, bool isBody) {
                return [&, id, isBody](std::span<const ValueId> params) {
                    bindResults(blk.params, std::vector<ValueId>(params.begin(), params.end()));
                    emitBlockBody(id);
                    const Inst& y = yieldOf(id);
                    if (!isBody) return std::vector<ValueId>{v(y.args[0])};
                    return withTangents(y.args, inst.results, true);
                };
            };
            std::vector<ValueId> res = b_.loop(inits, region(cond, inst.regions[0], false),
                                               region(body, inst.regions[1], true));
            bindResults(inst.results, res);
            return;
        }
        default:
            break;
        }
        // Ordinary instruction: copy it, then its tangent if anything needs it.
        Inst copy = inst;
        for (ValueId& a : copy.args) a = v(a);
        copy.results.clear();
        for (ValueId r : inst.results) {
            ValueId nr = g_.newValue(f_.type(r));
            copy.results.push_back(nr);
            vmap_[r] = nr;
        }
        g_.blocks[b_.block()].insts.push_back(std::move(copy));
        if (inst.results.size() == 1 && wantT(inst.results[0]) && !hasNoDerivative(inst.op))
            tmap_[inst.results[0]] = rule(inst, vmap_[inst.results[0]]);
    }

    // Binds old results (or params) to new values laid out as [values..., tangents...].
    void bindResults(const std::vector<ValueId>& olds, const std::vector<ValueId>& news) {
        size_t next = olds.size();
        for (size_t i = 0; i < olds.size(); ++i) {
            vmap_[olds[i]] = news[i];
        }
        // Tangent slots follow in the same order as withTangents() produced them; the slot
        // set is decided by the owning instruction's results, which share wantT with params.
        for (size_t i = 0; i < olds.size(); ++i) {
            if (!slotWanted(olds, i)) continue;
            Tangent d;
            for (int k = 0; k < kDims; ++k) d[k] = news[next++];
            tmap_[olds[i]] = d;
        }
        MOIRE_CHECK(next == news.size(), "AD: tangent slots mismatch");
    }
    bool slotWanted(const std::vector<ValueId>& olds, size_t i) const { return wantT(olds[i]); }

    const Function& f_;
    Function g_;
    Builder b_;
    std::vector<bool> needT_, hasT_;
    std::vector<ValueId> vmap_;
    std::vector<Tangent> tmap_;
};

} // namespace

Function autoDiff(const Function& f) {
    Function g = AutoDiff(f).run();
    verify(g);
    return g;
}

} // namespace moire::passes
