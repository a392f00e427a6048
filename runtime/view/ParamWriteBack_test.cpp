// Writing the panel's values into the scene's text: the changed defaults replaced in place,
// every other byte kept (comments, spacing, line breaks), expressions left alone with the
// reason. The expected texts are written out by hand.
#include "runtime/view/ParamWriteBack.h"

#include <doctest/doctest.h>
#include <numbers>

using namespace moire;
using namespace moire::view;

namespace {

constexpr double kRad = std::numbers::pi / 180.0;

// A parameter declared in `source` whose default is the first `text` after `name`.
Parameter declared(const std::string& source, const std::string& name, ast::Type type,
                   const std::string& text) {
    Parameter p;
    p.name = name;
    p.type = type;
    p.components = type == ast::Type::Vec2 ? 2 : type == ast::Type::Color ? 4 : 1;
    if (type == ast::Type::Angle) p.unit = text.ends_with("deg") ? Unit::Deg : Unit::Rad;
    size_t from = source.find("param " + name);
    REQUIRE(from != std::string::npos);
    size_t i = source.find(text, from);
    REQUIRE(i != std::string::npos);
    p.valueRange = {{0, static_cast<uint32_t>(i)}, static_cast<uint32_t>(text.size())};
    return p;
}

} // namespace

TEST_CASE("param write-back: changed defaults are replaced in place, the rest kept") {
    const std::string source =
        "// drifting circles\n"
        "param drift   = 1.2   in 0 .. 5 step 0.1 // how far\n"
        "param turn = 10deg in 0deg .. 45deg\n"
        "param shift = ( 1,  2 )\n"
        "/* ink */ param ink = #ff8800\n"
        "param dense = true\n"
        "param still = 3\n"
        "layer a { family = circles; spacing = 4 + drift; rotation = turn }\n";
    const std::vector<Parameter> params = {declared(source, "drift", ast::Type::Num, "1.2"),
                                           declared(source, "turn", ast::Type::Angle, "10deg"),
                                           declared(source, "shift", ast::Type::Vec2, "( 1,  2 )"),
                                           declared(source, "ink", ast::Type::Color, "#ff8800"),
                                           declared(source, "dense", ast::Type::Bool, "true"),
                                           declared(source, "still", ast::Type::Num, "3")};
    ParamSet set = {ParamValue{2.5, 0, 0, 0},  ParamValue{30 * kRad, 0, 0, 0},
                    ParamValue{1, -0.5, 0, 0}, ParamValue{0, 1, 128 / 255.0, 1},
                    ParamValue{0, 0, 0, 0},    ParamValue{3, 0, 0, 0}};
    ParamWriteBack w = writeBackParameters(source, 0, params, set);
    CHECK(w.text == "// drifting circles\n"
                    "param drift   = 2.5   in 0 .. 5 step 0.1 // how far\n"
                    "param turn = 30deg in 0deg .. 45deg\n"
                    "param shift = (1, -0.5)\n"
                    "/* ink */ param ink = #00ff80\n"
                    "param dense = false\n"
                    "param still = 3\n"
                    "layer a { family = circles; spacing = 4 + drift; rotation = turn }\n");
    // `still` was set to the value the file already says: not an edit.
    CHECK(w.written == std::vector<std::string>{"drift", "turn", "shift", "ink", "dense"});
    CHECK(w.skipped.empty());

    // Nothing set: the text byte for byte.
    ParamWriteBack none = writeBackParameters(source, 0, params, ParamSet(params.size()));
    CHECK(none.text == source);
    CHECK(none.written.empty());
}

TEST_CASE("param write-back: a default written as an expression is kept, and said") {
    const std::string source = "param speed = 2\n"
                               "param sway = 0.5 * speed in 0 .. 10\n"
                               "param ink = rgb(1, 0.5, 0)\n";
    const std::vector<Parameter> params = {
        declared(source, "speed", ast::Type::Num, "2"),
        declared(source, "sway", ast::Type::Num, "0.5 * speed"),
        declared(source, "ink", ast::Type::Color, "rgb(1, 0.5, 0)")};
    ParamSet set = {ParamValue{3, 0, 0, 0}, ParamValue{4, 0, 0, 0}, ParamValue{0, 0, 1, 1}};
    ParamWriteBack w = writeBackParameters(source, 0, params, set);
    CHECK(w.text == "param speed = 3\n"
                    "param sway = 0.5 * speed in 0 .. 10\n"
                    "param ink = rgb(1, 0.5, 0)\n");
    CHECK(w.written == std::vector<std::string>{"speed"});
    REQUIRE(w.skipped.size() == 2);
    CHECK(w.skipped[0] == "sway: its default is an expression (0.5 * speed); the file keeps it");
    CHECK(w.skipped[1].rfind("ink: its default is an expression", 0) == 0);

    // A default from another file (`-D`'s command line) is not this file's to edit.
    ParamWriteBack other = writeBackParameters(source, 1, params, set);
    CHECK(other.text == source);
    REQUIRE(other.skipped.size() == 3);
    CHECK(other.skipped[0] == "speed: its value comes from -D on the command line");
}

TEST_CASE("param write-back: edits of different lengths keep each other's places") {
    // The first value grows and the second shrinks: both land where their defaults were.
    const std::string source = "param a = 1 in 0 .. 1000\nparam b = 123.456\nparam c = 7\n";
    const std::vector<Parameter> params = {declared(source, "a", ast::Type::Num, "1"),
                                           declared(source, "b", ast::Type::Num, "123.456"),
                                           declared(source, "c", ast::Type::Num, "7")};
    ParamSet set = {ParamValue{999.125, 0, 0, 0}, ParamValue{-2, 0, 0, 0},
                    ParamValue{0.1, 0, 0, 0}};
    CHECK(writeBackParameters(source, 0, params, set).text ==
          "param a = 999.125 in 0 .. 1000\nparam b = -2\nparam c = 0.1\n");
}
