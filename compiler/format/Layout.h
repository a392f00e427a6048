// The layout rules of `moire fmt` (docs/formatting.md), applied to the tokens of a file that
// parses. It walks the declarations, blocks and properties of the grammar
// (compiler/parse/Parser.h) over the tokens and hands them to a Writer with the spacing,
// indentation and line breaks of the canonical layout; the comments between tokens go where
// they were (see gap()).
#pragma once

#include "compiler/format/TokenList.h"
#include "compiler/format/Writer.h"

#include <set>
#include <string>

namespace moire::format {

class Layout {
  public:
    // One block of indentation.
    static constexpr int kIndent = 4;

    explicit Layout(const TokenList& tokens) : t_(tokens) {}
    std::string format();

  private:
    // One declaration from token k; returns the index after it.
    size_t decl(size_t k);
    // The block whose '{' is at `open`, its declaration at `indent`.
    void block(size_t open, int indent);
    bool blockOnOneLine(size_t open, int indent);
    // Where the item that begins at k ends: past `[let] name = expression`.
    size_t itemEnd(size_t k) const;
    // Where the expression that begins at k ends.
    size_t exprEnd(size_t k) const;
    // Past a param's `in lo .. hi`, `step s` and `unit word`, from the end of its default.
    size_t paramTail(size_t k);
    // Tokens [b, e) of one declaration header or property, on one line but for the line
    // breaks written inside parentheses or after its '=' (kept, continuation lines aligned).
    void run(size_t b, size_t e, int indent, bool spaceFirst);
    // Begins a line for the item at token k (its comments first; one blank line kept).
    void startItem(size_t k, int indent);
    // A separator (';' or ',') that the layout replaces: its comments are kept.
    void dropSeparator(size_t k, int indent);
    // Writes the comments before token k; returns whether one began a line of its own.
    bool gap(size_t k, int indent);
    bool spaceBefore(size_t k) const;
    bool isSign(size_t k) const; // a unary + or -

    const TokenList& t_;
    Writer w_;
    std::set<size_t> tailWords_; // `in` and `step` of params: a sign after one is a sign
};

} // namespace moire::format
