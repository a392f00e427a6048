// The lexer on its own: token kinds and positions, numbers and units, colours, comments, and
// every kind of malformed input (each reported once, skipped, and lexing still ends).
// Expected values are written out or computed here, never read back from the lexer.
#include "compiler/lex/Lexer.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;

namespace {

struct Lexed {
    std::vector<Token> tokens; // without the final End
    std::vector<std::string> spellings;
    std::vector<Diagnostic> diags;
};

Lexed lex(std::string text) {
    SourceManager sm;
    uint32_t id = sm.add("lex.moire", std::move(text));
    DiagEngine diags(sm);
    Lexer lexer(id, sm.file(id).text(), diags);
    Lexed out;
    // Every call consumes at least one byte, so a lexer that stops advancing is a bug; the
    // bound turns that into a failure instead of a hang.
    for (size_t i = 0; i <= sm.file(id).text().size(); ++i) {
        Token t = lexer.next();
        if (t.kind == Tok::End) {
            out.diags = diags.all();
            return out;
        }
        out.tokens.push_back(t);
        out.spellings.emplace_back(lexer.spelling(t));
    }
    FAIL("the lexer did not reach the end of the text");
    return out;
}

// A string literal with embedded NULs, all of it.
template <size_t N>
std::string bytes(const char (&s)[N]) {
    return std::string(s, N - 1);
}

std::vector<Tok> kinds(const Lexed& l) {
    std::vector<Tok> k;
    for (const Token& t : l.tokens) k.push_back(t.kind);
    return k;
}

// The single number in `text`, which must lex without errors.
Token number(const std::string& text) {
    Lexed l = lex(text);
    INFO("text: ", text);
    REQUIRE(l.diags.empty());
    REQUIRE(l.tokens.size() == 1);
    REQUIRE(l.tokens[0].kind == Tok::Number);
    return l.tokens[0];
}

} // namespace

TEST_CASE("lexer: punctuation, names and their positions") {
    Lexed l = lex("scene { size = (1, 2); } + - * / ^");
    std::vector<Tok> want = {Tok::Ident,  Tok::LBrace, Tok::Ident,  Tok::Assign,
                             Tok::LParen, Tok::Number, Tok::Comma,  Tok::Number,
                             Tok::RParen, Tok::Semi,   Tok::RBrace, Tok::Plus,
                             Tok::Minus,  Tok::Star,   Tok::Slash,  Tok::Caret};
    CHECK(kinds(l) == want);
    CHECK(l.diags.empty());
    CHECK(l.spellings[0] == "scene");
    CHECK(l.spellings[2] == "size");

    Lexed names = lex("  _a1 b_2\tCamelCase");
    REQUIRE(names.tokens.size() == 3);
    CHECK(names.spellings == std::vector<std::string>{"_a1", "b_2", "CamelCase"});
    CHECK(names.tokens[0].offset == 2);
    CHECK(names.tokens[0].length == 3);
    CHECK(names.tokens[2].offset == 10);
}

TEST_CASE("lexer: numbers in every written form") {
    CHECK(number("1").number == 1.0);
    CHECK(number("1.5").number == 1.5);
    CHECK(number(".5").number == 0.5);
    CHECK(number("5.").number == 5.0);
    CHECK(number("1e3").number == 1000.0);
    CHECK(number("2.5e-2").number == 0.025);
    CHECK(number("1E+2").number == 100.0);
    CHECK(number("007").number == 7.0);
    CHECK(number("1").unit == Unit::None);
    // A sign is an operator, not part of the number.
    Lexed neg = lex("-3");
    CHECK(kinds(neg) == std::vector<Tok>{Tok::Minus, Tok::Number});
    // Past the range of double: the nearest value, not zero.
    CHECK(std::isinf(number("1e999").number));
    CHECK(number("1e-999").number == 0.0);
}

TEST_CASE("lexer: angle units convert to radians") {
    Token deg = number("30deg");
    CHECK(deg.unit == Unit::Deg);
    CHECK(deg.number == doctest::Approx(30 * std::numbers::pi / 180).epsilon(1e-15));
    Token rad = number("2rad");
    CHECK(rad.unit == Unit::Rad);
    CHECK(rad.number == 2.0);
    CHECK(number("0.5deg").number == doctest::Approx(0.5 * std::numbers::pi / 180).epsilon(1e-15));
    CHECK(number("1e1deg").number == doctest::Approx(10 * std::numbers::pi / 180).epsilon(1e-15));
    CHECK(number("90deg").length == 5);
}

