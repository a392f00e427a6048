#include "compiler/parse/Ast.h"

#include <fmt/format.h>
#include <utility>
#include <vector>

namespace moire::ast {

const char* typeName(Type t) {
    switch (t) {
    case Type::Error:
        return "an invalid value";
    case Type::Num:
        return "a number";
    case Type::Angle:
        return "an angle";
    case Type::Vec2:
        return "a 2-vector";
    case Type::Color:
        return "a colour";
    case Type::Bool:
        return "a boolean";
    }
    return "?";
}

const char* binOpSpelling(BinOp op) {
    switch (op) {
    case BinOp::Add:
        return "+";
    case BinOp::Sub:
        return "-";
    case BinOp::Mul:
        return "*";
    case BinOp::Div:
        return "/";
    case BinOp::Pow:
        return "^";
    }
    return "?";
}

const char* declKindName(DeclKind k) {
    switch (k) {
    case DeclKind::Scene:
        return "scene";
    case DeclKind::Camera:
        return "camera";
    case DeclKind::Field:
        return "field";
    case DeclKind::Family:
        return "family";
    case DeclKind::Layer:
        return "layer";
    case DeclKind::Timing:
        return "timing";
    case DeclKind::Easing:
        return "easing";
    case DeclKind::Param:
        return "param";
    }
    return "?";
}

namespace {
const char* shortType(Type t) {
    switch (t) {
    case Type::Error:
        return "?";
    case Type::Num:
        return "num";
    case Type::Angle:
        return "angle";
    case Type::Vec2:
        return "vec2";
    case Type::Color:
        return "color";
    case Type::Bool:
        return "bool";
    }
    return "?";
}

std::string annot(const Expr& e) {
    std::string s = fmt::format(" : {}", shortType(e.type));
    if (e.dependsOnPosition) s += " varying";
    if (e.dependsOnTime) s += " timed";
    if (e.literalSlot >= 0) s += fmt::format(" @lit{}", e.literalSlot);
    return s;
}
} // namespace

Expr::~Expr() {
    if (args.empty()) return;
    std::vector<ExprPtr> pending = std::move(args);
    while (!pending.empty()) {
        ExprPtr e = std::move(pending.back());
        pending.pop_back();
        if (!e) continue;
        for (ExprPtr& a : e->args) pending.push_back(std::move(a));
        e->args.clear();
    } // each node is destroyed here with no operands left to recurse into
}

std::string printExpr(const Expr& e) {
    if (isChainLink(e)) {
        // "((a + b) + c)": the spine in a loop, from the chain's first operand up.
        std::vector<const Expr*> spine;
        for (const Expr* link = &e; isChainLink(*link); link = link->args[0].get())
            spine.push_back(link);
        std::string s(spine.size(), '(');
        s += printExpr(*spine.back()->args[0]);
        for (auto it = spine.rbegin(); it != spine.rend(); ++it)
            s += fmt::format(" {} {})", binOpSpelling((*it)->bin), printExpr(*(*it)->args[1]));
        return s;
    }
    switch (e.kind) {
    case ExprKind::Error:
        return "<error>";
    case ExprKind::Number:
        return e.unit == Unit::Deg   ? fmt::format("{}rad(deg)", e.number)
               : e.unit == Unit::Rad ? fmt::format("{}rad", e.number)
                                     : fmt::format("{}", e.number);
    case ExprKind::Color:
        return fmt::format("rgba({:.4g}, {:.4g}, {:.4g}, {:.4g})", e.rgba[0], e.rgba[1], e.rgba[2],
                           e.rgba[3]);
    case ExprKind::Name:
        return e.name;
    case ExprKind::Unary:
        return fmt::format("({}{})", e.un == UnOp::Neg ? "-" : "+", printExpr(*e.args[0]));
    case ExprKind::Binary:
        return fmt::format("({} {} {})", printExpr(*e.args[0]), binOpSpelling(e.bin),
                           printExpr(*e.args[1]));
    case ExprKind::Call:
    case ExprKind::Vector: {
        std::string s = e.kind == ExprKind::Call ? e.name + "(" : "(";
        for (size_t i = 0; i < e.args.size(); ++i) s += (i ? ", " : "") + printExpr(*e.args[i]);
        return s + ")";
    }
    }
    return "?";
}

namespace {
void printTree(std::string& out, const Expr& root, int rootDepth) {
    // Depth first with an explicit stack, so that a long chain needs no stack of calls.
    std::vector<std::pair<const Expr*, int>> todo{{&root, rootDepth}};
    while (!todo.empty()) {
        auto [ep, depth] = todo.back();
        todo.pop_back();
        const Expr& e = *ep;
        std::string pad(depth * 2, ' ');
        switch (e.kind) {
        case ExprKind::Error:
        case ExprKind::Number:
        case ExprKind::Color:
        case ExprKind::Name:
            out += pad + printExpr(e) + annot(e) + "\n";
            continue;
        case ExprKind::Unary:
            out += pad + (e.un == UnOp::Neg ? "neg" : "plus");
            break;
        case ExprKind::Binary:
            out += pad + binOpSpelling(e.bin);
            break;
        case ExprKind::Call:
            out += pad + "call " + e.name;
            break;
        case ExprKind::Vector:
            out += pad + "vector";
            break;
        }
        out += annot(e) + "\n";
        for (auto a = e.args.rbegin(); a != e.args.rend(); ++a)
            todo.push_back({a->get(), depth + 1});
    }
}
} // namespace

std::string printModule(const Module& m) {
    std::string out;
    for (const DeclPtr& d : m.decls) {
        out += declKindName(d->kind);
        if (!d->name.empty()) out += " " + d->name;
        if (d->kind == DeclKind::Family && !d->params.empty()) {
            out += "(";
            for (size_t i = 0; i < d->params.size(); ++i) {
                const FamilyParam& p = d->params[i];
                out += (i ? ", " : "") + p.name;
                if (p.defaultValue) out += " = " + printExpr(*p.defaultValue);
            }
            out += ")";
        }
        out += "\n";
        if (d->value) printTree(out, *d->value, 1);
        if (d->rangeLo)
            out += "  in " + printExpr(*d->rangeLo) + " .. " + printExpr(*d->rangeHi) + "\n";
        if (d->step) out += "  step " + printExpr(*d->step) + "\n";
        if (!d->unitLabel.empty()) out += "  unit " + d->unitLabel + "\n";
        for (const Let& l : d->lets) {
            out += "  let " + l.name + "\n";
            printTree(out, *l.value, 2);
        }
        for (const Property& p : d->props) {
            out += "  " + p.name + " =\n";
            printTree(out, *p.value, 2);
        }
    }
    if (!m.literals.empty()) {
        out += "literals";
        for (size_t i = 0; i < m.literals.size(); ++i)
            out += fmt::format(" [{}]={}", i, m.literals[i]);
        out += "\n";
    }
    return out;
}

} // namespace moire::ast
