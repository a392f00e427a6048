// The panel's values: literals read as the lexer reads them, values snapped to what the file
// can say exactly, set in a copy of the literal table, and carried over a reload by name.
// Parameters are made by hand here, with the fields a declaration would give them.
#include "runtime/view/ParamValues.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <numbers>

using namespace moire;
using namespace moire::view;

namespace {

constexpr double kRad = std::numbers::pi / 180.0; // what `1deg` reads as

Parameter param(const std::string& name, ast::Type type, std::optional<double> lo = {},
                std::optional<double> hi = {}, std::optional<double> step = {}) {
    Parameter p;
    p.name = name;
    p.type = type;
    p.components = type == ast::Type::Vec2 ? 2 : type == ast::Type::Color ? 4 : 1;
    p.min = lo, p.max = hi, p.step = step;
    if (type == ast::Type::Angle) p.unit = Unit::Deg;
    return p;
}

// The double a decimal reads as (an independent reading: from_chars, not the lexer).
double decimal(const char* s) {
    double v = 0;
    std::from_chars(s, s + std::strlen(s), v);
    return v;
}

// Points `p`'s default at the first `text` in `source` (file 0), after `after`.
void at(Parameter& p, const std::string& source, const std::string& text,
        const std::string& after = "") {
    size_t from = source.find(after);
    REQUIRE(from != std::string::npos);
    size_t i = source.find(text, from);
    REQUIRE(i != std::string::npos);
    p.valueRange = {{0, static_cast<uint32_t>(i)}, static_cast<uint32_t>(text.size())};
}

} // namespace

TEST_CASE("param values: a literal of the parameter's type reads as the language reads it") {
    const Parameter num = param("n", ast::Type::Num), ang = param("a", ast::Type::Angle);
    const Parameter vec = param("v", ast::Type::Vec2), col = param("c", ast::Type::Color);
    const Parameter flag = param("b", ast::Type::Bool);

    CHECK(readLiteral(num, "1.5") == ParamValue{1.5, 0, 0, 0});
    CHECK(readLiteral(num, " -2e1 /* twenty */ ") == ParamValue{-20, 0, 0, 0});
    CHECK(readLiteral(ang, "30deg") == ParamValue{30 * kRad, 0, 0, 0});
    CHECK(readLiteral(ang, "-0.5rad") == ParamValue{-0.5, 0, 0, 0});
    CHECK(readLiteral(vec, "(1, -2.25)") == ParamValue{1, -2.25, 0, 0});
    CHECK(readLiteral(col, "#ff8000") == ParamValue{1, 128 / 255.0, 0, 1});
    CHECK(readLiteral(col, "#ff800040") == ParamValue{1, 128 / 255.0, 0, 64 / 255.0});
    CHECK(readLiteral(flag, "true") == ParamValue{1, 0, 0, 0});
    CHECK(readLiteral(flag, "false") == ParamValue{0, 0, 0, 0});

    // Expressions, other types, and text that is not the language at all.
    for (const char* text : {"1.5 * t", "2 + 1", "--1", "other", "(1)"})
        CHECK_FALSE(readLiteral(num, text));
    CHECK_FALSE(readLiteral(num, "30deg")); // an angle is not a number
    CHECK_FALSE(readLiteral(ang, "30"));    // nor a number an angle
    CHECK_FALSE(readLiteral(vec, "(1, 2) * 2"));
    CHECK_FALSE(readLiteral(vec, "(1, 2 + 3)"));
    CHECK_FALSE(readLiteral(col, "rgb(1, 0, 0)"));
    CHECK_FALSE(readLiteral(col, "#ff80"));
    CHECK_FALSE(readLiteral(flag, "yes"));
    CHECK_FALSE(readLiteral(num, "1 $"));
}

