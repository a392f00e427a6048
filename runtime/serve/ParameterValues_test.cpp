// The sliders' values read from JSON and checked against the declaration, and the list the
// page builds its sliders from.
#include "runtime/serve/ParameterValues.h"
#include "runtime/serve/Session.h"

#include <cmath>
#include <doctest/doctest.h>

namespace moire::serve {
namespace {

using json = nlohmann::json;

Parameter declared(const char* name, ast::Type type, int components,
                   std::optional<double> min = std::nullopt,
                   std::optional<double> max = std::nullopt) {
    Parameter p;
    p.name = name;
    p.type = type;
    p.components = components;
    p.min = min;
    p.max = max;
    return p;
}

std::string refusal(const Parameter& p, const json& value) {
    try {
        parameterValueFromJson(p, value);
    } catch (const RequestError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("serve parameters: each type's value from JSON") {
    const Parameter drift = declared("drift", ast::Type::Num, 1, 0.0, 5.0);
    CHECK(parameterValueFromJson(drift, 1.5) == std::vector<double>{1.5});
    CHECK(parameterValueFromJson(drift, json::array({0})) == std::vector<double>{0.0});

    const Parameter turn = declared("turn", ast::Type::Angle, 1, 0.0, M_PI / 4);
    CHECK(parameterValueFromJson(turn, 0.5) == std::vector<double>{0.5});

    const Parameter at = declared("at", ast::Type::Vec2, 2, -10.0, 10.0);
    CHECK(parameterValueFromJson(at, json::array({1, -2.5})) == std::vector<double>{1, -2.5});

    const Parameter ink = declared("ink", ast::Type::Color, 4);
    std::vector<double> c = parameterValueFromJson(ink, "#ff8000");
    REQUIRE(c.size() == 4);
    CHECK(c[0] == 1.0);
    CHECK(c[1] == doctest::Approx(128.0 / 255.0));
    CHECK(c[2] == 0.0);
    CHECK(c[3] == 1.0);
    CHECK(parameterValueFromJson(ink, "#FF800080")[3] == doctest::Approx(128.0 / 255.0));
    CHECK(parameterValueFromJson(ink, json::array({0.1, 0.2, 0.3})) ==
          std::vector<double>{0.1, 0.2, 0.3, 1.0});

    const Parameter on = declared("on", ast::Type::Bool, 1);
    CHECK(parameterValueFromJson(on, true) == std::vector<double>{1.0});
    CHECK(parameterValueFromJson(on, false) == std::vector<double>{0.0});
}

TEST_CASE("serve parameters: values of the wrong shape or out of range are refused") {
    const Parameter drift = declared("drift", ast::Type::Num, 1, 0.0, 5.0);
    CHECK(refusal(drift, 7.0) ==
          "param 'drift' must be from 0 to 5, not 7"); // checkParameterValue's
    CHECK(refusal(drift, -0.5) != "");
    CHECK(refusal(drift, true).find("no true or false") != std::string::npos);
    CHECK(refusal(drift, "#ffffff").find("no text") != std::string::npos);
    CHECK(refusal(drift, json::array({1, 2})).find("1 component, not 2") != std::string::npos);
    CHECK(refusal(drift, json::object()) != "");
    CHECK(refusal(drift, json::array({"a"})).find("must be numbers") != std::string::npos);

    const Parameter at = declared("at", ast::Type::Vec2, 2, -10.0, 10.0);
    CHECK(refusal(at, 3.0).find("2 components, not 1") != std::string::npos);
    CHECK(refusal(at, json::array({0, 11})) != "");

    const Parameter ink = declared("ink", ast::Type::Color, 4);
    CHECK(refusal(ink, "#ff80").find("#rrggbb") != std::string::npos);
    CHECK(refusal(ink, "#gg8000").find("#rrggbb") != std::string::npos);
    CHECK(refusal(ink, json::array({0.1, 0.2, 1.5, 1})) != ""); // a component above 1

    const Parameter on = declared("on", ast::Type::Bool, 1);
    CHECK(refusal(on, 0.5) != "");
}

TEST_CASE("serve parameters: the page's list") {
    Parameter turn = declared("turn", ast::Type::Angle, 1, 0.0, 1.0);
    turn.step = 0.01;
    turn.unit = Unit::Deg;
    json j = parameterJson(turn, {0.25}, true);
    CHECK(j["name"] == "turn");
    CHECK(j["type"] == "angle");
    CHECK(j["components"] == 1);
    CHECK(j["min"] == 0.0);
    CHECK(j["max"] == 1.0);
    CHECK(j["step"] == 0.01);
    CHECK(j["unit"] == "deg");
    CHECK(j["value"] == json::array({0.25}));
    CHECK(j["set"] == true);

    json c = parameterJson(declared("ink", ast::Type::Color, 4), {1, 0, 0, 1}, false);
    CHECK(c["type"] == "color");
    CHECK(c["min"].is_null());
    CHECK(c["unit"].is_null());
    CHECK(c["set"] == false);
    // A default that is not finite has no JSON number: null.
    json n = parameterJson(declared("x", ast::Type::Num, 1), {std::nan("")}, false);
    CHECK(n["value"][0].is_null());
}

} // namespace moire::serve
