// The lexer's comments for the formatter (Lexer::keepComments): each comment once, where it is
// written, and the tokens exactly those of a lexer that keeps none.
#include "compiler/lex/Lexer.h"

#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire;

namespace {
struct Lexed {
    std::vector<Tok> kinds;
    std::vector<uint32_t> offsets;
    std::vector<Comment> comments;
};

Lexed lex(const std::string& text, bool keep) {
    SourceManager sm;
    uint32_t id = sm.add("c.moire", text);
    DiagEngine diags(sm);
    Lexer lexer(id, sm.file(id).text(), diags);
    Lexed out;
    if (keep) lexer.keepComments(&out.comments);
    for (size_t i = 0; i <= text.size(); ++i) {
        Token t = lexer.next();
        out.kinds.push_back(t.kind);
        out.offsets.push_back(t.offset);
        if (t.kind == Tok::End) break;
    }
    return out;
}
} // namespace

TEST_CASE("lexer: kept comments are each line and block comment, at its offset") {
    const std::string text = "a = 1 // one\n/* two\n */ b /**/= 2 //";
    Lexed l = lex(text, true);
    REQUIRE(l.comments.size() == 4);
    CHECK(l.comments[0].offset == 6);
    CHECK(l.comments[0].length == 6); // the line comment stops before its newline
    CHECK_FALSE(l.comments[0].block);
    CHECK(l.comments[1].offset == 13);
    CHECK(l.comments[1].length == 10); // "/* two\n */"
    CHECK(l.comments[1].block);
    CHECK(l.comments[2].offset == 26);
    CHECK(l.comments[2].length == 4);
    CHECK(l.comments[3].offset == 34); // a comment at the very end, with no newline
    CHECK(l.comments[3].length == 2);
    for (const Comment& c : l.comments) {
        std::string s = text.substr(c.offset, c.length);
        CHECK(s.starts_with(c.block ? "/*" : "//"));
        if (c.block) CHECK(s.ends_with("*/"));
    }
}

TEST_CASE("lexer: keeping comments changes no token") {
    const std::string text =
        "// head\nscene { size = (1, 2) /* w */ } // tail\nfield f = x /* a */ * 2 // end";
    Lexed kept = lex(text, true);
    Lexed plain = lex(text, false);
    CHECK(kept.kinds == plain.kinds);
    CHECK(kept.offsets == plain.offsets);
    CHECK(plain.comments.empty());
    CHECK(kept.comments.size() == 5);
}

TEST_CASE("lexer: an unterminated block comment is kept to the end of the text") {
    const std::string text = "a = 1 /* open";
    Lexed l = lex(text, true);
    REQUIRE(l.comments.size() == 1);
    CHECK(l.comments[0].offset == 6);
    CHECK(l.comments[0].length == text.size() - 6);
}
