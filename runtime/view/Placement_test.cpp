// The placement text `p` prints: pasted back into the scene it compiles, and the pasted scene
// draws what the viewer showed, with literal values combined into numbers and expressions
// (ramps of timings, functions of t) kept as the scene wrote them.
#include "compiler/backend/interp/Interpreter.h"
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"
#include "runtime/view/Placement.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>

using namespace moire;
using namespace moire::view;

namespace {

// A scene with a camera block and three layers whose placing properties are filled in.
std::string scene(const std::string& camera, const std::string& a, const std::string& b,
                  const std::string& c) {
    return "scene { size = (90, 60) }\n"
           "timing sway { period = 4; mode = pingpong; easing = sine }\n" +
           camera +
           "\n"
           "layer a { family = circles; spacing = 5; stroke = 1.2; " +
           a +
           " }\n"
           "layer b { family = squares; spacing = 6; stroke = 1.4; color = #202080; " +
           b +
           " }\n"
           "layer { family = lines; spacing = 4; stroke = 1; color = #802020; " +
           c + " }\n";
}

// The text between the braces of the block that starts with `head` in `placement`; empty
// when there is none.
std::string body(const std::string& placement, const std::string& head) {
    size_t at = placement.find(head + " {");
    if (at == std::string::npos) return {};
    size_t open = placement.find('{', at), close = placement.find('}', open);
    return placement.substr(open + 1, close - open - 1);
}

// The scene drawn by the interpreter with the view's adjustments in its literal slots.
Image drawAdjusted(const SceneProgram& program, const ViewAdjust& view, double t) {
    std::vector<double> literals = program.literals;
    view.write(literals, program.viewSlot, static_cast<int>(program.checked.layers.size()));
    FrameRequest req;
    req.time = t;
    req.literals = &literals;
    FrameValues fv;
    std::string diags;
    INFO(diags);
    REQUIRE(evaluateFrame(program, req, fv, diags));
    InterpBackend interp;
    return renderFrame(program, interp, fv);
}

Image drawPlain(const SceneProgram& program, double t) {
    InterpBackend interp;
    return test::renderScene(program, interp, 0, 0, t);
}

// Pastes the placement into the scene (the camera block whole, each moved layer's placing
// properties in place of its own) and checks that it draws what the adjusted view drew.
void checkPasted(const std::string& camera, const std::string& a, const std::string& b,
                 const std::string& c, const ViewAdjust& view, std::string& placement) {
    auto original =
        test::compileOk(scene(camera, a, b, c), {.mode = CompileOptions::Mode::Interactive});
    placement = placementText(*original, view);
    INFO("placement:\n", placement);
    std::string ba = body(placement, "layer a"), bb = body(placement, "layer b");
    std::string bc = body(placement, "layer"); // the unnamed one, when printed
    if (placement.find("layer {") == std::string::npos) bc.clear();
    // A moved layer's placing properties are replaced by the printed ones (both are printed).
    std::string pasted = scene("camera {" + body(placement, "camera") + "}", ba.empty() ? a : ba,
                               bb.empty() ? b : bb, bc.empty() ? c : bc);
    INFO("pasted scene:\n", pasted);
    auto back = test::compileOk(pasted);
    for (double t : {0.0, 1.3, 5.1}) {
        CAPTURE(t);
        test::ImageDiff d =
            test::compareImages(drawAdjusted(*original, view, t), drawPlain(*back, t), 1e-3);
        CHECK(d.maxAbs < 2e-3);
    }
}

} // namespace

TEST_CASE("placement: numbers") {
    CHECK(formatNumber(0) == "0");
    CHECK(formatNumber(-0.0) == "0");
    CHECK(formatNumber(-1e-12) == "0");
    CHECK(formatNumber(3.5) == "3.5");
    CHECK(formatNumber(-20) == "-20");
    CHECK(formatNumber(123.456789) == "123.4568");
    CHECK(formatNumber(0.0123456789) == "0.01234568");
    CHECK(formatNumber(1.0 / 3.0) == "0.3333333");
    CHECK(formatNumber(2.5e-5) == "2.5e-05");
    // What it prints, the lexer reads back.
    for (double v : {3.5, -20.0, 123.456789, 0.0123456789, 2.5e-5, 4.0e8}) {
        auto p = test::compileOk("camera { zoom = " + formatNumber(std::fabs(v)) +
                                 " }\n"
                                 "layer { family = circles }\n");
        CHECK(p->literals.at(0) == doctest::Approx(std::fabs(v)).epsilon(1e-6));
    }
}