TEST_CASE("lexer: an unknown unit is reported, with a hint when one fits") {
    Lexed px = lex("3px");
    REQUIRE(px.diags.size() == 1);
    CHECK(px.diags[0].msg == Msg::UnknownUnit);
    CHECK(px.diags[0].text == "unknown unit 'px' after a number; the units are deg and rad");
    CHECK(px.diags[0].range.begin.offset == 1); // the suffix, not the digits
    CHECK(px.diags[0].range.length == 2);
    REQUIRE(px.tokens.size() == 1);
    CHECK(px.tokens[0].number == 3.0); // still a number, so parsing goes on

    // `2x` is paper notation for a product.
    Lexed product = lex("2x");
    REQUIRE(product.diags.size() == 1);
    CHECK(product.diags[0].text ==
          "unknown unit 'x' after a number; the units are deg and rad; to multiply, write 2 * x");
    Lexed spelt = lex("30degrees");
    REQUIRE(spelt.diags.size() == 1);
    CHECK(
        spelt.diags[0].text ==
        "unknown unit 'degrees' after a number; the units are deg and rad; did you mean '30deg'?");
    Lexed typo = lex("1.5rda");
    REQUIRE(typo.diags.size() == 1);
    CHECK(typo.diags[0].text ==
          "unknown unit 'rda' after a number; the units are deg and rad; did you mean '1.5rad'?");
    // A second exponent is not part of the number.
    Lexed twoExp = lex("1e3e4");
    REQUIRE(twoExp.diags.size() == 1);
    CHECK(twoExp.diags[0].text == "unknown unit 'e4' after a number; the units are deg and rad");
    CHECK(twoExp.tokens[0].number == 1000.0);
}

TEST_CASE("lexer: colours give straight components in 0..1") {
    Lexed six = lex("#ff8000");
    REQUIRE(six.tokens.size() == 1);
    CHECK(six.diags.empty());
    CHECK(six.tokens[0].kind == Tok::Color);
    CHECK(six.tokens[0].rgba == std::array<double, 4>{1.0, 128 / 255.0, 0.0, 1.0});
    Lexed eight = lex("#11223344");
    REQUIRE(eight.tokens.size() == 1);
    CHECK(eight.tokens[0].rgba ==
          std::array<double, 4>{17 / 255.0, 34 / 255.0, 51 / 255.0, 68 / 255.0});
    Lexed upper = lex("#ABCDEF");
    CHECK(upper.tokens[0].rgba ==
          std::array<double, 4>{171 / 255.0, 205 / 255.0, 239 / 255.0, 1.0});
}

TEST_CASE("lexer: a colour with the wrong digits is one error over the whole colour") {
    for (std::string bad : {"#fff", "#1234567", "#12345g", "#"}) {
        CAPTURE(bad);
        Lexed l = lex(bad + " x");
        REQUIRE(l.diags.size() == 1);
        CHECK(l.diags[0].msg == Msg::BadColor);
        CHECK(l.diags[0].range.length == bad.size());
        CHECK(l.diags[0].text.find("'" + bad + "'") != std::string::npos);
        CHECK(kinds(l) == std::vector<Tok>{Tok::Color, Tok::Ident});
    }
}

TEST_CASE("lexer: comments are skipped, whatever they hold") {
    CHECK(kinds(lex("a // b c\nd")) == std::vector<Tok>{Tok::Ident, Tok::Ident});
    CHECK(kinds(lex("a /* b\n c */ d")) == std::vector<Tok>{Tok::Ident, Tok::Ident});
    CHECK(kinds(lex("a // at the end")) == std::vector<Tok>{Tok::Ident});
    CHECK(kinds(lex("a/**/b")) == std::vector<Tok>{Tok::Ident, Tok::Ident});
    // Non-ASCII text, control bytes and NUL are all fine inside comments.
    Lexed any = lex(bytes("// \xC3\xA9t\xC3\xA9 \x01 \0 x\n/* \xCF\x80 \xFF \0 */ y"));
    CHECK(any.diags.empty());
    CHECK(any.spellings == std::vector<std::string>{"y"});
    // Block comments do not nest: the first */ ends the comment.
    CHECK(kinds(lex("/* /* */ */")) == std::vector<Tok>{Tok::Star, Tok::Slash});
}

TEST_CASE("lexer: an unterminated block comment is reported at its start") {
    Lexed l = lex("a /* no end\nb c");
    REQUIRE(l.diags.size() == 1);
    CHECK(l.diags[0].msg == Msg::UnterminatedComment);
    CHECK(l.diags[0].range.begin.offset == 2);
    CHECK(l.diags[0].range.length == 2);
    CHECK(kinds(l) == std::vector<Tok>{Tok::Ident}); // the comment ran to the end
}