TEST_CASE("param values: a value snaps to the step, the range and what the file can say") {
    // On the step from the range's start, as the decimal the file writes.
    Parameter drift = param("drift", ast::Type::Num, 0, 5, 0.1);
    CHECK(snapParamValue(drift, {1.2345, 0, 0, 0})[0] == decimal("1.2"));
    CHECK(snapParamValue(drift, {0.3000001, 0, 0, 0})[0] == decimal("0.3"));
    CHECK(snapParamValue(drift, {7, 0, 0, 0})[0] == 5);
    CHECK(snapParamValue(drift, {-1, 0, 0, 0})[0] == 0);
    Parameter offset = param("offset", ast::Type::Num, 0.05, 1, 0.1);
    CHECK(snapParamValue(offset, {0.26, 0, 0, 0})[0] == decimal("0.25"));
    // No step: the value as it is, inside the range.
    Parameter free = param("free", ast::Type::Num);
    CHECK(snapParamValue(free, {1.0 / 3, 0, 0, 0})[0] == 1.0 / 3);

    // An angle written in degrees steps in degrees, and is what `17deg` reads as.
    Parameter turn = param("turn", ast::Type::Angle, 0, 45 * kRad, kRad);
    CHECK(snapParamValue(turn, {17.4 * kRad, 0, 0, 0})[0] == 17 * kRad);
    CHECK(snapParamValue(turn, {50 * kRad, 0, 0, 0})[0] == 45 * kRad);
    CHECK(literalText(turn, {17 * kRad, 0, 0, 0}) == "17deg");
    CHECK(literalText(turn, {12.5 * kRad, 0, 0, 0}) == "12.5deg");

    // A vector's components each; a colour's to bytes; a boolean to 0 or 1.
    Parameter shift = param("shift", ast::Type::Vec2, -10, 10, 0.5);
    CHECK(snapParamValue(shift, {1.3, -11, 0, 0}) == ParamValue{1.5, -10, 0, 0});
    Parameter ink = param("ink", ast::Type::Color);
    CHECK(snapParamValue(ink, {0.5, 1.2, -0.1, 1}) == ParamValue{128 / 255.0, 1, 0, 1});
    Parameter on = param("on", ast::Type::Bool);
    CHECK(snapParamValue(on, {0.7, 0, 0, 0}) == ParamValue{1, 0, 0, 0});
    CHECK(snapParamValue(on, {0.2, 0, 0, 0}) == ParamValue{0, 0, 0, 0});
}

TEST_CASE("param values: set values go into their literal slots, the rest stays") {
    Parameter a = param("a", ast::Type::Num), v = param("v", ast::Type::Vec2);
    a.valueSlot = 2, a.setSlot = 3;
    v.valueSlot = 4, v.setSlot = 6;
    std::vector<double> literals = {9, 9, 1.5, 0, 7, 8, 0, 9};
    const std::vector<Parameter> params = {a, v};
    applyParams(params, {std::nullopt, ParamValue{-1, 2, 0, 0}}, literals);
    CHECK(literals == std::vector<double>{9, 9, 1.5, 0, -1, 2, 1, 9});
    applyParams(params, {ParamValue{4, 0, 0, 0}, std::nullopt}, literals);
    CHECK(literals == std::vector<double>{9, 9, 4, 1, -1, 2, 1, 9});
}

TEST_CASE("param values: a reload keeps the values whose parameter the edit left alone") {
    const std::string before = "param a = 1 in 0 .. 5\nparam b = 2 in 0 .. 5\n"
                               "param c = 3 in 0 .. 5\nparam d = 4\nparam e = 5\n";
    // a: untouched; b: its default edited; c: its range narrowed below the value; d: now an
    // angle; e: renamed f; a new parameter g.
    const std::string after = "param g = 0\nparam a = 1 in 0 .. 5\nparam b = 2.5 in 0 .. 5\n"
                              "param c = 3 in 0 .. 2\nparam d = 4deg\nparam f = 5\n";
    std::vector<Parameter> from = {
        param("a", ast::Type::Num, 0, 5), param("b", ast::Type::Num, 0, 5),
        param("c", ast::Type::Num, 0, 5), param("d", ast::Type::Num), param("e", ast::Type::Num)};
    at(from[0], before, "1", "param a"), at(from[1], before, "2", "param b");
    at(from[2], before, "3", "param c"), at(from[3], before, "4", "param d");
    at(from[4], before, "5", "param e");
    std::vector<Parameter> to = {param("g", ast::Type::Num),       param("a", ast::Type::Num, 0, 5),
                                 param("b", ast::Type::Num, 0, 5), param("c", ast::Type::Num, 0, 2),
                                 param("d", ast::Type::Angle),     param("f", ast::Type::Num)};
    at(to[0], after, "0", "param g"), at(to[1], after, "1", "param a");
    at(to[2], after, "2.5", "param b"), at(to[3], after, "3", "param c");
    at(to[4], after, "4deg", "param d"), at(to[5], after, "5", "param f");
    ParamSet set(5, ParamValue{4.5, 0, 0, 0});
    ParamSet carried = carryParams(from, set, before, to, after);
    REQUIRE(carried.size() == 6);
    CHECK_FALSE(carried[0]);
    CHECK(carried[1] == ParamValue{4.5, 0, 0, 0});
    CHECK_FALSE(carried[2]);
    CHECK_FALSE(carried[3]);
    CHECK_FALSE(carried[4]);
    CHECK_FALSE(carried[5]);
    // The same text again: everything set stays.
    ParamSet same = carryParams(from, set, before, from, before);
    for (const auto& v : same) CHECK(v == ParamValue{4.5, 0, 0, 0});
}