TEST_CASE("placement: literal values are combined into numbers") {
    ViewAdjust view;
    view.panX = 2.5;
    view.panY = -1.25;
    view.zoomFactor = 1.6;
    view.layerRef(0) = {4.0, -3.0, 30 * std::numbers::pi / 180};
    view.layerRef(1) = {0.0, 0.0, -10 * std::numbers::pi / 180};
    std::string placement;
    checkPasted("camera { center = (3, -2); zoom = 1.5; rotation = 10deg }",
                "origin = (-10, 4); rotation = 15deg", "", "origin = (2, 0)", view, placement);
    CHECK(placement.find("camera { center = (5.5, -3.25); zoom = 2.4; rotation = 10deg; }") !=
          std::string::npos);
    // Rot(30deg) (-10, 4) + (4, -3), and 15deg + 30deg.
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    CHECK(body(placement, "layer a") == " origin = (" + formatNumber(c * -10 - s * 4 + 4) + ", " +
                                            formatNumber(s * -10 + c * 4 - 3) +
                                            "); rotation = 45deg ");
    CHECK(body(placement, "layer b") == " origin = (0, 0); rotation = -10deg ");
    CHECK(placement.find("layer {") == std::string::npos); // the third layer did not move
}

TEST_CASE("placement: with no camera block, and an unnamed layer") {
    ViewAdjust view;
    view.zoomFactor = 0.5;
    view.layerRef(2) = {1.0, 2.0, 0.0};
    std::string placement;
    checkPasted("", "", "", "", view, placement);
    CHECK(placement.find("camera { center = (0, 0); zoom = 0.5; }") != std::string::npos);
    CHECK(placement.find("layer { origin = (1, 2); rotation = 0deg }  // layer 3 (unnamed)") !=
          std::string::npos);
}

TEST_CASE("placement: expressions keep the scene's text, the offset added on top") {
    const std::string camera =
        "camera { center = ramp(sway, (0, 0), (10, 5)); zoom = 1 + 0.5 * progress(sway) }";
    const std::string a = "origin = ramp(sway, (-20, 0), (20, 0)); rotation = ramp(sway, 0deg, "
                          "30deg)";
    const std::string b = "origin = (5 * sin(tau * t / 4), 2) * 1.5";
    const std::string c = "origin = -(1, 1) * (1 + t) + (2, 0); rotation = t * 20deg";

    SUBCASE("moved only") {
        ViewAdjust view;
        view.panX = 3;
        view.zoomFactor = 2;
        view.layerRef(0) = {3.5, 0.0, 0.0};
        std::string placement;
        checkPasted(camera, a, b, c, view, placement);
        CHECK(placement.find("center = ramp(sway, (0, 0), (10, 5)) + (3, 0); zoom = (1 + 0.5 * "
                             "progress(sway)) * 2;") != std::string::npos);
        CHECK(body(placement, "layer a") ==
              " origin = ramp(sway, (-20, 0), (20, 0)) + (3.5, 0); rotation = ramp(sway, 0deg, "
              "30deg) ");
    }
    SUBCASE("moved and turned") {
        ViewAdjust view;
        view.layerRef(0) = {3.5, -1.0, 0.4};
        view.layerRef(1) = {-2.0, 1.0, -0.7};
        view.layerRef(2) = {0.0, 4.0, 1.1};
        std::string placement;
        checkPasted(camera, a, b, c, view, placement);
        // A ramp is affine in its ends, so the turn goes into them.
        CHECK(body(placement, "layer a").find(" origin = ramp(sway, (") == 0);
        CHECK(body(placement, "layer a").find("rotation = ramp(sway, 0deg, 30deg) + ") !=
              std::string::npos);
        CHECK(body(placement, "layer b").find("rotation = -40.10705deg") != std::string::npos);
    }
}

