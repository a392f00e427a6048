// The tokens of a file together with what lies between them (comments, line breaks), which
// is all the formatter needs to lay them out again. Made by the compiler's own lexer.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/lex/Lexer.h"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace moire::format {

struct GapComment {
    std::string text;    // as written, less trailing blanks (and CRs) of a line comment
    bool block = false;  // /* ... */ (may span lines) rather than // ...
    int linesBefore = 0; // line breaks between it and the token or comment before it
};

struct FormatToken {
    Tok kind = Tok::End;
    std::string_view spelling;
    size_t firstComment = 0, endComment = 0; // the comments just before it: [first, end)
    int linesBefore = 0;   // line breaks between it and the comment or token before it
    bool gapBreak = false; // a line break anywhere between it and the token before it
    size_t match = 0;      // ( and { : the index of the closing bracket; ) and } : the opening
};

class TokenList {
  public:
    // Lexes the file; the caller has parsed it without errors first (errors found again
    // here are not reported). The file must outlive the list.
    TokenList(const SourceManager& sm, uint32_t fileId);

    const FormatToken& operator[](size_t i) const { return tokens_.at(i); }
    size_t size() const { return tokens_.size(); } // the last token is Tok::End
    const std::vector<GapComment>& comments() const { return comments_; }
    bool isWord(size_t i, std::string_view w) const {
        return tokens_.at(i).kind == Tok::Ident && tokens_[i].spelling == w;
    }
    // Whether tokens a and b (a before b) begin on the same line.
    bool sameLine(size_t a, size_t b) const { return lineOf_.at(a) == lineOf_.at(b); }
    // Whether a comment lies between tokens a and b (a before b).
    bool commentsBetween(size_t a, size_t b) const {
        return tokens_.at(a + 1).firstComment != tokens_.at(b).endComment;
    }

  private:
    std::vector<FormatToken> tokens_;
    std::vector<GapComment> comments_;
    std::vector<uint32_t> lineOf_; // each token's 0-based line
};

} // namespace moire::format
