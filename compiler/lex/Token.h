// Tokens: what the lexer gives the parser.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace moire {

// The unit written after a number (the AST keeps it as ast::Unit).
enum class Unit : uint8_t { None, Deg, Rad };

enum class Tok : uint8_t {
    End,
    Ident,
    Number,
    Color,
    LParen,
    RParen,
    LBrace,
    RBrace,
    Comma,
    Semi,
    Assign,
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    DotDot, // `..` between the ends of a parameter's range
};

// How a token kind is named in "expected X, found Y" diagnostics.
const char* tokDescription(Tok t);

struct Token {
    Tok kind = Tok::End;
    uint32_t offset = 0;
    uint32_t length = 0;
    double number = 0.0;          // Number: value in canonical units (radians for angles)
    Unit unit = Unit::None;       // Number: the written unit
    std::array<double, 4> rgba{}; // Color
};

} // namespace moire