namespace {

// Writes the placement into the scene's text and checks that the result compiles to one
// scene that draws what the adjusted view drew, at several times.
std::string checkPlaced(const std::string& text, const ViewAdjust& view) {
    auto original = test::compileOk(text, {.mode = CompileOptions::Mode::Interactive});
    std::string placed, why;
    REQUIRE_MESSAGE(placedSource(*original, view, placed, why), why);
    INFO("placed scene:\n", placed);
    auto back = test::compileOk(placed);
    for (double t : {0.0, 1.3, 5.1}) {
        CAPTURE(t);
        test::ImageDiff d =
            test::compareImages(drawAdjusted(*original, view, t), drawPlain(*back, t), 1e-3);
        CHECK(d.maxAbs < 2e-3);
    }
    return placed;
}

} // namespace

TEST_CASE("placement: written into the scene's text, in place, the rest kept") {
    SUBCASE("literals and expressions replaced where the scene writes them") {
        const std::string text =
            scene("// the camera\ncamera { center = ramp(sway, (0, 0), (10, 5)); zoom = 1.5 }",
                  "origin = (-10, 4); rotation = 15deg /* kept */",
                  "origin = (5 * sin(tau * t / 4), 2)", "rotation = t * 20deg");
        ViewAdjust view;
        view.panX = 2;
        view.zoomFactor = 2;
        view.layerRef(0) = {4.0, -3.0, 30 * std::numbers::pi / 180};
        view.layerRef(1) = {1.0, 0.5, 0.0};
        view.layerRef(2) = {0.0, 2.0, 0.25};
        const std::string placed = checkPlaced(text, view);
        CHECK(placed.find("// the camera\ncamera { center = ramp(sway, (0, 0), (10, 5)) + (2, 0); "
                          "zoom = 3 }") != std::string::npos);
        CHECK(placed.find("rotation = 45deg /* kept */ }") != std::string::npos);
        CHECK(placed.find("origin = (5 * sin(tau * t / 4), 2) + (1, 0.5) }") != std::string::npos);
        // The unnamed layer had no origin: it is added at the start of its block.
        CHECK(placed.find("layer { origin = (0, 2); family = lines;") != std::string::npos);
        CHECK(placed.find("rotation = t * 20deg + 14.32394deg }") != std::string::npos);
        // Nothing else changed: the text before the camera and after the last layer.
        CHECK(placed.rfind(text.substr(0, text.find("// the camera")), 0) == 0);
    }
    SUBCASE("a camera block added when there is none, properties added where missing") {
        const std::string text = scene("", "", "rotation = 10deg", "");
        ViewAdjust view;
        view.panY = -3;
        view.layerRef(0) = {0.0, 0.0, 0.5};
        const std::string placed = checkPlaced(text, view);
        CHECK(placed.find("\ncamera { center = (0, -3); zoom = 1 }\nlayer a {") !=
              std::string::npos);
        // Both added to layer a, origin first.
        CHECK(placed.find("layer a { origin = (0, 0); rotation = 28.64789deg; family = circles") !=
              std::string::npos);
    }
    SUBCASE("no motion, no change") {
        const std::string text = scene("camera { zoom = 2 }", "", "", "");
        CHECK(checkPlaced(text, ViewAdjust{}) == text);
    }
    SUBCASE("an origin the language cannot turn is refused, saying why") {
        const std::string text = "scene { size = (90, 60) }\n"
                                 "field o = (3, 4)\n"
                                 "layer a { family = circles; origin = o }\n";
        auto program = test::compileOk(text, {.mode = CompileOptions::Mode::Interactive});
        ViewAdjust view;
        view.layerRef(0) = {1.0, 0.0, 0.3};
        std::string placed, why;
        CHECK(!placedSource(*program, view, placed, why));
        CHECK(why.find("the origin of layer 'a' is an expression that cannot be turned") == 0);
    }
}
