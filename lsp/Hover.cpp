// Hover: what the name under the cursor is (a signature or declaration line, and its meaning
// from the compiler's tables or the comment above its declaration), and for a value that is
// an expression the figure it has at t = 0.
#include "lsp/Describe.h"
#include "lsp/Features.h"
#include "lsp/Syntax.h"
#include "lsp/ValueAtZero.h"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace moire::lsp {

namespace {

std::string formatValue(const std::vector<double>& v, ast::Type type) {
    auto g = [](double d) { return fmt::format("{:.6g}", d); };
    switch (type) {
    case ast::Type::Angle:
        return fmt::format("{} rad ({}deg)", g(v[0]), g(v[0] * 180 / std::numbers::pi));
    case ast::Type::Vec2:
        return fmt::format("({}, {})", g(v[0]), g(v[1]));
    case ast::Type::Color:
        return fmt::format("rgba({}, {}, {}, {})", g(v[0]), g(v[1]), g(v[2]), g(v[3]));
    default:
        return g(v[0]);
    }
}

// The line of source that holds a range, trimmed.
std::string lineOf(const SceneProgram& fe, SourceRange r) {
    const SourceFile& file = fe.sources->file(r.begin.file);
    std::string_view line = file.lineText(r.begin.offset);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    return std::string(line);
}

// Whether an expression names anything (a param, t, a function...): a plain literal's value
// at t = 0 is itself, not worth a line of its own.
bool namesAnything(const ast::Expr* e) {
    bool any = false;
    forEachExpr(e, [&](const ast::Expr& x) {
        if (x.kind == ast::ExprKind::Name || x.kind == ast::ExprKind::Call) any = true;
    });
    return any;
}

struct Found {
    std::optional<Description> what;
    const ast::Expr* value = nullptr; // a value whose figure at t = 0 is worth showing
    uint32_t begin = 0, end = 0;
};

// The family a layer's `family = name` names, if it names one.
const ast::Decl* layerFamily(const ast::Decl& layer) {
    const ast::Property* fam = layer.prop("family");
    if (!fam || !fam->value) return nullptr;
    const ast::Expr* e = fam->value.get();
    if (e->kind == ast::ExprKind::Call && e->name == "morph" && e->args.size() > 1)
        e = e->args[1].get();
    return e->ref == ast::RefKind::Family ? e->refDecl : nullptr;
}

// A property of `decl` named at `begin`, described from the block's table or, in a layer, as a
// parameter of its family.
std::optional<Description> describePropertyAt(const SceneProgram& fe, const ast::Decl& decl,
                                              const ast::Property& p) {
    if (const auto* table = propertyTable(decl.kind))
        for (const sema::PropertySpec& s : *table)
            if (p.name == s.name) return describeProperty(s, ast::declKindName(decl.kind));
    if (decl.kind == ast::DeclKind::Layer)
        if (const ast::Decl* fam = layerFamily(decl))
            for (size_t i = 0; i < fam->params.size(); ++i)
                if (fam->params[i].name == p.name) return describeParam(fe, *fam, int(i));
    return std::nullopt;
}

Found find(const DocView& doc, uint32_t offset) {
    const Analysis& a = doc.analysis;
    const SceneProgram& fe = *a.frontEnd();
    Found f;
    auto [wb, we] = wordAt(doc.text(), offset);
    f.begin = wb;
    f.end = we;
    const ast::Decl* decl = declAt(fe.userModule(), offset);
    // A property's value that is an expression (not a bare number): its figure at t = 0.
    if (decl && decl->kind != ast::DeclKind::Family && decl->kind != ast::DeclKind::Easing) {
        for (const ast::Property& p : decl->props)
            if (p.value && covers(p.value->range, offset) && p.value->kind != ast::ExprKind::Number)
                f.value = p.value.get();
        if (decl->value && covers(decl->value->range, offset)) f.value = decl->value.get();
    }
    if (wb == we) {
        if (f.value) {
            f.begin = f.value->range.begin.offset;
            f.end = f.begin + f.value->range.length;
        }
        return f;
    }
    // A name of the scene's or the library's.
    if (const sema::Symbol* s = a.result.symbols.at(SourceLoc{a.userFile(), wb})) {
        if (s->kind == sema::SymbolKind::Param)
            f.what = describeParam(fe, *s->decl, s->index);
        else if (s->kind == sema::SymbolKind::SceneParam)
            f.what = describeSceneParam(fe, *s->decl);
        else if (s->kind == sema::SymbolKind::Let)
            f.what = Description{lineOf(fe, s->declaration),
                                 "a value named in the family " + s->decl->name};
        else
            f.what = describeDecl(fe, *s->decl);
        if (s->kind == sema::SymbolKind::Field && s->decl->value) f.value = s->decl->value.get();
        if (s->kind == sema::SymbolKind::SceneParam && namesAnything(s->decl->value.get()))
            f.value = s->decl->value.get();
        return f;
    }
    if (!decl) return f;
    // A param's `in`, `step` or `unit`.
    if (decl->kind == ast::DeclKind::Param)
        for (const Token& t :
             paramClauseWords(doc.text(), lexTokens(doc.text()), fe.userModule(), *decl))
            if (t.offset == wb) {
                f.what = describeParamClause(doc.text().substr(t.offset, t.length));
                return f;
            }
    for (const ast::Property& p : decl->props)
        if (p.nameRange.begin.offset == wb) {
            f.what = describePropertyAt(fe, *decl, p);
            if (p.value && p.value->kind != ast::ExprKind::Number) f.value = p.value.get();
            return f;
        }
    // A built-in name or function in an expression.
    forEachExprOf(*decl, [&](const ast::Expr& e) {
        if (e.opRange.begin.offset != wb || f.what) return;
        if (e.kind == ast::ExprKind::Call) {
            if (auto fn = sema::lookupFn(e.name)) f.what = describeFunction(sema::fnInfo(*fn));
        } else if (e.kind == ast::ExprKind::Name) {
            if (auto n = sema::lookupName(e.name))
                f.what = describeBuiltinName(sema::nameInfo(*n));
            else if (e.ref == ast::RefKind::Spacing)
                f.what = describeProperty(sema::propertySpec(sema::layerProperties(), "spacing"),
                                          "layer");
            else if (e.refDecl)
                f.what = describeDecl(fe, *e.refDecl);
        }
    });
    return f;
}

} // namespace

Json hover(const DocView& doc, uint32_t offset) {
    if (!doc.analysis.frontEnd()) return nullptr;
    Found f = find(doc, offset);
    std::string md;
    if (f.what) {
        md = "```moire\n" + f.what->signature + "\n```";
        if (!f.what->meaning.empty()) md += "\n" + f.what->meaning;
    }
    // Only a scene that compiled has a first frame to take the figure from.
    if (f.value && doc.analysis.result.program)
        if (auto v = valueAtZero(*doc.analysis.result.program, *f.value)) {
            if (!md.empty()) md += "\n\n";
            md += "Value at t = 0: `" + formatValue(*v, f.value->type) + "`";
        }
    if (md.empty()) return nullptr;
    return Json{{"contents", {{"kind", "markdown"}, {"value", md}}},
                {"range", rangeJson(doc.index, f.begin, f.end)}};
}

} // namespace moire::lsp