TEST_CASE("lexer: a UTF-8 byte-order mark at the start is skipped") {
    Lexed l = lex("\xEF\xBB\xBFscene");
    CHECK(l.diags.empty());
    REQUIRE(l.tokens.size() == 1);
    CHECK(l.spellings[0] == "scene");
    CHECK(l.tokens[0].offset == 3);
    // Anywhere else it is a stray character.
    Lexed inner = lex("a \xEF\xBB\xBF");
    REQUIRE(inner.diags.size() == 1);
    CHECK(inner.diags[0].msg == Msg::NonAsciiChar);
}

TEST_CASE("lexer: stray ASCII characters are reported and skipped") {
    Lexed l = lex("a @ b");
    REQUIRE(l.diags.size() == 1);
    CHECK(l.diags[0].text == "unexpected character '@'");
    CHECK(l.diags[0].range.begin.offset == 2);
    CHECK(l.spellings == std::vector<std::string>{"a", "b"});
    Lexed pct = lex("x % 2");
    REQUIRE(pct.diags.size() == 1);
    CHECK(pct.diags[0].text == "unexpected character '%'; for a remainder, write mod(a, b)");
    Lexed dot = lex(". 5");
    REQUIRE(dot.diags.size() == 1);
    CHECK(dot.diags[0].msg == Msg::UnexpectedChar);
}

TEST_CASE("lexer: a non-ASCII character is one error, however many bytes it has") {
    Lexed l = lex("x \xC3\x97 y"); // U+00D7 multiplication sign, 2 bytes
    REQUIRE(l.diags.size() == 1);
    CHECK(l.diags[0].msg == Msg::NonAsciiChar);
    CHECK(l.diags[0].text ==
          "unexpected character '\xC3\x97' (U+00D7): outside comments, use only ASCII "
          "characters; to multiply, write *");
    CHECK(l.diags[0].range.begin.offset == 2);
    CHECK(l.diags[0].range.length == 2);
    CHECK(l.spellings == std::vector<std::string>{"x", "y"});
    Lexed emoji = lex("\xF0\x9F\x8E\xA8"); // U+1F3A8, 4 bytes
    REQUIRE(emoji.diags.size() == 1);
    CHECK(emoji.diags[0].text.find("(U+1F3A8)") != std::string::npos);
    CHECK(emoji.diags[0].range.length == 4);
    CHECK(emoji.tokens.empty());
}

TEST_CASE("lexer: bytes that are not UTF-8 text are reported one by one") {
    // 0xE9 is Latin-1 'e acute': a file saved in the wrong encoding.
    Lexed latin1 = lex("caf\xE9 = 1");
    REQUIRE(latin1.diags.size() == 1);
    CHECK(latin1.diags[0].text ==
          "unexpected byte 0xE9, which is not a printable character of UTF-8 text");
    CHECK(latin1.spellings == std::vector<std::string>{"caf", "=", "1"});
    // A lone continuation byte, an overlong encoding of '/', a cut-short sequence, DEL.
    for (std::string bad : {"\x80", "\xC0\xAF", "\xE2\x88", "\x7F"}) {
        CAPTURE(bad);
        Lexed l = lex("a" + bad + "b");
        CHECK(l.diags.size() == bad.size());
        for (const Diagnostic& d : l.diags) CHECK(d.msg == Msg::UnexpectedByte);
        CHECK(l.spellings == std::vector<std::string>{"a", "b"});
    }
}

TEST_CASE("lexer: NUL and control bytes in the text are errors, and lexing goes on past them") {
    Lexed l = lex(bytes("a\0b\x01"
                        "c"));
    REQUIRE(l.diags.size() == 2);
    CHECK(l.diags[0].text ==
          "unexpected byte 0x00, which is not a printable character of UTF-8 text");
    CHECK(l.diags[0].range.begin.offset == 1);
    CHECK(l.diags[1].text ==
          "unexpected byte 0x01, which is not a printable character of UTF-8 text");
    CHECK(l.spellings == std::vector<std::string>{"a", "b", "c"});
    // A NUL right after a number or a name ends it; it is not read past.
    Lexed tail = lex(bytes("12\0"));
    REQUIRE(tail.tokens.size() == 1);
    CHECK(tail.tokens[0].number == 12.0);
    CHECK(tail.diags.size() == 1);
}

TEST_CASE("lexer: any bytes at all lex to the end without hanging") {
    // A deterministic scramble of every byte value, cut at every length: each prefix must
    // lex to End (the helper fails on a lexer that stops advancing).
    std::string text;
    uint32_t state = 12345;
    for (int i = 0; i < 600; ++i) {
        state = state * 1664525u + 1013904223u;
        text += static_cast<char>(i < 256 ? i : (state >> 24));
    }
    for (size_t n = 0; n <= text.size(); n += 7) {
        Lexed l = lex(text.substr(0, n));
        CHECK(l.tokens.size() <= n);
    }
}
