// Checking expressions: name resolution, the types and units of operators and calls, and
// what each expression depends on (the position, the clock).
#include "compiler/diag/Suggest.h"
#include "compiler/sema/Builtins.h"
#include "compiler/sema/Checker.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace moire::sema::detail {

void Checker::expectType(const Expr& e, Type want, const std::string& what) {
    if (e.type == Type::Error || want == Type::Error || e.type == want) return;
    if (want == Type::Angle && e.type == Type::Num) {
        if (isLiteralZero(e)) return;
        // The example repeats the number written, sign included (`-30` -> -30deg).
        const Expr* lit = &e;
        bool negative = false;
        while (lit->kind == ExprKind::Unary) {
            negative ^= lit->un == UnOp::Neg;
            lit = lit->args[0].get();
        }
        std::string example = lit->kind == ExprKind::Number
                                  ? fmt::format("{}{}", negative ? "-" : "", lit->number)
                                  : "30";
        diags_.error(e.range, Msg::AngleNeedsUnit, what, example, example);
        return;
    }
    diags_.error(e.range, Msg::TypeMismatch, what, typeName(want), typeName(e.type));
}

void Checker::inherit(Expr& e) {
    for (const ExprPtr& a : e.args) {
        e.dependsOnPosition |= a->dependsOnPosition;
        e.dependsOnTime |= a->dependsOnTime;
    }
}

void Checker::tooDeep(const Expr& e) {
    // Once is enough: the rest of a long chain would report it again every
    // kMaxExpandedDepth links.
    if (!tooDeepReported_) diags_.error(e.opRange, Msg::FieldsTooDeep, e.name, kMaxExpandedDepth);
    tooDeepReported_ = true;
}

// Checks `e` and leaves in lastHeight_ its height with fields and lets filled in.
Type Checker::checkExpr(Expr& e, const Scope& scope) {
    DepthGuard guard(exprDepth_);
    if (isChainLink(e)) {
        // A chain's left spine is checked in a loop from its first operand up, as lowering
        // walks it: every operand of the chain is one level below it, however long it is.
        std::vector<Expr*> spine;
        for (Expr* link = &e; isChainLink(*link); link = link->args[0].get()) spine.push_back(link);
        checkExpr(*spine.back()->args[0], scope);
        int height = lastHeight_;
        for (auto it = spine.rbegin(); it != spine.rend(); ++it) {
            checkExpr(*(*it)->args[1], scope);
            height = std::max(height, lastHeight_);
            finishExpr(**it, scope, height);
        }
        return e.type;
    }
    int height = 0;
    // ramp and progress take a timing's name first: it names a declaration, not a value.
    const bool timed =
        e.kind == ExprKind::Call && (e.name == "ramp" || e.name == "progress") && !e.args.empty();
    for (size_t i = 0; i < e.args.size(); ++i) {
        if (timed && i == 0) {
            if (!timingArgument(*e.args[0], e.name)) e.args[0]->type = Type::Error;
            continue;
        }
        checkExpr(*e.args[i], scope);
        height = std::max(height, lastHeight_);
    }
    return finishExpr(e, scope, height);
}

// The type of `e` once its operands are checked; lastHeight_ = 1 + max(height, the height of
// what a name names).
Type Checker::finishExpr(Expr& e, const Scope& scope, int height) {
    inherit(e);
    refHeight_ = 0;
    e.type = typeOf(e, scope); // a name sets refHeight_ to the height of what it names
    // (A name whose value is already in error was reported where that error is.)
    if (refHeight_ >= kMaxExpandedDepth && e.type != Type::Error) {
        tooDeep(e);
        // Reported once, here: whatever uses this expression counts it as a leaf.
        refHeight_ = 0;
        e.type = Type::Error;
    }
    lastHeight_ = 1 + std::max(height, refHeight_);
    return e.type;
}

bool Checker::anyError(const Expr& e) const {
    for (const ExprPtr& a : e.args)
        if (a->type == Type::Error) return true;
    return false;
}

