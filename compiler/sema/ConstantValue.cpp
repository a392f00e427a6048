#include "compiler/sema/ConstantValue.h"

#include "compiler/sema/Builtins.h"

#include <cmath>
#include <numbers>

namespace moire::sema {

using namespace ast;

namespace {
std::optional<double> value(const Expr& e, int depth) {
    // Nesting was bounded by the parser; the guard only keeps a malformed tree finite.
    if (depth > 512) return std::nullopt;
    switch (e.kind) {
    case ExprKind::Number:
        return e.number;
    case ExprKind::Name:
        if (e.ref != RefKind::Builtin) return std::nullopt;
        switch (static_cast<Name>(e.refIndex)) {
        case Name::Pi:
            return std::numbers::pi;
        case Name::Tau:
            return 2.0 * std::numbers::pi;
        case Name::E:
            return std::numbers::e;
        default:
            return std::nullopt;
        }
    case ExprKind::Unary: {
        std::optional<double> v = value(*e.args[0], depth + 1);
        if (!v) return v;
        return e.un == UnOp::Neg ? -*v : *v;
    }
    case ExprKind::Binary: {
        std::optional<double> a = value(*e.args[0], depth + 1), b = value(*e.args[1], depth + 1);
        if (!a || !b) return std::nullopt;
        switch (e.bin) {
        case BinOp::Add:
            return *a + *b;
        case BinOp::Sub:
            return *a - *b;
        case BinOp::Mul:
            return *a * *b;
        case BinOp::Div:
            return *a / *b;
        case BinOp::Pow:
            return std::pow(*a, *b);
        }
        return std::nullopt;
    }
    default:
        return std::nullopt;
    }
}
} // namespace

std::optional<double> constantValue(const Expr& e) {
    std::optional<double> v = value(e, 0);
    if (v && !std::isfinite(*v)) return std::nullopt;
    return v;
}

} // namespace moire::sema
