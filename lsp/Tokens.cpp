// Semantic tokens (the whole document) and folding ranges. Names are classified by what the
// checks resolved them to, so a field, a family parameter and a built-in read differently even
// where a grammar cannot tell them apart; the lexer's tokens give numbers and colours, and the
// gaps between tokens the comments.
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Builtins.h"
#include "lsp/Features.h"
#include "lsp/Syntax.h"

#include <map>

namespace moire::lsp {

namespace {

enum TokenType {
    kKeyword,
    kType,
    kFunction,
    kVariable,
    kParameter,
    kProperty,
    kNumber,
    kString,
    kComment,
    kEvent,
    kNamespace,
    kEnumMember
};
const char* const kTypeNames[] = {"keyword",   "type",     "function",  "variable",
                                  "parameter", "property", "number",    "string",
                                  "comment",   "event",    "namespace", "enumMember"};
enum Modifier { kDeclaration = 1, kReadonly = 2, kDefaultLibrary = 4 };
const char* const kModifierNames[] = {"declaration", "readonly", "defaultLibrary"};

struct Classified {
    uint32_t length;
    int type;
    int modifiers;
};

int declType(ast::DeclKind k) {
    switch (k) {
    case ast::DeclKind::Family:
        return kType;
    case ast::DeclKind::Field:
        return kVariable;
    case ast::DeclKind::Timing:
        return kEvent;
    case ast::DeclKind::Easing:
        return kFunction;
    case ast::DeclKind::Param:
        return kVariable;
    default:
        return kNamespace;
    }
}

void classifyExpr(const ast::Expr& e, std::map<uint32_t, Classified>& out) {
    auto put = [&](SourceRange r, int type, int mods) {
        out.emplace(r.begin.offset, Classified{r.length, type, mods});
    };
    if (e.kind == ast::ExprKind::Call) {
        bool builtin = sema::lookupFn(e.name).has_value() || e.name == "morph";
        put(e.opRange, kFunction, builtin ? kDefaultLibrary : 0);
        return;
    }
    if (e.kind != ast::ExprKind::Name) return;
    switch (e.ref) {
    case ast::RefKind::Builtin:
        return put(e.range, kVariable, kDefaultLibrary | kReadonly);
    case ast::RefKind::Field:
        return put(e.range, kVariable, kReadonly);
    case ast::RefKind::Param:
        return put(e.range, kVariable, 0);
    case ast::RefKind::Boolean:
        return put(e.range, kEnumMember, 0);
    case ast::RefKind::FamilyParam:
    case ast::RefKind::EasingVar:
        return put(e.range, kParameter, 0);
    case ast::RefKind::Let:
        return put(e.range, kVariable, kReadonly);
    case ast::RefKind::Spacing:
        return put(e.range, kProperty, 0);
    case ast::RefKind::Timing:
        return put(e.range, kEvent, 0);
    case ast::RefKind::Family:
        return put(e.range, kType, 0);
    case ast::RefKind::Easing:
        return put(e.range, kFunction, 0);
    case ast::RefKind::Unresolved:
        // The words a property takes by name: a timing's mode, the scene's view, a switch.
        if (e.name == "once" || e.name == "loop" || e.name == "pingpong" || e.name == "true" ||
            e.name == "false" || e.name == "pattern" || e.name == "envelope" || e.name == "split" ||
            e.name == "ratio")
            put(e.range, kEnumMember, 0);
        else if (sema::lookupName(e.name))
            put(e.range, kVariable, kDefaultLibrary | kReadonly);
        return;
    }
}

// The comments in text[from, to) (a gap between two tokens), one entry per line they cover.
void comments(std::string_view text, uint32_t from, uint32_t to,
              std::map<uint32_t, Classified>& out) {
    uint32_t i = from;
    while (i + 1 < to) {
        if (text[i] == '/' && text[i + 1] == '/') {
            uint32_t e = i;
            while (e < to && text[e] != '\n') ++e;
            out.emplace(i, Classified{e - i, kComment, 0});
            i = e;
        } else if (text[i] == '/' && text[i + 1] == '*') {
            size_t close = text.find("*/", i + 2);
            uint32_t e = close == std::string_view::npos || close + 2 > to
                             ? to
                             : static_cast<uint32_t>(close + 2);
            for (uint32_t s = i; s < e;) {
                uint32_t nl = s;
                while (nl < e && text[nl] != '\n') ++nl;
                if (nl > s) out.emplace(s, Classified{nl - s, kComment, 0});
                s = nl + 1;
            }
            i = e;
        } else {
            ++i;
        }
    }
}

} // namespace

Json semanticTokensLegend() {
    return Json{{"tokenTypes", kTypeNames}, {"tokenModifiers", kModifierNames}};
}

Json semanticTokens(const DocView& doc) {
    std::string_view text = doc.text();
    std::map<uint32_t, Classified> byOffset;
    std::vector<Token> toks = lexTokens(text);
    if (const SceneProgram* fe = doc.analysis.frontEnd()) {
        for (const ast::DeclPtr& d : fe->userModule().decls) {
            byOffset.emplace(d->range.begin.offset, Classified{d->range.length, kKeyword, 0});
            if (!d->name.empty() && d->nameRange.begin.valid())
                byOffset.emplace(d->nameRange.begin.offset,
                                 Classified{d->nameRange.length, declType(d->kind), kDeclaration});
            for (const ast::FamilyParam& p : d->params)
                byOffset.emplace(p.nameRange.begin.offset,
                                 Classified{p.nameRange.length, kParameter, kDeclaration});
            for (const ast::Let& l : d->lets)
                byOffset.emplace(l.nameRange.begin.offset, Classified{l.nameRange.length, kVariable,
                                                                      kDeclaration | kReadonly});
            for (const ast::Property& p : d->props)
                byOffset.emplace(p.nameRange.begin.offset,
                                 Classified{p.nameRange.length, kProperty, 0});
            forEachExprOf(*d, [&](const ast::Expr& e) { classifyExpr(e, byOffset); });
            // A param's `in`, `step` and `unit` (not the function step), and the unit's label.
            for (const Token& t : paramClauseWords(text, toks, fe->userModule(), *d))
                byOffset.emplace(t.offset, Classified{t.length, kKeyword, 0});
            if (d->kind == ast::DeclKind::Param && d->unitRange.begin.valid() &&
                !d->unitLabel.empty())
                byOffset.emplace(d->unitRange.begin.offset,
                                 Classified{d->unitRange.length, kString, 0});
        }
    }
    uint32_t last = 0;
    for (const Token& t : toks) {
        comments(text, last, t.offset, byOffset);
        last = t.offset + t.length;
        if (t.kind == Tok::Number)
            byOffset.emplace(t.offset, Classified{t.length, kNumber, 0});
        else if (t.kind == Tok::Color)
            byOffset.emplace(t.offset, Classified{t.length, kString, 0});
        else if (t.kind == Tok::Ident) {
            std::string_view w = text.substr(t.offset, t.length);
            if (isKeyword(w))
                byOffset.emplace(t.offset, Classified{t.length, kKeyword, 0});
            else if (sema::lookupFn(w))
                byOffset.emplace(t.offset, Classified{t.length, kFunction, kDefaultLibrary});
        }
    }
    comments(text, last, static_cast<uint32_t>(text.size()), byOffset);
    // Relative encoding: each token's line and start from the previous one's.
    Json data = Json::array();
    Position prev;
    uint32_t prevEnd = 0;
    for (const auto& [offset, c] : byOffset) {
        if (offset < prevEnd || c.length == 0) continue; // overlapping: the first one wins
        Position p = doc.index.position(offset);
        Position e = doc.index.position(offset + c.length);
        if (e.line != p.line) continue; // a token never spans lines (comments are split)
        data.push_back(p.line - prev.line);
        data.push_back(p.line == prev.line ? p.character - prev.character : p.character);
        data.push_back(e.character - p.character);
        data.push_back(c.type);
        data.push_back(c.modifiers);
        prev = p;
        prevEnd = offset + c.length;
    }
    return Json{{"data", std::move(data)}};
}

Json foldingRanges(const DocView& doc) {
    std::string_view text = doc.text();
    Json out = Json::array();
    std::vector<Token> toks = lexTokens(text);
    // Each `{ ... }` over more than one line, and each run of comment lines.
    std::vector<uint32_t> open;
    uint32_t last = 0;
    std::map<uint32_t, Classified> notes;
    for (const Token& t : toks) {
        comments(text, last, t.offset, notes);
        last = t.offset + t.length;
        if (t.kind == Tok::LBrace) open.push_back(t.offset);
        if (t.kind == Tok::RBrace && !open.empty()) {
            uint32_t a = doc.index.position(open.back()).line;
            uint32_t b = doc.index.position(t.offset).line;
            open.pop_back();
            if (b > a) out.push_back({{"startLine", a}, {"endLine", b}});
        }
    }
    comments(text, last, static_cast<uint32_t>(text.size()), notes);
    int64_t runStart = -1, runEnd = -2;
    auto flush = [&] {
        if (runStart >= 0 && runEnd > runStart)
            out.push_back({{"startLine", runStart}, {"endLine", runEnd}, {"kind", "comment"}});
    };
    for (const auto& [offset, c] : notes) {
        int64_t line = doc.index.position(offset).line;
        if (line == runEnd + 1 || line == runEnd) {
            runEnd = line;
        } else {
            flush();
            runStart = runEnd = line;
        }
    }
    flush();
    return out;
}

} // namespace moire::lsp