Type Checker::typeOf(Expr& e, const Scope& scope) {
    switch (e.kind) {
    case ExprKind::Error:
        return Type::Error;
    case ExprKind::Number:
        return e.unit == Unit::None ? Type::Num : Type::Angle;
    case ExprKind::Color:
        return Type::Color;
    case ExprKind::Name:
        return resolveName(e, scope);
    case ExprKind::Vector: {
        if (e.args.size() != 2) {
            diags_.error(e.range, Msg::VectorSize, e.args.size());
            return Type::Error;
        }
        for (const ExprPtr& a : e.args)
            if (a->type != Type::Num && a->type != Type::Error) {
                diags_.error(a->range, Msg::TypeMismatch, "a vector component", typeName(Type::Num),
                             typeName(a->type));
                return Type::Error;
            }
        return anyError(e) ? Type::Error : Type::Vec2;
    }
    case ExprKind::Unary: {
        Type t = e.args[0]->type;
        if (t == Type::Error) return t;
        if (t == Type::Color || t == Type::Bool) {
            diags_.error(e.opRange, Msg::UnaryType, e.un == UnOp::Neg ? "-" : "+", typeName(t));
            return Type::Error;
        }
        return t;
    }
    case ExprKind::Binary:
        return binaryType(e);
    case ExprKind::Call:
        return callType(e);
    }
    return Type::Error;
}

Type Checker::binaryType(Expr& e) {
    Type a = e.args[0]->type, b = e.args[1]->type;
    if (a == Type::Error || b == Type::Error) return Type::Error;
    auto fail = [&] {
        // Adding a bare number to an angle is the usual slip: the number wants a unit.
        bool angleAndNumber =
            (a == Type::Angle && b == Type::Num) || (a == Type::Num && b == Type::Angle);
        const char* hint = (e.bin == BinOp::Add || e.bin == BinOp::Sub) && angleAndNumber
                               ? "; give the number a unit, as in 30deg"
                               : "";
        diags_.error(e.opRange, Msg::BinaryTypes, binOpSpelling(e.bin), typeName(a), typeName(b),
                     hint);
        return Type::Error;
    };
    switch (e.bin) {
    case BinOp::Add:
    case BinOp::Sub:
        if (a == b && a != Type::Color && a != Type::Bool) return a;
        // 0 is zero in every unit: `rotation + 0` is harmless.
        if (a == Type::Angle && b == Type::Num && isLiteralZero(*e.args[1])) return a;
        if (b == Type::Angle && a == Type::Num && isLiteralZero(*e.args[0])) return b;
        return fail();
    case BinOp::Mul:
        if (a == Type::Num && b == Type::Num) return Type::Num;
        if (a == Type::Num && (b == Type::Angle || b == Type::Vec2)) return b;
        if (b == Type::Num && (a == Type::Angle || a == Type::Vec2)) return a;
        return fail();
    case BinOp::Div:
        if (b == Type::Num && (a == Type::Num || a == Type::Angle || a == Type::Vec2)) return a;
        if (a == Type::Angle && b == Type::Angle) return Type::Num;
        return fail();
    case BinOp::Pow:
        if (a == Type::Num && b == Type::Num) return Type::Num;
        return fail();
    }
    return Type::Error;
}

