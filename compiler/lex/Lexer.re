// re2c source for the lexer; CMake generates Lexer.cpp from it.
#include "compiler/lex/Lexer.h"

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>

#include "compiler/diag/Suggest.h"
#include "compiler/lex/Keywords.h"

namespace moire {

const char* tokDescription(Tok t) {
    switch (t) {
    case Tok::End: return "end of file";
    case Tok::Ident: return "a name";
    case Tok::Number: return "a number";
    case Tok::Color: return "a colour";
    case Tok::LParen: return "'('";
    case Tok::RParen: return "')'";
    case Tok::LBrace: return "'{'";
    case Tok::RBrace: return "'}'";
    case Tok::Comma: return "','";
    case Tok::Semi: return "';'";
    case Tok::Assign: return "'='";
    case Tok::Plus: return "'+'";
    case Tok::Minus: return "'-'";
    case Tok::Star: return "'*'";
    case Tok::Slash: return "'/'";
    case Tok::Caret: return "'^'";
    case Tok::DotDot: return "'..'";
    }
    return "?";
}

Lexer::Lexer(uint32_t fileId, std::string_view text, DiagEngine& diags)
    : file_(fileId), text_(text), diags_(diags) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
}

void Lexer::skipBlockComment(size_t start) {
    size_t close = text_.find("*/", start + 2);
    if (close == std::string_view::npos) {
        diags_.error(rangeAt(start, 2), Msg::UnterminatedComment);
        pos_ = text_.size();
    } else {
        pos_ = close + 2;
    }
    if (comments_)
        comments_->push_back(
            {static_cast<uint32_t>(start), static_cast<uint32_t>(pos_ - start), true});
}

void Lexer::lexNumber(Token& t, size_t start, size_t end) {
    // The token is a decimal number followed by letters and digits; from_chars reads the
    // longest number it can, and the rest is the unit suffix. (An earlier hand-written scan
    // accepted a second exponent, so "1e3e4" was silently read as 1000.)
    const char* first = text_.data() + start;
    const char* last = text_.data() + end;
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    // Out of range: from_chars leaves v unset; strtod gives +-HUGE_VAL or 0 as the value
    // nearest to what was written (the pattern is already known to be plain decimal).
    if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(first, ptr).c_str(), nullptr);
    size_t digitsEnd = static_cast<size_t>(ptr - text_.data());
    std::string_view suffix = text_.substr(digitsEnd, end - digitsEnd);
    t.kind = Tok::Number;
    t.unit = Unit::None;
    if (suffix == "deg") {
        t.unit = Unit::Deg;
        v *= std::numbers::pi / 180.0;
    } else if (suffix == "rad") {
        t.unit = Unit::Rad;
    } else if (!suffix.empty()) {
        // `2x` and `2r` are multiplications written the way they are on paper; `30degrees`
        // and `1dg` are misspelt units.
        Hint hint;
        std::string number(text_.substr(start, digitsEnd - start));
        std::string near = nearestName(suffix, {std::begin(kUnitNames), std::end(kUnitNames)}, 2);
        // A suggestion must keep some of what was written: "e4" is not a misspelt "deg".
        if (!near.empty() && editDistance(suffix, near) >= static_cast<int>(suffix.size())) near.clear();
        if (suffix.size() == 1 || isBuiltinValueName(suffix)) near.clear();
        else if (suffix.starts_with("deg")) near = "deg";
        else if (suffix.starts_with("rad")) near = "rad";
        if (!near.empty())
            hint = suggest(number + near, rangeAt(start, end - start)); // the whole number
        else if (suffix.size() == 1 || isBuiltinValueName(suffix))
            hint = "; to multiply, write " + number + " * " + std::string(suffix);
        diags_.error(rangeAt(digitsEnd, suffix.size()), Msg::UnknownUnit, suffix, hint);
    }
    t.number = v;
}

void Lexer::lexColor(Token& t, size_t start, size_t end) {
    std::string_view digits = text_.substr(start + 1, end - start - 1);
    bool hex = !digits.empty();
    for (char c : digits) hex = hex && std::isxdigit(static_cast<unsigned char>(c));
    t.kind = Tok::Color;
    t.rgba = {0, 0, 0, 1};
    if (!hex || (digits.size() != 6 && digits.size() != 8)) {
        diags_.error(rangeAt(start, end - start), Msg::BadColor, text_.substr(start, end - start));
        return;
    }
    for (size_t i = 0; i < digits.size() / 2; ++i) {
        unsigned value = 0;
        std::from_chars(digits.data() + 2 * i, digits.data() + 2 * i + 2, value, 16);
        t.rgba[i] = value / 255.0;
    }
}

