#include "compiler/Parameters.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lex/Lexer.h"
#include "compiler/sema/ConstantValue.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace moire {

using namespace ast;

namespace {
int componentsOf(Type t) {
    return t == Type::Vec2 ? 2 : t == Type::Color ? 4 : 1;
}

// The unit a default's angle was written in: `30deg`, `-0.5rad`, `(10deg)`.
Unit writtenUnit(const Expr& e) {
    if (e.kind == ExprKind::Number) return e.unit;
    if (e.kind == ExprKind::Unary) return writtenUnit(*e.args[0]);
    if (e.kind == ExprKind::Binary)
        for (const ExprPtr& a : e.args)
            if (Unit u = writtenUnit(*a); u != Unit::None) return u;
    return Unit::None;
}

// The shortest text that reads back as the same double.
std::string shortest(double v) {
    if (v == 0) return "0";
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}
// The shortest degrees that the lexer reads back (d * pi / 180) as exactly `radians`: the
// radians times 180 / pi alone can be 30.000000000000004 for what `30deg` read.
std::string shortestDegrees(double radians) {
    const double degrees = radians * 180.0 / std::numbers::pi;
    for (int decimals = 0; decimals <= 17; ++decimals) {
        std::string text = fmt::format("{:.{}f}", degrees, decimals);
        if (std::stod(text) * (std::numbers::pi / 180.0) == radians)
            return shortest(std::stod(text));
    }
    return shortest(degrees);
}
// The tokens of `text`, none of them malformed; empty when the lexer reports anything.
std::optional<std::vector<Token>> tokens(std::string_view text) {
    SourceManager sm;
    const uint32_t file = sm.add("<value>", std::string(text));
    DiagEngine diags(sm);
    Lexer lexer(file, sm.file(file).text(), diags);
    std::vector<Token> out;
    for (Token t = lexer.next();; t = lexer.next()) {
        out.push_back(t);
        if (t.kind == Tok::End) break;
        if (t.kind == Tok::Ident) // only `true` and `false` are read, and only alone
            out.back().number = lexer.spelling(t) == "true"    ? 1
                                : lexer.spelling(t) == "false" ? 0
                                                               : -1;
    }
    if (diags.hasErrors()) return std::nullopt;
    return out;
}

// Reads `[-] number` at `at` with the unit `unit` (None: none written; an angle takes Deg or
// Rad), advancing `at`.
bool signedNumber(const std::vector<Token>& ts, size_t& at, bool angle, double& v) {
    const bool minus = ts[at].kind == Tok::Minus;
    if (minus) ++at;
    const Token& t = ts[at];
    if (t.kind != Tok::Number || (t.unit == Unit::None) == angle) return false;
    v = minus ? -t.number : t.number;
    ++at;
    return true;
}

} // namespace

std::vector<Parameter> collectParameters(const sema::CheckedScene& scene) {
    std::vector<Parameter> out;
    for (const Decl* d : scene.params) {
        Parameter p;
        p.name = d->name;
        p.type = d->value->type;
        p.components = componentsOf(p.type);
        if (d->rangeLo) {
            p.min = sema::constantValue(*d->rangeLo);
            p.max = sema::constantValue(*d->rangeHi);
        }
        if (d->step) p.step = sema::constantValue(*d->step);
        p.unitLabel = d->unitLabel;
        if (p.type == Type::Angle) {
            p.unit = writtenUnit(*d->value);
            if (p.unit == Unit::None && d->rangeLo) p.unit = writtenUnit(*d->rangeHi);
            if (p.unit == Unit::None) p.unit = Unit::Rad;
        }
        p.nameRange = d->nameRange;
        p.valueRange = d->value->range;
        p.valueSlot = d->valueSlot;
        p.setSlot = d->setSlot;
        out.push_back(std::move(p));
    }
    return out;
}

