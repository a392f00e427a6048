#include "lsp/Syntax.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lex/Lexer.h"

#include <algorithm>

namespace moire::lsp {

std::vector<Token> lexTokens(std::string_view text) {
    SourceManager sm;
    uint32_t id = sm.add("<tokens>", std::string(text));
    DiagEngine diags(sm); // errors are the compiler's to report; here they are skipped
    Lexer lexer(id, sm.file(id).text(), diags);
    std::vector<Token> out;
    for (Token t = lexer.next(); t.kind != Tok::End; t = lexer.next()) out.push_back(t);
    return out;
}

bool isWordChar(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

std::pair<uint32_t, uint32_t> wordAt(std::string_view text, uint32_t offset) {
    if (offset > text.size()) offset = static_cast<uint32_t>(text.size());
    uint32_t begin = offset, end = offset;
    while (begin > 0 && isWordChar(text[begin - 1])) --begin;
    while (end < text.size() && isWordChar(text[end])) ++end;
    // A number is no word.
    if (begin < end && text[begin] >= '0' && text[begin] <= '9') return {offset, offset};
    return {begin, end};
}

const ast::Decl* declAt(const ast::Module& module, uint32_t offset) {
    const ast::Decl* found = nullptr;
    for (const ast::DeclPtr& d : module.decls) {
        if (d->range.begin.offset > offset) break;
        found = d.get();
    }
    return found;
}

uint32_t declEnd(const ast::Module& module, const ast::Decl& decl, uint32_t textSize) {
    for (size_t i = 0; i < module.decls.size(); ++i)
        if (module.decls[i].get() == &decl)
            return i + 1 < module.decls.size() ? module.decls[i + 1]->range.begin.offset : textSize;
    return textSize;
}

bool isParamClauseWord(std::string_view word) {
    return word == "in" || word == "step" || word == "unit";
}

std::vector<Token> paramClauseWords(std::string_view text, const std::vector<Token>& toks,
                                    const ast::Module& module, const ast::Decl& decl) {
    std::vector<Token> out;
    if (decl.kind != ast::DeclKind::Param) return out;
    uint32_t begin = decl.range.begin.offset;
    uint32_t end = declEnd(module, decl, static_cast<uint32_t>(text.size()));
    auto inside = [](SourceRange r, uint32_t offset) {
        return r.begin.valid() && offset >= r.begin.offset && offset < r.begin.offset + r.length;
    };
    // The tokens are in order: start at the declaration's first (a scene of many params
    // costs no pass over the whole text per param).
    auto first = std::lower_bound(toks.begin(), toks.end(), begin,
                                  [](const Token& t, uint32_t at) { return t.offset < at; });
    for (auto it = first; it != toks.end() && it->offset < end; ++it) {
        const Token& t = *it;
        if (t.kind != Tok::Ident) continue;
        if (!isParamClauseWord(text.substr(t.offset, t.length))) continue;
        if (inside(decl.nameRange, t.offset) || inside(decl.unitRange, t.offset)) continue;
        bool inExpr = false;
        for (const ast::ExprPtr* e : {&decl.value, &decl.rangeLo, &decl.rangeHi, &decl.step})
            if (*e && inside((*e)->range, t.offset)) inExpr = true;
        if (!inExpr) out.push_back(t);
    }
    return out;
}

bool covers(SourceRange r, uint32_t offset) {
    return r.begin.valid() && offset >= r.begin.offset && offset <= r.begin.offset + r.length;
}

} // namespace moire::lsp
