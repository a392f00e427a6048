#include "compiler/format/SameTree.h"

#include <utility>
#include <vector>

namespace moire::format {

namespace {
bool sameNumber(double a, double b) {
    return a == b || (a != a && b != b); // NaN is never written, but is the same as itself
}

bool sameNode(const ast::Expr& a, const ast::Expr& b) {
    if (a.kind != b.kind || a.args.size() != b.args.size() || a.literalSlot != b.literalSlot)
        return false;
    switch (a.kind) {
    case ast::ExprKind::Number:
        return sameNumber(a.number, b.number) && a.unit == b.unit;
    case ast::ExprKind::Color:
        for (int i = 0; i < 4; ++i)
            if (!sameNumber(a.rgba[i], b.rgba[i])) return false;
        return true;
    case ast::ExprKind::Name:
    case ast::ExprKind::Call:
        return a.name == b.name;
    case ast::ExprKind::Unary:
        return a.un == b.un;
    case ast::ExprKind::Binary:
        return a.bin == b.bin;
    case ast::ExprKind::Error:
    case ast::ExprKind::Vector:
        return true;
    }
    return false;
}

bool sameOptional(const ast::ExprPtr& a, const ast::ExprPtr& b) {
    if (!a || !b) return !a && !b;
    return sameExpr(*a, *b);
}
} // namespace

bool sameExpr(const ast::Expr& a, const ast::Expr& b) {
    std::vector<std::pair<const ast::Expr*, const ast::Expr*>> todo{{&a, &b}};
    while (!todo.empty()) {
        auto [x, y] = todo.back();
        todo.pop_back();
        if (!x || !y) {
            if (x || y) return false;
            continue;
        }
        if (!sameNode(*x, *y)) return false;
        for (size_t i = 0; i < x->args.size(); ++i)
            todo.push_back({x->args[i].get(), y->args[i].get()});
    }
    return true;
}

bool sameModule(const ast::Module& a, const ast::Module& b) {
    if (a.decls.size() != b.decls.size() || a.literals.size() != b.literals.size()) return false;
    for (size_t i = 0; i < a.literals.size(); ++i)
        if (!sameNumber(a.literals[i], b.literals[i])) return false;
    for (size_t i = 0; i < a.decls.size(); ++i) {
        const ast::Decl& x = *a.decls[i];
        const ast::Decl& y = *b.decls[i];
        if (x.kind != y.kind || x.name != y.name || x.builtin != y.builtin ||
            x.params.size() != y.params.size() || x.lets.size() != y.lets.size() ||
            x.props.size() != y.props.size() || !sameOptional(x.value, y.value))
            return false;
        for (size_t j = 0; j < x.params.size(); ++j)
            if (x.params[j].name != y.params[j].name ||
                !sameOptional(x.params[j].defaultValue, y.params[j].defaultValue))
                return false;
        for (size_t j = 0; j < x.lets.size(); ++j)
            if (x.lets[j].name != y.lets[j].name || !sameOptional(x.lets[j].value, y.lets[j].value))
                return false;
        for (size_t j = 0; j < x.props.size(); ++j)
            if (x.props[j].name != y.props[j].name ||
                !sameOptional(x.props[j].value, y.props[j].value))
                return false;
    }
    return true;
}

} // namespace moire::format