std::string checkParameterValue(const Parameter& p, std::span<const double> value) {
    if (static_cast<int>(value.size()) != p.components)
        return fmt::format("param '{}' is {} and takes {} number{}, not {}", p.name,
                           typeName(p.type), p.components, p.components == 1 ? "" : "s",
                           value.size());
    for (double v : value)
        if (!std::isfinite(v)) return fmt::format("param '{}' must be finite, not {}", p.name, v);
    if (p.type == Type::Bool && value[0] != 0 && value[0] != 1)
        return fmt::format("param '{}' is a boolean: 0 (false) or 1 (true), not {}", p.name,
                           value[0]);
    if (p.type == Type::Color)
        for (double v : value)
            if (v < 0 || v > 1)
                return fmt::format("the components of colour param '{}' are from 0 to 1, not {}",
                                   p.name, v);
    if (p.min && p.max)
        for (double v : value)
            if (v < *p.min || v > *p.max)
                return fmt::format("param '{}' must be from {:g} to {:g}, not {:g}", p.name, *p.min,
                                   *p.max, v);
    return {};
}

void setParameterValue(const Parameter& p, std::span<const double> value,
                       std::vector<double>& literals) {
    for (size_t i = 0; i < value.size() && static_cast<int>(i) < p.components; ++i)
        literals.at(static_cast<size_t>(p.valueSlot) + i) = value[i];
    literals.at(static_cast<size_t>(p.setSlot)) = 1.0;
}

void clearParameterValue(const Parameter& p, std::vector<double>& literals) {
    literals.at(static_cast<size_t>(p.setSlot)) = 0.0;
}

const char* parameterKind(ast::Type type) {
    switch (type) {
    case ast::Type::Angle:
        return "angle";
    case ast::Type::Vec2:
        return "vector";
    case ast::Type::Color:
        return "color";
    case ast::Type::Bool:
        return "bool";
    default:
        return "number";
    }
}

std::string formatParameterValue(const Parameter& p, std::span<const double> value) {
    auto at = [&](size_t i) { return i < value.size() ? value[i] : 0.0; };
    switch (p.type) {
    case Type::Angle:
        if (p.unit == Unit::Deg) return shortestDegrees(at(0)) + "deg";
        return shortest(at(0)) + "rad";
    case Type::Vec2:
        return "(" + shortest(at(0)) + ", " + shortest(at(1)) + ")";
    case Type::Color: {
        auto byte = [](double v) {
            return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
        };
        std::string hex = fmt::format("#{:02x}{:02x}{:02x}", byte(at(0)), byte(at(1)), byte(at(2)));
        if (byte(at(3)) != 255) hex += fmt::format("{:02x}", byte(at(3)));
        return hex;
    }
    case Type::Bool:
        return at(0) != 0 ? "true" : "false";
    default:
        return shortest(at(0));
    }
}

std::optional<std::array<double, 4>> readParameterValue(const Parameter& p, std::string_view text) {
    std::optional<std::vector<Token>> ts = tokens(text);
    if (!ts) return std::nullopt;
    std::array<double, 4> v{};
    size_t at = 0;
    switch (p.type) {
    case ast::Type::Num:
    case ast::Type::Angle:
        if (!signedNumber(*ts, at, p.type == ast::Type::Angle, v[0])) return std::nullopt;
        break;
    case ast::Type::Vec2:
        if ((*ts)[at++].kind != Tok::LParen || !signedNumber(*ts, at, false, v[0]) ||
            (*ts)[at++].kind != Tok::Comma || !signedNumber(*ts, at, false, v[1]) ||
            (*ts)[at++].kind != Tok::RParen)
            return std::nullopt;
        break;
    case ast::Type::Color:
        if ((*ts)[at].kind != Tok::Color) return std::nullopt;
        v = (*ts)[at++].rgba;
        break;
    case ast::Type::Bool:
        if ((*ts)[at].kind != Tok::Ident || (*ts)[at].number < 0) return std::nullopt;
        v[0] = (*ts)[at++].number;
        break;
    default:
        return std::nullopt;
    }
    if ((*ts)[at].kind != Tok::End) return std::nullopt;
    return v;
}

} // namespace moire
