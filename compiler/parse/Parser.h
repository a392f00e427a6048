// Hand-written recursive-descent parser for .moire modules.
//
//   module   := decl*
//   decl     := 'scene' block | 'camera' block | 'layer' [name] block
//             | 'field' name '=' expr
//             | 'family' name ['(' param (',' param)* ')'] ('=' expr | body)
//   block    := '{' (name '=' expr [';' | ','])* '}'
//   body     := '{' ('let' name '=' expr | name '=' expr)* '}'   (separators optional)
//   param    := name ['=' expr]
//   expr     := sum;  sum := product (('+'|'-') product)*
//   product  := unary (('*'|'/') unary)*
//   unary    := ('-'|'+') unary | power
//   power    := primary ['^' unary]          -- right-associative, binds tighter than unary minus
//   primary  := number [unit] | colour | name ['(' args ')'] | '(' expr [',' expr] ')'
#pragma once

#include "compiler/diag/Diagnostics.h"
#include "compiler/lex/Lexer.h"
#include "compiler/parse/Ast.h"

namespace moire {

class Parser {
  public:
    // Literals of a user file get slots in the module's literal table; stdlib literals are
    // structural constants.
    Parser(const SourceManager& sm, uint32_t fileId, DiagEngine& diags);
    // Reads from byte `start` of the file, numbering its literals' slots from `firstSlot`:
    // a `-D` value, read out of the command line and added to the scene's literal table.
    Parser(const SourceManager& sm, uint32_t fileId, DiagEngine& diags, size_t start,
           int firstSlot);
    // The literals read so far (their slots numbered from the constructor's `firstSlot`).
    const std::vector<double>& literals() const { return literals_; }

    ast::Module parseModule();
    // Parses one expression filling the whole text (used by tests and tools).
    ast::ExprPtr parseStandaloneExpr();

    static constexpr int kMaxDepth = 256;

  private:
    void advance();
    bool at(Tok k) const { return tok_.kind == k; }
    bool atWord(std::string_view w) const { return at(Tok::Ident) && lexer_.spelling(tok_) == w; }
    bool accept(Tok k);
    // Reports "expected <what>, found <current token>" and returns false when not at `k`.
    bool expect(Tok k, const char* what);
    std::string describeCurrent() const;
    // Where the current token is (for "found X" diagnostics).
    SourceRange range() const;
    SourceRange spanFrom(SourceRange start) const;
    // Skip to something that can begin the next declaration or property after an error.
    void recoverTo(bool inBlock);
    bool atDeclWord() const;
    // Whether the token after the current one is '=' (a property, not a declaration: a
    // layer's `field = saddle` against `field saddle = ...`).
    bool nextIsAssign() const;
    // Reports TooDeep once depth_ is past kMaxDepth, and skips the rest of the input.
    bool tooDeep();
    // After a value: false (reported) when a second value follows with no operator between.
    bool valueEnds();

    ast::DeclPtr parseDecl();
    void parseBlock(ast::Decl& d);
    void parseFamily(ast::Decl& d);
    void parseParam(ast::Decl& d);
    bool parseProperty(std::vector<ast::Property>& props);

    ast::ExprPtr parseExpr();
    ast::ExprPtr parseSum();
    ast::ExprPtr parseProduct();
    ast::ExprPtr parseUnary();
    ast::ExprPtr parsePower();
    ast::ExprPtr parsePrimary();
    ast::ExprPtr errorExpr();
    ast::ExprPtr binary(ast::BinOp op, SourceRange opRange, ast::ExprPtr lhs, ast::ExprPtr rhs);
    int assignLiteral(double v);

    uint32_t file_;
    std::string_view text_;
    bool isStdlib_;
    DiagEngine& diags_;
    Lexer lexer_;
    Token tok_;
    Token prevTok_;
    int depth_ = 0;          // nesting of the expression being read (chains do not count)
    bool abandoned_ = false; // an expression was too deep; the rest of the input is skipped
    std::vector<double> literals_;
    int firstSlot_ = 0;
};

} // namespace moire
