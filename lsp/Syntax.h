// What the features ask of a document's text and tree: its tokens (the compiler's lexer), the
// word under the cursor, the declaration a place belongs to, and every expression of a tree,
// walked without recursion (a chain `1 + 1 + ...` is as deep as it is long).
#pragma once

#include "compiler/lex/Token.h"
#include "compiler/parse/Ast.h"

#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

namespace moire::lsp {

// The tokens of `text`, as the parser reads them (comments and bad bytes skipped), without the
// final End.
std::vector<Token> lexTokens(std::string_view text);

bool isWordChar(char c);
// The identifier at or just before `offset` ([begin, end) in bytes; begin == end: none).
std::pair<uint32_t, uint32_t> wordAt(std::string_view text, uint32_t offset);

// The declaration of `module` whose text holds `offset`: from its keyword up to the next
// declaration's. Null before the first.
const ast::Decl* declAt(const ast::Module& module, uint32_t offset);
// Where a declaration's text ends: the start of the next one's, or the end of the text.
uint32_t declEnd(const ast::Module& module, const ast::Decl& decl, uint32_t textSize);

// Calls f(expr) for every expression under `root` (root included), in no particular order.
template <class F>
void forEachExpr(const ast::Expr* root, F&& f) {
    if (!root) return;
    std::vector<const ast::Expr*> stack{root};
    while (!stack.empty()) {
        const ast::Expr* e = stack.back();
        stack.pop_back();
        f(*e);
        for (const ast::ExprPtr& a : e->args)
            if (a) stack.push_back(a.get());
    }
}

// Calls f(expr) for every expression of a declaration: its value, parameters' defaults,
// lets and properties, and a param's range and step.
template <class F>
void forEachExprOf(const ast::Decl& d, F&& f) {
    forEachExpr(d.value.get(), f);
    forEachExpr(d.rangeLo.get(), f);
    forEachExpr(d.rangeHi.get(), f);
    forEachExpr(d.step.get(), f);
    for (const ast::FamilyParam& p : d.params) forEachExpr(p.defaultValue.get(), f);
    for (const ast::Let& l : d.lets) forEachExpr(l.value.get(), f);
    for (const ast::Property& p : d.props) forEachExpr(p.value.get(), f);
}

bool covers(SourceRange r, uint32_t offset); // r.begin <= offset <= r's end (end included)

// The words `in`, `step` and `unit` of a param's declaration (`param gap = 8 in 4 .. 20 step
// 0.5 unit px`): the tokens of its text that are those words and lie outside its expressions
// and its unit's label (so `step(e, v)` in its value is not one). None for another declaration.
std::vector<Token> paramClauseWords(std::string_view text, const std::vector<Token>& toks,
                                    const ast::Module& module, const ast::Decl& decl);
bool isParamClauseWord(std::string_view word); // in, step or unit

} // namespace moire::lsp