namespace {
// What to write instead of a character that some other notation uses.
const char* asciiHint(char c) {
    switch (c) {
    case '%': return "; for a remainder, write mod(a, b)";
    case ':': return "; set a property with '=', as in spacing = 4";
    case '"':
    case '\'': return "; names are written without quotes, as in family = circles";
    case '[':
    case ']': return "; write a vector with round brackets, as in (1, 2)";
    default: return "";
    }
}

const char* unicodeHint(uint32_t cp) {
    switch (cp) {
    case 0xB0: return "; for degrees, write 30deg";                    // °
    case 0x3C0: return "; write pi";                                   // π
    case 0x3C4: return "; write tau";                                  // τ
    case 0x3B8: return "; write theta";                                // θ
    case 0xD7: case 0xB7: case 0x22C5: return "; to multiply, write *"; // × · ⋅
    case 0xF7: return "; to divide, write /";                          // ÷
    case 0x2212: case 0x2013: case 0x2014: return "; for minus, write -"; // − – —
    case 0x2018: case 0x2019: case 0x201C: case 0x201D:
        return "; names are written without quotes, as in family = circles";
    case 0xA0: return "; this is a non-breaking space: type an ordinary space";
    default: return "";
    }
}

} // namespace

void Lexer::unexpectedBytes(size_t start) {
    // A whole UTF-8 character is one error with one caret, not one error per byte.
    uint32_t cp = 0;
    size_t n = decodeUtf8(text_, start, cp);
    if (n < 2) n = 0; // ASCII bytes that reach here are control characters
    if (n > 0) {
        diags_.error(rangeAt(start, n), Msg::NonAsciiChar, text_.substr(start, n), cp, unicodeHint(cp));
        pos_ = start + n;
        return;
    }
    diags_.error(rangeAt(start, 1), Msg::UnexpectedByte, static_cast<unsigned char>(text_[start]));
    pos_ = start + 1;
}

Token Lexer::next() {
    const unsigned char* base = reinterpret_cast<const unsigned char*>(text_.data());
    const unsigned char* limit = base + text_.size();
    for (;;) {
        Token t;
        size_t start = pos_;
        t.offset = static_cast<uint32_t>(start);
        if (pos_ >= text_.size()) {
            t.kind = Tok::End;
            return t;
        }
        const unsigned char* cur = base + pos_;
        const unsigned char* mar = cur;
        // The scanner never reads past `limit`: every rule that can consume more than one
        // character stops at a NUL, and the text handed to the lexer is NUL-terminated
        // (std::string). A NUL inside the text is reported as an unexpected byte.
        auto finish = [&](Tok k) {
            pos_ = static_cast<size_t>(cur - base);
            t.kind = k;
            t.length = static_cast<uint32_t>(pos_ - start);
            return t;
        };
        (void)mar;
        (void)limit;
        /*!re2c
            re2c:yyfill:enable = 0;
            re2c:define:YYCTYPE = "unsigned char";
            re2c:define:YYCURSOR = cur;
            re2c:define:YYMARKER = mar;

            digits = [0-9]+;
            mantissa = digits ("." digits?)? | "." digits;
            exponent = [eE] [+-]? digits;
            word = [a-zA-Z0-9_]*;

            [ \t\r\n\f\v]+ { pos_ = static_cast<size_t>(cur - base); continue; }
            "//" {
                // A comment may hold any byte, a NUL included (the scanner's own rules stop
                // at NUL, so the rest of the line is skipped here).
                size_t end = text_.find('\n', start);
                pos_ = end == std::string_view::npos ? text_.size() : end;
                if (comments_)
                    comments_->push_back({static_cast<uint32_t>(start),
                                          static_cast<uint32_t>(pos_ - start), false});
                continue;
            }
            "/*" { skipBlockComment(start); continue; }

            // `0..5`: a whole number just before `..` ends there (else `0.` would be read).
            digits / ".." {
                pos_ = static_cast<size_t>(cur - base);
                t.length = static_cast<uint32_t>(pos_ - start);
                lexNumber(t, start, pos_);
                return t;
            }
            mantissa exponent? word {
                pos_ = static_cast<size_t>(cur - base);
                t.length = static_cast<uint32_t>(pos_ - start);
                lexNumber(t, start, pos_);
                return t;
            }
            "#" word {
                pos_ = static_cast<size_t>(cur - base);
                t.length = static_cast<uint32_t>(pos_ - start);
                lexColor(t, start, pos_);
                return t;
            }
            [a-zA-Z_] word {
                Token name = finish(Tok::Ident);
                if (name.length > kMaxNameLength)
                    diags_.error(rangeAt(start, name.length), Msg::NameTooLong, name.length,
                                 kMaxNameLength);
                return name;
            }

            "(" { return finish(Tok::LParen); }
            ")" { return finish(Tok::RParen); }
            "{" { return finish(Tok::LBrace); }
            "}" { return finish(Tok::RBrace); }
            "," { return finish(Tok::Comma); }
            ";" { return finish(Tok::Semi); }
            "=" { return finish(Tok::Assign); }
            "+" { return finish(Tok::Plus); }
            "-" { return finish(Tok::Minus); }
            "*" { return finish(Tok::Star); }
            "/" { return finish(Tok::Slash); }
            "^" { return finish(Tok::Caret); }
            ".." { return finish(Tok::DotDot); }

            [\x21-\x7e] {
                pos_ = static_cast<size_t>(cur - base);
                diags_.error(rangeAt(start, 1), Msg::UnexpectedChar, std::string(1, text_[start]),
                             asciiHint(text_[start]));
                continue;
            }
            * {
                unexpectedBytes(start);
                continue;
            }
        */
    }
}

} // namespace moire
