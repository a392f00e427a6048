#include "compiler/parse/Parser.h"

#include "compiler/diag/Suggest.h"
#include "compiler/lex/Keywords.h"

#include <fmt/format.h>

namespace moire {

using namespace ast;

namespace {
struct DepthGuard {
    int& depth;
    explicit DepthGuard(int& d) : depth(d) { ++depth; }
    ~DepthGuard() { --depth; }
};

// Tokens that can begin a value but never a property or a declaration: met right after a
// value, they mean a missing operator, as in `2 (x + 1)`.
bool beginsValueOnly(Tok k) {
    return k == Tok::Number || k == Tok::Color || k == Tok::LParen;
}
} // namespace

Parser::Parser(const SourceManager& sm, uint32_t fileId, DiagEngine& diags)
    : file_(fileId), text_(sm.file(fileId).text()), isStdlib_(sm.file(fileId).isStdlib()),
      diags_(diags), lexer_(fileId, sm.file(fileId).text(), diags) {
    advance();
}

Parser::Parser(const SourceManager& sm, uint32_t fileId, DiagEngine& diags, size_t start,
               int firstSlot)
    : file_(fileId), text_(sm.file(fileId).text()), isStdlib_(false), diags_(diags),
      lexer_(fileId, sm.file(fileId).text(), diags), firstSlot_(firstSlot) {
    lexer_.seek(start);
    advance();
}

void Parser::advance() {
    prevTok_ = tok_;
    tok_ = lexer_.next();
}

bool Parser::accept(Tok k) {
    if (!at(k)) return false;
    advance();
    return true;
}

std::string Parser::describeCurrent() const {
    switch (tok_.kind) {
    case Tok::End:
        return "end of file";
    case Tok::Ident:
        return fmt::format("'{}'", lexer_.spelling(tok_));
    case Tok::Number:
    case Tok::Color:
        return fmt::format("{} '{}'", tokDescription(tok_.kind), lexer_.spelling(tok_));
    default:
        return tokDescription(tok_.kind);
    }
}

bool Parser::expect(Tok k, const char* what) {
    if (accept(k)) return true;
    // After a too-deep expression the rest of the input was skipped; every ')' and '}' still
    // open would be "missing", and saying so would only bury the real error.
    if (!abandoned_) diags_.error(range(), Msg::Expected, what, describeCurrent());
    return false;
}

SourceRange Parser::range() const {
    // "found end of file" points just after the last token, on the line where the missing
    // text belongs, rather than at an empty line below it.
    if (at(Tok::End) && prevTok_.length > 0) return {{file_, prevTok_.offset + prevTok_.length}, 1};
    return {{file_, tok_.offset}, tok_.length ? tok_.length : 1};
}

bool Parser::tooDeep() {
    if (depth_ <= kMaxDepth) return false;
    if (!abandoned_) diags_.error(range(), Msg::TooDeep, kMaxDepth);
    abandoned_ = true;
    // Skip the rest of the input: whatever follows is inside the runaway nesting.
    while (!at(Tok::End)) advance();
    return true;
}

bool Parser::valueEnds() {
    if (!beginsValueOnly(tok_.kind)) return true;
    diags_.error(range(), Msg::Expected, "an operator such as '*' between two values",
                 describeCurrent());
    return false;
}

bool Parser::nextIsAssign() const {
    // Scans the text after the current token, past white space and comments. (Peeking with
    // the lexer would report its errors twice.)
    size_t i = tok_.offset + tok_.length;
    while (i < text_.size()) {
        char c = text_[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') {
            ++i;
        } else if (text_.compare(i, 2, "//") == 0) {
            while (i < text_.size() && text_[i] != '\n') ++i;
        } else if (text_.compare(i, 2, "/*") == 0) {
            size_t close = text_.find("*/", i + 2);
            if (close == std::string_view::npos) return false;
            i = close + 2;
        } else {
            return c == '=';
        }
    }
    return false;
}

bool Parser::atDeclWord() const {
    for (const std::string& w : declarationKeywords())
        if (atWord(w)) return true;
    return false;
}

SourceRange Parser::spanFrom(SourceRange start) const {
    uint32_t end = prevTok_.offset + prevTok_.length;
    SourceRange r = start;
    if (end > start.begin.offset) r.length = end - start.begin.offset;
    return r;
}

void Parser::recoverTo(bool inBlock) {
    // Skip tokens until a plausible restart point: a closing brace (in a block), or a
    // declaration keyword at the top level.
    int braces = 0;
    while (!at(Tok::End)) {
        if (at(Tok::LBrace)) ++braces;
        if (at(Tok::RBrace)) {
            if (braces == 0) {
                if (!inBlock) advance();
                return;
            }
            --braces;
        }
        if (braces == 0 && !inBlock && atDeclWord()) return;
        if (braces == 0 && inBlock && at(Tok::Semi)) {
            // The next property may well be fine: resume there rather than at the '}'.
            advance();
            return;
        }
        advance();
    }
}

int Parser::assignLiteral(double v) {
    if (isStdlib_) return -1;
    literals_.push_back(v);
    return firstSlot_ + static_cast<int>(literals_.size() - 1);
}

Module Parser::parseModule() {
    Module m;
    m.file = file_;
    while (!at(Tok::End)) {
        if (diags_.errorCount() >= DiagEngine::kMaxErrors) break;
        DeclPtr d = parseDecl();
        if (d) m.decls.push_back(std::move(d));
    }
    m.literals = std::move(literals_);
    return m;
}

ExprPtr Parser::parseStandaloneExpr() {
    ExprPtr e = parseExpr();
    if (!at(Tok::End)) diags_.error(range(), Msg::Expected, "end of expression", describeCurrent());
    return e;
}

DeclPtr Parser::parseDecl() {
    SourceRange kw = range();
    std::string word = at(Tok::Ident) ? std::string(lexer_.spelling(tok_)) : std::string();
    DeclKind kind;
    // `builtin family name(params)`: a family the compiler implements in IR-building code
    // (the lattices). Only the standard library declares them.
    bool builtin = false;
    if (word == "builtin" && isStdlib_) {
        builtin = true;
        advance();
        word = at(Tok::Ident) ? std::string(lexer_.spelling(tok_)) : std::string();
        if (word != "family") {
            diags_.error(range(), Msg::Expected, "'family' after 'builtin'", describeCurrent());
            recoverTo(false);
            return nullptr;
        }
    }
    if (word == "scene")
        kind = DeclKind::Scene;
    else if (word == "camera")
        kind = DeclKind::Camera;
    else if (word == "layer")
        kind = DeclKind::Layer;
    else if (word == "field")
        kind = DeclKind::Field;
    else if (word == "family")
        kind = DeclKind::Family;
    else if (word == "timing")
        kind = DeclKind::Timing;
    else if (word == "easing")
        kind = DeclKind::Easing;
    else if (word == "param")
        kind = DeclKind::Param;
    else {
        Hint found = describeCurrent();
        if (at(Tok::Ident)) {
            found = didYouMean(word, declarationKeywords());
            found.text = describeCurrent() + found.text;
        }
        diags_.error(range(), Msg::Expected,
                     "a declaration (scene, camera, layer, field, family, timing, easing or param)",
                     found);
        advance();
        recoverTo(false);
        return nullptr;
    }
    advance();
    auto d = std::make_unique<Decl>(kind, kw);
    bool named = kind == DeclKind::Field || kind == DeclKind::Family || kind == DeclKind::Timing ||
                 kind == DeclKind::Easing || kind == DeclKind::Param;
    if (named || (kind == DeclKind::Layer && at(Tok::Ident))) {
        d->nameRange = range();
        if (!at(Tok::Ident)) {
            diags_.error(range(), Msg::Expected, fmt::format("a name for the {}", word),
                         describeCurrent());
            recoverTo(false);
            return nullptr;
        }
        d->name = std::string(lexer_.spelling(tok_));
        advance();
    }
    switch (kind) {
    case DeclKind::Field:
    case DeclKind::Easing:
        if (!expect(Tok::Assign, fmt::format("'=' after the {}'s name", word).c_str())) {
            recoverTo(false);
            return nullptr;
        }
        d->value = parseExpr();
        if (!valueEnds()) {
            recoverTo(false);
            break;
        }
        accept(Tok::Semi);
        break;
    case DeclKind::Param:
        parseParam(*d);
        break;
    case DeclKind::Family:
        d->builtin = builtin;
        parseFamily(*d);
        break;
    default:
        parseBlock(*d);
        break;
    }
    return d;
}

// `param name = default [in lo .. hi] [step s] [unit word]`: the words after the default are
// read only there, so `in`, `step` and `unit` stay free as names elsewhere (`step(e, v)`).
void Parser::parseParam(Decl& d) {
    if (!expect(Tok::Assign, "'=' after the param's name")) {
        recoverTo(false);
        return;
    }
    d.value = parseExpr();
    if (atWord("in")) {
        advance();
        d.rangeLo = parseExpr();
        if (!expect(Tok::DotDot, "'..' between the range's ends")) {
            recoverTo(false);
            return;
        }
        d.rangeHi = parseExpr();
    }
    if (atWord("step")) {
        advance();
        d.step = parseExpr();
    }
    if (atWord("unit")) {
        advance();
        d.unitRange = range();
        if (!at(Tok::Ident)) {
            diags_.error(range(), Msg::Expected,
                         "a unit's name after 'unit' (a word: px, mm, s...)", describeCurrent());
            recoverTo(false);
            return;
        }
        d.unitLabel = std::string(lexer_.spelling(tok_));
        advance();
    }
    if (!valueEnds()) {
        recoverTo(false);
        return;
    }
    accept(Tok::Semi);
    // The slots a tool writes in place of the default (compiler/Parameters.h): four value
    // components (as many as a colour has) and the switch, all 0 until a tool sets them.
    if (!isStdlib_) {
        d.valueSlot = assignLiteral(0.0);
        for (int i = 1; i < 4; ++i) assignLiteral(0.0);
        d.setSlot = assignLiteral(0.0);
    }
}

bool Parser::parseProperty(std::vector<Property>& props) {
    Property p;
    p.nameRange = range();
    if (!at(Tok::Ident)) {
        diags_.error(range(), Msg::Expected, "a property name or '}'", describeCurrent());
        return false;
    }
    p.name = std::string(lexer_.spelling(tok_));
    advance();
    if (!expect(Tok::Assign, fmt::format("'=' after '{}'", p.name).c_str())) return false;
    p.value = parseExpr();
    props.push_back(std::move(p));
    if (!valueEnds()) return false;
    if (!accept(Tok::Semi)) accept(Tok::Comma);
    return true;
}

void Parser::parseBlock(Decl& d) {
    if (!expect(Tok::LBrace, fmt::format("'{{' to open the {}", declKindName(d.kind)).c_str())) {
        recoverTo(false);
        return;
    }
    while (!at(Tok::RBrace) && !at(Tok::End)) {
        if (diags_.errorCount() >= DiagEngine::kMaxErrors) return;
        // A declaration keyword not followed by '=' is not a property (`family = ...` and
        // `field = ...` are): the block's '}' is missing, and the declaration is left for
        // parseModule to read.
        if (atDeclWord() && !nextIsAssign()) break;
        if (!parseProperty(d.props)) recoverTo(true);
    }
    expect(Tok::RBrace, fmt::format("'}}' to close the {}", declKindName(d.kind)).c_str());
}

void Parser::parseFamily(Decl& d) {
    if (accept(Tok::LParen)) {
        if (!at(Tok::RParen)) {
            do {
                FamilyParam p;
                p.nameRange = range();
                if (!at(Tok::Ident)) {
                    diags_.error(range(), Msg::Expected, "a parameter name", describeCurrent());
                    recoverTo(false);
                    return;
                }
                p.name = std::string(lexer_.spelling(tok_));
                advance();
                if (accept(Tok::Assign)) p.defaultValue = parseExpr();
                d.params.push_back(std::move(p));
            } while (accept(Tok::Comma));
        }
        if (!expect(Tok::RParen, "',' or ')' in the parameter list")) {
            recoverTo(false);
            return;
        }
    }
    if (d.builtin) return; // no body: the compiler provides it
    if (accept(Tok::Assign)) {
        // Shorthand: family name(params) = phase-expression
        Property p;
        p.name = "phase";
        p.nameRange = d.nameRange;
        p.value = parseExpr();
        d.props.push_back(std::move(p));
        if (!valueEnds()) {
            recoverTo(false);
            return;
        }
        accept(Tok::Semi);
        return;
    }
    if (!expect(Tok::LBrace, "'=' or '{' after the family's name")) {
        recoverTo(false);
        return;
    }
    while (!at(Tok::RBrace) && !at(Tok::End)) {
        if (diags_.errorCount() >= DiagEngine::kMaxErrors) return;
        if (atDeclWord()) break; // the family's '}' is missing (see parseBlock)
        if (atWord("let")) {
            advance();
            Let l;
            l.nameRange = range();
            if (!at(Tok::Ident)) {
                diags_.error(range(), Msg::Expected, "a name after 'let'", describeCurrent());
                recoverTo(true);
                continue;
            }
            l.name = std::string(lexer_.spelling(tok_));
            advance();
            if (!expect(Tok::Assign, fmt::format("'=' after '{}'", l.name).c_str())) {
                recoverTo(true);
                continue;
            }
            l.value = parseExpr();
            d.lets.push_back(std::move(l));
            if (!valueEnds()) {
                recoverTo(true);
                continue;
            }
            if (!accept(Tok::Semi)) accept(Tok::Comma);
            continue;
        }
        if (!parseProperty(d.props)) recoverTo(true);
    }
    expect(Tok::RBrace, "'}' to close the family");
}

ExprPtr Parser::errorExpr() {
    return std::make_unique<Expr>(ExprKind::Error, range());
}

ExprPtr Parser::parseExpr() {
    DepthGuard g(depth_);
    if (tooDeep()) return errorExpr();
    return parseSum();
}

ExprPtr Parser::binary(BinOp op, SourceRange opRange, ExprPtr lhs, ExprPtr rhs) {
    auto e = std::make_unique<Expr>(ExprKind::Binary, spanFrom(lhs->range));
    e->opRange = opRange;
    e->bin = op;
    e->args.push_back(std::move(lhs));
    e->args.push_back(std::move(rhs));
    return e;
}

// A chain `a + b + c + ...` builds a left-leaning tree as tall as the chain is long. The
// chain is not nesting: only parentheses, calls, signs and powers count towards kMaxDepth,
// and every later stage walks a chain's left spine in a loop rather than by recursion.
ExprPtr Parser::parseSum() {
    ExprPtr lhs = parseProduct();
    while (at(Tok::Plus) || at(Tok::Minus)) {
        SourceRange opRange = range();
        BinOp op = at(Tok::Plus) ? BinOp::Add : BinOp::Sub;
        advance();
        ExprPtr rhs = parseProduct();
        lhs = binary(op, opRange, std::move(lhs), std::move(rhs));
    }
    return lhs;
}

ExprPtr Parser::parseProduct() {
    ExprPtr lhs = parseUnary();
    while (at(Tok::Star) || at(Tok::Slash)) {
        SourceRange opRange = range();
        BinOp op = at(Tok::Star) ? BinOp::Mul : BinOp::Div;
        advance();
        ExprPtr rhs = parseUnary();
        lhs = binary(op, opRange, std::move(lhs), std::move(rhs));
    }
    return lhs;
}

ExprPtr Parser::parseUnary() {
    if (at(Tok::Minus) || at(Tok::Plus)) {
        DepthGuard g(depth_);
        if (tooDeep()) return errorExpr();
        SourceRange start = range();
        auto e = std::make_unique<Expr>(ExprKind::Unary, start);
        e->un = at(Tok::Minus) ? UnOp::Neg : UnOp::Plus;
        advance();
        e->args.push_back(parseUnary());
        e->range = spanFrom(start);
        return e;
    }
    return parsePower();
}

ExprPtr Parser::parsePower() {
    ExprPtr base = parsePrimary();
    if (!at(Tok::Caret)) return base;
    SourceRange opRange = range();
    advance();
    DepthGuard g(depth_);
    if (tooDeep()) return errorExpr();
    // Right-associative: a ^ b ^ c = a ^ (b ^ c); the exponent may carry a sign: 2 ^ -1.
    ExprPtr exponent = parseUnary();
    return binary(BinOp::Pow, opRange, std::move(base), std::move(exponent));
}

ExprPtr Parser::parsePrimary() {
    SourceRange start = range();
    switch (tok_.kind) {
    case Tok::Number: {
        auto e = std::make_unique<Expr>(ExprKind::Number, start);
        e->number = tok_.number;
        e->unit = tok_.unit;
        e->literalSlot = assignLiteral(tok_.number);
        advance();
        return e;
    }
    case Tok::Color: {
        auto e = std::make_unique<Expr>(ExprKind::Color, start);
        e->rgba = tok_.rgba;
        if (!isStdlib_) {
            e->literalSlot = assignLiteral(tok_.rgba[0]);
            for (int i = 1; i < 4; ++i) assignLiteral(tok_.rgba[i]);
        }
        advance();
        return e;
    }
    case Tok::Ident: {
        std::string name(lexer_.spelling(tok_));
        advance();
        if (!at(Tok::LParen)) {
            auto e = std::make_unique<Expr>(ExprKind::Name, start);
            e->name = std::move(name);
            return e;
        }
        auto e = std::make_unique<Expr>(ExprKind::Call, start);
        e->name = std::move(name);
        advance();
        if (!at(Tok::RParen)) {
            do {
                e->args.push_back(parseExpr());
            } while (accept(Tok::Comma));
        }
        expect(Tok::RParen, fmt::format("',' or ')' in the call to '{}'", e->name).c_str());
        e->range = spanFrom(start);
        return e;
    }
    case Tok::LParen: {
        advance();
        ExprPtr first = parseExpr();
        if (accept(Tok::Comma)) {
            auto v = std::make_unique<Expr>(ExprKind::Vector, start);
            v->args.push_back(std::move(first));
            v->args.push_back(parseExpr());
            while (accept(Tok::Comma)) v->args.push_back(parseExpr());
            expect(Tok::RParen, "')' to close the vector");
            v->range = spanFrom(start);
            return v;
        }
        expect(Tok::RParen, "')'");
        // The parentheses belong to the value a diagnostic points at; its operator or
        // name (opRange) stays where it was.
        first->range = spanFrom(start);
        return first;
    }
    default:
        if (!abandoned_) diags_.error(range(), Msg::Expected, "an expression", describeCurrent());
        // Leave a closing token to whatever expects it (`sin()`, `(1, )`, `size = ;`), so one
        // missing value is one error; skip anything else, so that parsing moves on.
        if (!at(Tok::End) && !at(Tok::RBrace) && !at(Tok::RParen) && !at(Tok::Comma) &&
            !at(Tok::Semi))
            advance();
        return errorExpr();
    }
}

} // namespace moire
