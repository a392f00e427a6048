// The abstract syntax tree of a .moire module. The parser builds it; semantic checks
// annotate it (types, resolved names); lowering turns it into IR.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/lex/Token.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace moire::ast {

using moire::Unit; // as the lexer read it

// The value types of the language. Vectors and colours are scalarised during lowering.
enum class Type : uint8_t { Error, Num, Angle, Vec2, Color, Bool };
const char* typeName(Type t); // "a number", "an angle", ...

// Error marks an expression the parser could not read (already diagnosed).
enum class ExprKind : uint8_t { Error, Number, Color, Name, Unary, Binary, Call, Vector };
enum class BinOp : uint8_t { Add, Sub, Mul, Div, Pow };
enum class UnOp : uint8_t { Neg, Plus };
const char* binOpSpelling(BinOp op);

struct Decl;

// What a Name expression refers to, filled in by semantic checks.
enum class RefKind : uint8_t {
    Unresolved,
    Builtin,     // x, y, r, theta, pi, tau, e, t
    Field,       // a top-level field declaration
    FamilyParam, // a parameter of the enclosing family
    Let,         // a let binding in the enclosing family
    Spacing,     // `spacing` inside a family body: the layer's spacing
    Timing,      // a timing's name, as the first argument of ramp, progress or morph
    EasingVar,   // `u` inside an easing
    Family,      // a family's name: a layer's `family`, a member of a morph
    Easing,      // an easing's name: a timing's `easing`
    Param,       // a top-level `param` declaration
    Boolean,     // `true` or `false` (refIndex 1 or 0)
};

struct Expr {
    ExprKind kind;
    SourceRange range;   // the whole expression, for diagnostics about its value
    SourceRange opRange; // the operator of a Unary/Binary, the name of a Call; else = range

    // Number: value in the language's canonical unit (angles in radians).
    double number = 0.0;
    Unit unit = Unit::None;
    // Colour literal, straight (not premultiplied) sRGB components in 0..1.
    std::array<double, 4> rgba{0, 0, 0, 1};
    // User literals live in the scene's literal table (slot >= 0) so that editing a number
    // changes only a uniform; stdlib literals are structural constants (slot == -1).
    int literalSlot = -1;

    // Name / Call
    std::string name;
    // Operators
    BinOp bin = BinOp::Add;
    UnOp un = UnOp::Neg;
    // Operands, call arguments or vector components.
    std::vector<std::unique_ptr<Expr>> args;

    // Annotations from semantic checks.
    Type type = Type::Error;
    RefKind ref = RefKind::Unresolved;
    const Decl* refDecl = nullptr;  // the Field, Timing, Family or Easing decl, or the family
                                    // owning a param/let
    int refIndex = -1;              // builtin id, param index or let index
    bool dependsOnPosition = false; // uses x, y, r or theta (directly or through fields)
    bool dependsOnTime = false;     // uses t

    Expr(ExprKind k, SourceRange r) : kind(k), range(r), opRange(r) {}
    // Takes the tree apart in a loop: a chain `a + b + c + ...` is a left spine as deep as
    // the chain is long, and destroying it by recursion would overflow the stack.
    ~Expr();
    Expr(Expr&&) = default;
    Expr& operator=(Expr&&) = default;
};

// A link of a chain of sums or products, whose left operand may be the chain's previous link.
// Every walk over expressions follows a chain's left spine in a loop, not by recursion
// (the parser does not count a chain's length as nesting).
inline bool isChainLink(const Expr& e) {
    return e.kind == ExprKind::Binary && e.bin != BinOp::Pow;
}
using ExprPtr = std::unique_ptr<Expr>;

struct Property {
    std::string name;
    SourceRange nameRange;
    ExprPtr value;
};

struct Let {
    std::string name;
    SourceRange nameRange;
    ExprPtr value;
};

struct FamilyParam {
    std::string name;
    SourceRange nameRange;
    ExprPtr defaultValue;  // null: the layer must set it
    Type type = Type::Num; // from the default value's type (Num when there is none)
};

enum class DeclKind : uint8_t { Scene, Camera, Field, Family, Layer, Timing, Easing, Param };
const char* declKindName(DeclKind k);

struct Decl {
    DeclKind kind;
    SourceRange range; // the keyword
    std::string name;  // empty for scene, camera and unnamed layers
    SourceRange nameRange;

    std::vector<FamilyParam> params; // family
    std::vector<Let> lets;           // family body, in order
    std::vector<Property> props;     // scene, camera, layer, family body
    ExprPtr value;                   // field; param: its default
    // param: `in lo .. hi`, `step s` and `unit word`, each optional (null / empty when absent).
    ExprPtr rangeLo, rangeHi, step;
    std::string unitLabel;
    SourceRange unitRange;
    // param: the literal slots a tool sets in place of the default (compiler/Parameters.h):
    // the value's components from valueSlot, and setSlot, 1 when they are in force.
    int valueSlot = -1, setSlot = -1;
    // param: the default written in the scene, when `-D` replaced it (its type is the param's).
    ExprPtr sceneDefault;
    bool builtin = false; // family implemented by the compiler (stdlib only)

    const Property* prop(std::string_view n) const {
        for (const Property& p : props)
            if (p.name == n) return &p;
        return nullptr;
    }

    Decl(DeclKind k, SourceRange r) : kind(k), range(r) {}
};
using DeclPtr = std::unique_ptr<Decl>;

struct Module {
    uint32_t file = 0;
    std::vector<DeclPtr> decls;
    // Values of the user literals by slot (angles already in radians; colours as 4 slots).
    std::vector<double> literals;
};

// `moire compile --dump=ast`
std::string printModule(const Module& m);
std::string printExpr(const Expr& e);

} // namespace moire::ast
