// re2c source for the lexer; CMake generates Lexer.cpp from it.
#include "compiler/lex/Lexer.h"

#include <charconv>
#include <cmath>
#include <numbers>
#include <string>

#include "compiler/sema/Suggest.h"

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
}

void Lexer::lexNumber(Token& t, size_t start, size_t end) {
    // The digits run up to the first letter; what follows is a unit suffix.
    size_t digitsEnd = start;
    while (digitsEnd < end) {
        char c = text_[digitsEnd];
        bool exp = (c == 'e' || c == 'E') && digitsEnd + 1 < end &&
                   (std::isdigit(static_cast<unsigned char>(text_[digitsEnd + 1])) ||
                    ((text_[digitsEnd + 1] == '+' || text_[digitsEnd + 1] == '-') &&
                     digitsEnd + 2 < end &&
                     std::isdigit(static_cast<unsigned char>(text_[digitsEnd + 2]))));
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
            ++digitsEnd;
        } else if (exp) {
            digitsEnd += 2;
        } else {
            break;
        }
    }
    double v = 0.0;
    std::from_chars(text_.data() + start, text_.data() + digitsEnd, v);
    std::string_view suffix = text_.substr(digitsEnd, end - digitsEnd);
    t.kind = Tok::Number;
    t.unit = ast::Unit::None;
    if (suffix == "deg") {
        t.unit = ast::Unit::Deg;
        v *= std::numbers::pi / 180.0;
    } else if (suffix == "rad") {
        t.unit = ast::Unit::Rad;
    } else if (!suffix.empty()) {
        std::string hint;
        std::string near = nearestName(suffix, {"deg", "rad"}, 2);
        if (!near.empty())
            hint = "; did you mean '" + near + "'?";
        else
            hint = "; to multiply, write " + std::string(text_.substr(start, digitsEnd - start)) +
                   " * " + std::string(suffix);
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
            "//" [^\n\x00]* { pos_ = static_cast<size_t>(cur - base); continue; }
            "/*" { skipBlockComment(start); continue; }

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
            [a-zA-Z_] word { return finish(Tok::Ident); }

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

            [\x21-\x7e] {
                pos_ = static_cast<size_t>(cur - base);
                diags_.error(rangeAt(start, 1), Msg::UnexpectedChar, std::string(1, text_[start]));
                continue;
            }
            * {
                pos_ = static_cast<size_t>(cur - base);
                diags_.error(rangeAt(start, 1), Msg::UnexpectedByte,
                             static_cast<unsigned>(base[start]));
                continue;
            }
        */
    }
}

} // namespace moire
