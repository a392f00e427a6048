// Go to definition, find references, rename and the outline, all from the compiler's symbol
// table (sema/Symbols.h): the scene's fields, families, timings, easings, params, layers,
// family parameters and lets, and the library's declarations the scene names.
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Builtins.h"
#include "lsp/Features.h"
#include "lsp/Syntax.h"

#include <algorithm>

namespace moire::lsp {

namespace {

// The symbol named at `offset` (the cursor may sit just after the name).
const sema::Symbol* symbolAt(const DocView& doc, uint32_t offset) {
    if (!doc.analysis.frontEnd()) return nullptr;
    auto [wb, we] = wordAt(doc.text(), offset);
    if (wb == we) return nullptr;
    return doc.analysis.result.symbols.at(SourceLoc{doc.analysis.userFile(), wb});
}

bool isUserDeclared(const DocView& doc, const sema::Symbol& s) {
    return s.declaration.begin.file == doc.analysis.userFile();
}

Json range(const DocView& doc, SourceRange r) {
    return rangeJson(doc.index, r.begin.offset, r.begin.offset + r.length);
}

bool validName(const std::string& name) {
    if (name.empty() || name.size() > 256 || (name[0] >= '0' && name[0] <= '9')) return false;
    return std::all_of(name.begin(), name.end(), isWordChar);
}

bool reserved(const std::string& name) {
    const auto& fns = sema::builtinFunctions();
    const auto& names = sema::builtinNames();
    return isKeyword(name) || name == "spacing" || name == "true" || name == "false" ||
           std::find(fns.begin(), fns.end(), name) != fns.end() ||
           std::find(names.begin(), names.end(), name) != names.end();
}

// Whether two symbols' names would clash: the top-level declarations but layers share one
// space of names (a param cannot take a field's name), layers have their own, and a family's
// parameters and lets are its own.
bool sameNames(const sema::Symbol& a, const sema::Symbol& b) {
    using K = sema::SymbolKind;
    auto global = [](K k) {
        return k == K::Field || k == K::Family || k == K::Timing || k == K::Easing ||
               k == K::SceneParam;
    };
    if (global(a.kind)) return global(b.kind);
    return a.kind == b.kind && (a.kind == K::Layer || a.decl == b.decl);
}

} // namespace

Json definition(const DocView& doc, uint32_t offset) {
    const sema::Symbol* s = symbolAt(doc, offset);
    if (!s) return nullptr;
    return locationJson(doc, s->declaration);
}

Json references(const DocView& doc, uint32_t offset, bool includeDeclaration) {
    const sema::Symbol* s = symbolAt(doc, offset);
    if (!s) return nullptr;
    Json out = Json::array();
    if (includeDeclaration) out.push_back(locationJson(doc, s->declaration));
    for (SourceRange r : s->references) out.push_back(locationJson(doc, r));
    return out;
}

Json prepareRename(const DocView& doc, uint32_t offset) {
    const sema::Symbol* s = symbolAt(doc, offset);
    if (!s) {
        auto [wb, we] = wordAt(doc.text(), offset);
        std::string word(doc.text().substr(wb, we - wb));
        if (!word.empty() && reserved(word))
            throw RpcError(ErrorCode::RequestFailed,
                           "'" + word + "' is built in: it cannot be renamed");
        return nullptr;
    }
    if (!isUserDeclared(doc, *s))
        throw RpcError(ErrorCode::RequestFailed,
                       "'" + s->name + "' is the standard library's: it cannot be renamed here");
    auto [wb, we] = wordAt(doc.text(), offset);
    return Json{{"range", rangeJson(doc.index, wb, we)}, {"placeholder", s->name}};
}

Json rename(const DocView& doc, uint32_t offset, const std::string& newName) {
    prepareRename(doc, offset); // refuses built-ins and the library's names
    const sema::Symbol* s = symbolAt(doc, offset);
    if (!s) throw RpcError(ErrorCode::RequestFailed, "no name of the scene here to rename");
    if (!validName(newName))
        throw RpcError(ErrorCode::InvalidParams, "'" + newName + "' is not a name");
    if (reserved(newName))
        throw RpcError(ErrorCode::RequestFailed, "'" + newName + "' is a reserved name");
    for (const sema::Symbol& other : doc.analysis.result.symbols.symbols)
        if (other.name == newName && sameNames(other, *s))
            throw RpcError(ErrorCode::RequestFailed, "'" + newName + "' is already declared");
    Json edits = Json::array();
    edits.push_back({{"range", range(doc, s->declaration)}, {"newText", newName}});
    for (SourceRange r : s->references)
        edits.push_back({{"range", range(doc, r)}, {"newText", newName}});
    return Json{{"changes", {{doc.uri, std::move(edits)}}}};
}

Json documentSymbols(const DocView& doc) {
    Json out = Json::array();
    const SceneProgram* fe = doc.analysis.frontEnd();
    if (!fe) return out;
    std::string_view text = doc.text();
    std::vector<Token> toks = lexTokens(text);
    const ast::Module& m = fe->userModule();
    // SymbolKind
    auto kindOf = [](ast::DeclKind k) {
        switch (k) {
        case ast::DeclKind::Scene:
            return 2;
        case ast::DeclKind::Camera:
            return 19;
        case ast::DeclKind::Layer:
            return 3;
        case ast::DeclKind::Field:
            return 13;
        case ast::DeclKind::Family:
            return 5;
        case ast::DeclKind::Timing:
            return 24;
        case ast::DeclKind::Easing:
            return 12;
        case ast::DeclKind::Param:
            return 14; // Constant: a value a slider turns, not a formula
        }
        return 13;
    };
    for (const ast::DeclPtr& d : m.decls) {
        uint32_t begin = d->range.begin.offset;
        uint32_t limit = declEnd(m, *d, static_cast<uint32_t>(text.size()));
        // The declaration ends with its last token, before the comments of the next.
        uint32_t end = begin + d->range.length;
        for (const Token& t : toks)
            if (t.offset >= begin && t.offset < limit) end = std::max(end, t.offset + t.length);
        SourceRange sel = d->nameRange.begin.valid() && !d->name.empty() ? d->nameRange : d->range;
        Json sym{{"name", d->name.empty() ? std::string(ast::declKindName(d->kind)) : d->name},
                 {"detail", ast::declKindName(d->kind)},
                 {"kind", kindOf(d->kind)},
                 {"range", rangeJson(doc.index, begin, end)},
                 {"selectionRange", range(doc, sel)}};
        Json children = Json::array();
        auto child = [&](const std::string& name, SourceRange nameRange, const ast::Expr* value,
                         int kind) {
            uint32_t cb = nameRange.begin.offset;
            uint32_t ce = value ? std::max(cb + nameRange.length,
                                           value->range.begin.offset + value->range.length)
                                : cb + nameRange.length;
            children.push_back({{"name", name},
                                {"kind", kind},
                                {"range", rangeJson(doc.index, cb, std::min(ce, end))},
                                {"selectionRange", range(doc, nameRange)}});
        };
        for (const ast::FamilyParam& p : d->params)
            child(p.name, p.nameRange, p.defaultValue.get(), 26);
        for (const ast::Let& l : d->lets) child(l.name, l.nameRange, l.value.get(), 13);
        for (const ast::Property& p : d->props)
            if (p.nameRange.begin.valid() && p.nameRange.begin.file == m.file)
                child(p.name, p.nameRange, p.value.get(), 7);
        if (!children.empty()) sym["children"] = std::move(children);
        out.push_back(std::move(sym));
    }
    return out;
}

} // namespace moire::lsp