Type Checker::callType(Expr& e) {
    auto fn = lookupFn(e.name);
    if (!fn) {
        if (lookupName(e.name))
            diags_.error(e.opRange, Msg::NotAFunction, e.name, "a built-in value", "");
        else if (globals_.count(e.name))
            // `sine(x)` is more likely a slip for sin than a call of the easing.
            diags_.error(e.opRange, Msg::NotAFunction, e.name,
                         std::string(globals_[e.name]->kind == DeclKind::Easing ? "an " : "a ") +
                             declKindName(globals_[e.name]->kind),
                         didYouMean(e.name, builtinFunctions()));
        else
            diags_.error(e.opRange, Msg::UnknownFunction, e.name,
                         didYouMean(e.name, builtinFunctions()));
        return Type::Error;
    }
    e.refIndex = static_cast<int>(*fn);
    const FnInfo& info = fnInfo(*fn);
    int given = static_cast<int>(e.args.size());
    if (given != info.numArgs) {
        diags_.error(e.range, Msg::Arity, e.name, plural(info.numArgs, "argument"),
                     fmt::format("{} {}", given, given == 1 ? "was" : "were"));
        return Type::Error;
    }
    if (anyError(e)) return Type::Error;
    auto argFail = [&](int i, const char* want) {
        diags_.error(e.args[i]->range, Msg::ArgumentType, i + 1, e.name, want,
                     typeName(e.args[i]->type));
        return Type::Error;
    };
    switch (info.sig) {
    case Signature::Trig:
        if (e.args[0]->type != Type::Num && e.args[0]->type != Type::Angle)
            return argFail(0, "a number or an angle");
        return Type::Num;
    case Signature::NumToNum:
        for (int i = 0; i < given; ++i)
            if (e.args[i]->type != Type::Num) return argFail(i, "a number");
        return Type::Num;
    case Signature::SameUnit:
    case Signature::SameToNum: {
        Type t = e.args[0]->type;
        if (t != Type::Num && t != Type::Angle) return argFail(0, "a number or an angle");
        for (int i = 1; i < given; ++i) {
            Type u = e.args[i]->type;
            if (u == t) continue;
            if (u == Type::Num && isLiteralZero(*e.args[i])) continue;
            if (u != Type::Num && u != Type::Angle) return argFail(i, "a number or an angle");
            diags_.error(e.args[i]->range, Msg::SameTypeArgs, e.name, typeName(t), typeName(u));
            return Type::Error;
        }
        return info.sig == Signature::SameUnit ? t : Type::Num;
    }
    case Signature::Mix:
        if (e.args[0]->type != e.args[1]->type) {
            diags_.error(e.args[1]->range, Msg::SameTypeArgs, e.name, typeName(e.args[0]->type),
                         typeName(e.args[1]->type));
            return Type::Error;
        }
        if (e.args[2]->type != Type::Num) return argFail(2, "a number");
        return e.args[0]->type;
    case Signature::Timed:
        if (given == 1) return Type::Num; // progress(timing)
        if (e.args[1]->type != e.args[2]->type) {
            diags_.error(e.args[2]->range, Msg::SameTypeArgs, e.name, typeName(e.args[1]->type),
                         typeName(e.args[2]->type));
            return Type::Error;
        }
        return e.args[1]->type;
    case Signature::Select:
        if (e.args[0]->type != Type::Bool) return argFail(0, "a boolean (true, false or a param)");
        if (e.args[1]->type != e.args[2]->type) {
            diags_.error(e.args[2]->range, Msg::SameTypeArgs, e.name, typeName(e.args[1]->type),
                         typeName(e.args[2]->type));
            return Type::Error;
        }
        return e.args[1]->type;
    case Signature::Length:
        if (e.args[0]->type != Type::Vec2) return argFail(0, "a 2-vector");
        return Type::Num;
    case Signature::Color:
        for (int i = 0; i < given; ++i)
            if (e.args[i]->type != Type::Num) return argFail(i, "a number");
        return Type::Color;
    }
    return Type::Error;
}

