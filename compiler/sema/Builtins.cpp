#include "compiler/sema/Builtins.h"

#include "compiler/lex/Keywords.h"

#include <iterator>

namespace moire::sema {

namespace {
// The spellings are the lexer's list (lex/Keywords.h), in the order of Name.
constexpr const char* const* kSpelling = kBuiltinValueNames;
constexpr NameInfo kNames[] = {
    {kSpelling[0], true, false, "the x coordinate"},
    {kSpelling[1], true, false, "the y coordinate"},
    {kSpelling[2], true, false, "the distance from the origin"},
    {kSpelling[3], true, false, "the polar angle atan2(y, x), in radians"},
    {kSpelling[4], false, false, "pi"},
    {kSpelling[5], false, false, "2 pi"},
    {kSpelling[6], false, false, "Euler's number"},
    {kSpelling[7], false, true, "the scene clock, in seconds"},
};
static_assert(std::size(kNames) == std::size(kBuiltinValueNames));

constexpr FnInfo kFns[] = {
    {"sin", 1, Signature::Trig, "sine"},
    {"cos", 1, Signature::Trig, "cosine"},
    {"tan", 1, Signature::Trig, "tangent"},
    {"asin", 1, Signature::NumToNum, "arc sine, in radians (argument clamped to [-1, 1])"},
    {"acos", 1, Signature::NumToNum, "arc cosine, in radians (argument clamped to [-1, 1])"},
    {"atan", 1, Signature::NumToNum, "arc tangent, in radians"},
    {"atan2", 2, Signature::NumToNum, "atan2(y, x): the angle of (x, y), in radians"},
    {"exp", 1, Signature::NumToNum, "e to the power"},
    {"log", 1, Signature::NumToNum, "natural logarithm (argument floored at 1e-30)"},
    {"sqrt", 1, Signature::NumToNum, "square root (of max(v, 0))"},
    {"abs", 1, Signature::SameUnit, "absolute value"},
    {"floor", 1, Signature::SameUnit, "largest whole number not above"},
    {"fract", 1, Signature::SameUnit, "v - floor(v)"},
    {"round", 1, Signature::SameUnit, "nearest whole number (halves round up)"},
    {"sign", 1, Signature::SameToNum, "-1, 0 or 1"},
    {"min", 2, Signature::SameUnit, "smaller of two"},
    {"max", 2, Signature::SameUnit, "larger of two"},
    {"mod", 2, Signature::SameUnit, "mod(a, b) = a - b floor(a / b)"},
    {"hypot", 2, Signature::SameUnit, "sqrt(a^2 + b^2) without overflow"},
    {"clamp", 3, Signature::SameUnit, "clamp(v, lo, hi)"},
    {"wrap", 2, Signature::SameUnit,
     "wrap(v, w): v moved by whole multiples of w into [-w/2, w/2)"},
    {"smoothstep", 3, Signature::SameToNum,
     "smoothstep(e0, e1, v): 0 below e0, 1 above e1, smooth between"},
    {"mix", 3, Signature::Mix,
     "mix(a, b, u) = a + (b - a) u, for numbers, angles, vectors or colours"},
    {"length", 1, Signature::Length, "length of a 2-vector"},
    {"rgb", 3, Signature::Color, "colour from red, green, blue in 0..1"},
    {"rgba", 4, Signature::Color, "colour from red, green, blue, alpha in 0..1"},
    {"step", 2, Signature::SameToNum, "step(edge, v): 0 below the edge, 1 from it on"},
    {"ramp", 3, Signature::Timed,
     "ramp(timing, from, to): from the first value to the second as the timing runs (eased)"},
    {"progress", 1, Signature::Timed, "progress(timing): the timing's eased progress, 0 to 1"},
    {"select", 3, Signature::Select,
     "select(b, a, c): a where the boolean b is true, else c (any value type)"},
};
} // namespace

const NameInfo& nameInfo(Name n) {
    return kNames[static_cast<int>(n)];
}
const FnInfo& fnInfo(Fn f) {
    return kFns[static_cast<int>(f)];
}

std::optional<Name> lookupName(std::string_view s) {
    for (size_t i = 0; i < std::size(kNames); ++i)
        if (s == kNames[i].spelling) return static_cast<Name>(i);
    return std::nullopt;
}

std::optional<Fn> lookupFn(std::string_view s) {
    for (size_t i = 0; i < std::size(kFns); ++i)
        if (s == kFns[i].spelling) return static_cast<Fn>(i);
    return std::nullopt;
}

const std::vector<std::string>& builtinNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const NameInfo& n : kNames) v.push_back(n.spelling);
        return v;
    }();
    return names;
}

const std::vector<std::string>& builtinFunctions() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const FnInfo& f : kFns) v.push_back(f.spelling);
        return v;
    }();
    return names;
}

} // namespace moire::sema
