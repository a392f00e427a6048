#include "compiler/lower/LowerExpr.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/sema/Builtins.h"

#include <cmath>
#include <numbers>

namespace moire::lower {

using namespace ast;
using ir::Op;
using ir::ValueId;

ValueId ExprLowering::literal(double value, int slot) {
    // A user's number is read from the literal table, so editing it changes a uniform and
    // not the kernel; a standard-library number is a constant the compiler may fold.
    return slot >= 0 ? b_.param(slot) : b_.constF(value);
}

Vals ExprLowering::param(const Decl& p, Frame& frame) {
    // The value a tool set (its literal slots, when the switch slot is 1), else the default:
    // both uniforms, so a slider never changes the kernel (compiler/Parameters.h).
    auto it = frame.fields.find(&p);
    if (it != frame.fields.end()) return it->second;
    Vals v = lower(*p.value, frame);
    if (p.setSlot >= 0) {
        ValueId set = b_.lt(b_.constF(0.5), b_.param(p.setSlot));
        for (size_t i = 0; i < v.size(); ++i)
            v[i] = b_.select(set, b_.param(p.valueSlot + static_cast<int>(i)), v[i]);
    }
    frame.fields[&p] = v;
    return v;
}

ValueId ExprLowering::scalar(const Expr& e, Frame& frame) {
    Vals v = lower(e, frame);
    MOIRE_CHECK(v.size() == 1, "expected a scalar, got {} components", v.size());
    return v[0];
}

Vals ExprLowering::property(const Decl* block, const std::vector<sema::PropertySpec>& table,
                            std::string_view name, Frame& frame) {
    if (const Property* p = block ? block->prop(name) : nullptr) return lower(*p->value, frame);
    Vals v;
    for (double d : sema::propertySpec(table, name).defaults) v.push_back(b_.constF(d));
    return v;
}

Vals ExprLowering::lower(const Expr& e, Frame& frame) {
    b_.setLoc(e.range.begin);
    switch (e.kind) {
    case ExprKind::Error:
        MOIRE_ICE("lowering an expression that failed to parse");
    case ExprKind::Number:
        return {literal(e.number, e.literalSlot)};
    case ExprKind::Color: {
        Vals v;
        for (int i = 0; i < 4; ++i)
            v.push_back(literal(e.rgba[i], e.literalSlot < 0 ? -1 : e.literalSlot + i));
        return v;
    }
    case ExprKind::Name:
        return name(e, frame);
    case ExprKind::Vector:
        return {scalar(*e.args[0], frame), scalar(*e.args[1], frame)};
    case ExprKind::Unary: {
        Vals v = lower(*e.args[0], frame);
        if (e.un == UnOp::Neg)
            for (ValueId& c : v) c = b_.neg(c);
        return v;
    }
    case ExprKind::Binary:
        return binary(e, frame);
    case ExprKind::Call:
        return call(e, frame);
    }
    MOIRE_ICE("unhandled expression kind");
}

Vals ExprLowering::name(const Expr& e, Frame& frame) {
    switch (e.ref) {
    case RefKind::Builtin:
        switch (static_cast<sema::Name>(e.refIndex)) {
        case sema::Name::X:
            return {frame.x};
        case sema::Name::Y:
            return {frame.y};
        case sema::Name::R:
            if (frame.r == ir::kNoValue) frame.r = b_.hypot(frame.x, frame.y);
            return {frame.r};
        case sema::Name::Theta:
            if (frame.theta == ir::kNoValue) frame.theta = b_.emit(Op::Atan2, {frame.y, frame.x});
            return {frame.theta};
        case sema::Name::Pi:
            return {b_.constF(std::numbers::pi)};
        case sema::Name::Tau:
            return {b_.constF(2.0 * std::numbers::pi)};
        case sema::Name::E:
            return {b_.constF(std::numbers::e)};
        case sema::Name::T:
            return {b_.leaf(Op::Time)};
        }
        break;
    case RefKind::Field: {
        auto it = frame.fields.find(e.refDecl);
        if (it != frame.fields.end()) return it->second;
        Vals v = lower(*e.refDecl->value, frame);
        frame.fields[e.refDecl] = v;
        return v;
    }
    case RefKind::Param:
        return param(*e.refDecl, frame);
    case RefKind::Boolean: // as the number 1 or 0 (select reads it so)
        return {b_.constF(e.refIndex)};
    case RefKind::FamilyParam:
        MOIRE_CHECK(frame.family == e.refDecl, "parameter used outside its family");
        return frame.params.at(e.refIndex);
    case RefKind::Let:
        MOIRE_CHECK(frame.family == e.refDecl && e.refIndex < static_cast<int>(frame.lets.size()),
                    "let used before it is lowered");
        return frame.lets[e.refIndex];
    case RefKind::Spacing:
        MOIRE_CHECK(frame.spacing != ir::kNoValue, "spacing outside a family");
        return {frame.spacing};
    case RefKind::EasingVar:
        MOIRE_CHECK(frame.u != ir::kNoValue, "u outside an easing");
        return {frame.u};
    case RefKind::Timing:
    case RefKind::Family:
    case RefKind::Easing:
        MOIRE_ICE("a declaration's name ('{}') reached lowering as a value", e.name);
    case RefKind::Unresolved:
        break;
    }
    MOIRE_ICE("unresolved name '{}' reached lowering", e.name);
}

namespace {
// The exponent of `a ^ n` when it is a small whole literal: then the power is a chain of
// multiplications (exact, and defined for negative bases), and n is part of the structure.
std::optional<int> integerExponent(const Expr& e) {
    const Expr* n = &e;
    bool negative = false;
    if (n->kind == ExprKind::Unary) {
        negative = n->un == UnOp::Neg;
        n = n->args[0].get();
    }
    if (n->kind != ExprKind::Number || n->unit != Unit::None) return std::nullopt;
    if (n->number != std::floor(n->number) || std::fabs(n->number) > 64) return std::nullopt;
    return static_cast<int>(negative ? -n->number : n->number);
}
} // namespace

Vals ExprLowering::binary(const Expr& e, Frame& frame) {
    const Expr& lhsE = *e.args[0];
    const Expr& rhsE = *e.args[1];
    if (e.bin == BinOp::Pow) {
        if (auto n = integerExponent(rhsE)) return {b_.powi(scalar(lhsE, frame), *n)};
        ValueId x = scalar(rhsE, frame);
        if (lhsE.kind == ExprKind::Name && lhsE.ref == RefKind::Builtin &&
            static_cast<sema::Name>(lhsE.refIndex) == sema::Name::E)
            return {b_.emit(Op::Exp, {x})};
        return {b_.emit(Op::Pow, {scalar(lhsE, frame), x})};
    }
    // A chain `a + b - c * d ...`: its left spine in a loop, from the first operand up, in
    // the order recursion would take (a chain may be far longer than the stack is deep).
    std::vector<const Expr*> spine;
    for (const Expr* link = &e; isChainLink(*link); link = link->args[0].get())
        spine.push_back(link);
    Vals a = lower(*spine.back()->args[0], frame);
    for (auto it = spine.rbegin(); it != spine.rend(); ++it) {
        const Expr& link = **it;
        Vals c = lower(*link.args[1], frame);
        b_.setLoc(link.range.begin);
        Op op = link.bin == BinOp::Add   ? Op::Add
                : link.bin == BinOp::Sub ? Op::Sub
                : link.bin == BinOp::Mul ? Op::Mul
                                         : Op::Div;
        // Component-wise, broadcasting a scalar against a vector.
        size_t n = std::max(a.size(), c.size());
        Vals out;
        for (size_t i = 0; i < n; ++i) {
            ValueId l = a.size() == 1 ? a[0] : a[i];
            ValueId r = c.size() == 1 ? c[0] : c[i];
            out.push_back(b_.emit(op, {l, r}));
        }
        a = std::move(out);
    }
    return a;
}

Vals ExprLowering::call(const Expr& e, Frame& frame) {
    std::vector<Vals> a;
    for (const ExprPtr& arg : e.args)
        // A timing's name is not a value: ramp and progress look the timing up instead.
        a.push_back(arg->ref == RefKind::Timing ? Vals{} : lower(*arg, frame));
    b_.setLoc(e.range.begin);
    auto s = [&](int i) { return a[i][0]; };
    auto unary = [&](Op op) { return Vals{b_.emit(op, {s(0)})}; };
    auto binaryOp = [&](Op op) { return Vals{b_.emit(op, {s(0), s(1)})}; };
    switch (static_cast<sema::Fn>(e.refIndex)) {
    case sema::Fn::Sin:
        return unary(Op::Sin);
    case sema::Fn::Cos:
        return unary(Op::Cos);
    case sema::Fn::Tan:
        return unary(Op::Tan);
    case sema::Fn::Asin:
        return unary(Op::Asin);
    case sema::Fn::Acos:
        return unary(Op::Acos);
    case sema::Fn::Atan:
        return unary(Op::Atan);
    case sema::Fn::Atan2:
        return binaryOp(Op::Atan2);
    case sema::Fn::Exp:
        return unary(Op::Exp);
    case sema::Fn::Log:
        return unary(Op::Log);
    case sema::Fn::Sqrt:
        return unary(Op::Sqrt);
    case sema::Fn::Abs:
        return unary(Op::Abs);
    case sema::Fn::Floor:
        return unary(Op::Floor);
    case sema::Fn::Fract:
        return unary(Op::Fract);
    case sema::Fn::Round:
        return unary(Op::Round);
    case sema::Fn::Sign:
        return unary(Op::Sign);
    case sema::Fn::Min:
        return binaryOp(Op::Min);
    case sema::Fn::Max:
        return binaryOp(Op::Max);
    case sema::Fn::Mod:
        return binaryOp(Op::Mod);
    case sema::Fn::Hypot:
        return binaryOp(Op::Hypot);
    case sema::Fn::Clamp:
        return {b_.clamp(s(0), s(1), s(2))};
    case sema::Fn::Wrap:
        return {b_.wrap(s(0), s(1))};
    case sema::Fn::Smoothstep:
        return {b_.smoothstep(s(0), s(1), s(2))};
    case sema::Fn::Mix: {
        Vals out;
        for (size_t i = 0; i < a[0].size(); ++i) out.push_back(b_.mix(a[0][i], a[1][i], s(2)));
        return out;
    }
    case sema::Fn::Length:
        return {b_.hypot(a[0][0], a[0][1])};
    case sema::Fn::Rgb:
        return {s(0), s(1), s(2), b_.constF(1.0)};
    case sema::Fn::Rgba:
        return {s(0), s(1), s(2), s(3)};
    case sema::Fn::Step: // step(edge, v): 1 from the edge on
        return {b_.select(b_.emit(Op::Ge, {s(1), s(0)}), b_.constF(1.0), b_.constF(0.0))};
    case sema::Fn::Select: { // a boolean is 0 or 1; a set value is exactly one of them
        ValueId on = b_.lt(b_.constF(0.5), s(0));
        Vals out;
        for (size_t i = 0; i < a[1].size(); ++i) out.push_back(b_.select(on, a[1][i], a[2][i]));
        return out;
    }
    case sema::Fn::Progress:
    case sema::Fn::Ramp: {
        MOIRE_CHECK(progress_, "no timings to lower '{}' with", e.name);
        ValueId p = progress_(e.args[0]->refDecl).eased;
        if (e.args.size() == 1) return {p};
        Vals out; // from a[1] to a[2], component by component (colours too)
        for (size_t i = 0; i < a[1].size(); ++i) out.push_back(b_.mix(a[1][i], a[2][i], p));
        return out;
    }
    }
    MOIRE_ICE("unhandled function '{}'", e.name);
}

} // namespace moire::lower