Type Checker::resolveName(Expr& e, const Scope& scope) {
    const std::string& n = e.name;
    if (scope.easing && n == kEasingProgressName) { // the progress an easing shapes
        e.ref = RefKind::EasingVar;
        return Type::Num;
    }
    if (scope.family) {
        for (size_t i = scope.visibleLets; i-- > 0;) {
            const Let& l = scope.family->lets[i];
            if (l.name != n) continue;
            e.ref = RefKind::Let;
            e.refDecl = scope.family;
            e.refIndex = static_cast<int>(i);
            e.dependsOnPosition = l.value->dependsOnPosition;
            e.dependsOnTime = l.value->dependsOnTime;
            refHeight_ = letHeight_[&l];
            return l.value->type;
        }
        for (size_t i = 0; i < scope.family->params.size(); ++i) {
            const FamilyParam& p = scope.family->params[i];
            if (p.name != n) continue;
            e.ref = RefKind::FamilyParam;
            e.refDecl = scope.family;
            e.refIndex = static_cast<int>(i);
            // A parameter is whatever the layer sets it to, which may vary.
            e.dependsOnPosition = true;
            e.dependsOnTime = true;
            return p.type;
        }
    }
    if (n == kSpacingName) {
        if (!scope.allowSpacing) {
            diags_.error(e.opRange, Msg::NameNotHere, n, "in a family's phase");
            return Type::Error;
        }
        e.ref = RefKind::Spacing;
        e.dependsOnPosition = e.dependsOnTime = true;
        return Type::Num;
    }
    if (n == "true" || n == "false") {
        e.ref = RefKind::Boolean;
        e.refIndex = n == "true" ? 1 : 0;
        return Type::Bool;
    }
    if (auto b = lookupName(n)) {
        e.ref = RefKind::Builtin;
        e.refIndex = static_cast<int>(*b);
        e.dependsOnPosition = nameInfo(*b).position;
        e.dependsOnTime = nameInfo(*b).time;
        return Type::Num;
    }
    auto g = globals_.find(n);
    if (g != globals_.end() &&
        (g->second->kind == DeclKind::Field || g->second->kind == DeclKind::Param)) {
        Decl* f = const_cast<Decl*>(g->second);
        if (fieldState_[f] == State::InProgress) {
            std::string path;
            bool on = false;
            for (const Decl* d : fieldStack_) {
                if (d == f) on = true;
                if (on) path += (path.empty() ? "" : " -> ") + d->name;
            }
            path += " -> " + f->name;
            diags_.error(e.opRange, Msg::FieldCycle, f->name, path);
            return Type::Error;
        }
        if (fieldState_[f] == State::Unvisited && exprDepth_ >= kMaxExpandedDepth) {
            // Checking `f` now would recurse once more per field in a chain of fields
            // each defined by the next; past the limit the chain is too deep anyway.
            tooDeep(e);
            return Type::Error;
        }
        checkField(*f);
        refHeight_ = fieldHeight_[f];
        e.ref = f->kind == DeclKind::Param ? RefKind::Param : RefKind::Field;
        e.refDecl = f;
        e.dependsOnPosition = f->value->dependsOnPosition;
        e.dependsOnTime = f->value->dependsOnTime;
        // A `-D` value of 0 for an angle param is still an angle.
        if (f->sceneDefault) return f->sceneDefault->type;
        return f->value->type;
    }
    if (g != globals_.end() && g->second->kind == DeclKind::Family) {
        diags_.error(e.opRange, Msg::FamilyAsValue, n, n);
        return Type::Error;
    }
    if (g != globals_.end() && g->second->kind == DeclKind::Timing) {
        diags_.error(e.opRange, Msg::TimingAsValue, n, n, n);
        return Type::Error;
    }
    if (g != globals_.end() && g->second->kind == DeclKind::Easing) {
        diags_.error(e.opRange, Msg::EasingAsValue, n, n);
        return Type::Error;
    }
    if (lookupFn(n)) {
        diags_.error(e.opRange, Msg::FunctionAsValue, n, n);
        return Type::Error;
    }
    if (scope.family) {
        // A let below this point (or this very let) is not defined yet.
        for (size_t i = scope.visibleLets; i < scope.family->lets.size(); ++i)
            if (scope.family->lets[i].name == n) {
                diags_.error(e.opRange, Msg::NameNotHere, n,
                             fmt::format("after 'let {} = ...' defines it", n));
                return Type::Error;
            }
    }
    std::vector<std::string> candidates = builtinNames();
    for (auto& [name, d] : globals_)
        if (d->kind == DeclKind::Field || d->kind == DeclKind::Param) candidates.push_back(name);
    if (scope.family) {
        for (size_t i = 0; i < scope.visibleLets; ++i)
            candidates.push_back(scope.family->lets[i].name);
        for (const FamilyParam& p : scope.family->params) candidates.push_back(p.name);
    }
    if (scope.allowSpacing) candidates.push_back(kSpacingName);
    diags_.error(e.opRange, Msg::UnknownName, n, didYouMean(n, candidates));
    return Type::Error;
}

} // namespace moire::sema::detail
