// Values the renderers cannot draw are errors located at the value (docs/language.md, "Values
// the renderers draw"). They used to pass: a stroke of 1e308, a turn of 1e308deg, a zoom of
// 1e-30 or a scene size of 9e30 under --size are finite in double but overflow the float
// that the JIT and Vulkan compute in, which then drew another picture than the interpreter;
// a spacing of 0 or 1e-30 drew solid ink, a stroke of 0 or less the thinnest line, and an
// opacity of 2 or 2.5 sides passed `moire check`. Every value is checked when the frame is
// computed, since it may be an expression in t.
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>

using namespace moire;

namespace {

// `marked` has one '@' just before the value that must be reported. Returns the diagnostics
// of the frame at `time` (at `width` x `height` when given), which must fail, after checking
// that the first error is located at the mark and says `says`.
std::string frameError(const std::string& marked, const std::string& says, double time = 0.0,
                       int width = 0, int height = 0) {
    const size_t at = marked.find('@');
    REQUIRE(at != std::string::npos);
    std::string text = marked;
    text.erase(at, 1);
    const size_t lineStart = text.rfind('\n', at == 0 ? 0 : at - 1);
    const size_t col = lineStart == std::string::npos ? at + 1 : at - lineStart;
    size_t line = 1;
    for (size_t i = 0; i < at; ++i) line += text[i] == '\n';
    CAPTURE(text);
    auto program = test::compileOk(text);
    FrameRequest req;
    req.time = time;
    req.width = width;
    req.height = height;
    FrameValues fv;
    std::string diags;
    CHECK_FALSE(evaluateFrame(*program, req, fv, diags));
    const std::string where = fmt::format("test.moire:{}:{}: error: ", line, col);
    CAPTURE(diags);
    CHECK(diags.rfind(where, 0) == 0);
    CHECK(diags.find(says) != std::string::npos);
    return diags;
}

bool frameOk(const std::string& text, double time = 0.0) {
    auto program = test::compileOk(text);
    FrameRequest req;
    req.time = time;
    FrameValues fv;
    std::string diags;
    const bool ok = evaluateFrame(*program, req, fv, diags);
    INFO(diags);
    return ok;
}

} // namespace

TEST_CASE("value limits: values that overflow float are located errors") {
    frameError("layer { family = circles; stroke = @1e308 }",
               "'stroke' must be more than 0 and at most 1e12");
    frameError("layer { family = squares; offset = (1, 0); turn = @1e308deg }",
               "'turn' must be between -1e12 and 1e12 radians, not 1.74533e+306rad");
    frameError("camera { zoom = @1e-30 }\nlayer { family = circles }",
               "'zoom' must be from 1e-6 to 1e6, not 1e-30");
    frameError("camera { zoom = @1e30 }\nlayer { family = circles }", "'zoom' must be");
    frameError("layer { family = circles; origin = (0, @-1e300) }",
               "'origin' must be between -1e12 and 1e12");
    frameError("camera { center = @(1e300, 0) }\nlayer { family = circles }", "'center' must be");
    frameError("layer { family = wave; amplitude = @1e300 }", "'amplitude' must be");
    frameError("layer { family = lines; phase = @1e40 }", "'phase' must be");
    frameError("layer { family = lines; spacing = @1e40 }", "'spacing' must be from 1e-6 to 1e12");
}

TEST_CASE("value limits: the scene's own size is checked when --size replaces it") {
    // The scene's size frames the picture (one pixel is max(scene w / w, scene h / h) / zoom
    // world units), so a size of 9e30 reached the kernel through the pixel size.
    frameError("scene { size = @(9e30, 800) }\nlayer { family = circles }",
               "image size must be whole numbers", 0.0, 64, 48);
    frameError("scene { size = @(640.5, 480) }\nlayer { family = circles }",
               "image size must be whole numbers", 0.0, 64, 48);
    CHECK(frameOk("scene { size = (640, 480) }\nlayer { family = circles }"));
}

TEST_CASE("value limits: spacing, stroke, opacity and sides out of their ranges") {
    for (const char* spacing : {"0", "-4", "1e-30", "-1e-30"})
        frameError(fmt::format("layer {{ family = circles; spacing = @{} }}", spacing),
                   "'spacing' must be from 1e-6 to 1e12");
    for (const char* stroke : {"0", "-2", "-1e-9"})
        frameError(fmt::format("layer {{ family = lines; stroke = @{} }}", stroke),
                   "'stroke' must be more than 0 and at most 1e12 (to hide a layer, set its "
                   "opacity to 0)");
    for (const char* opacity : {"2", "-0.5", "1.0001"})
        frameError(fmt::format("layer {{ family = lines; opacity = @{} }}", opacity),
                   "'opacity' must be from 0 to 1");
    for (const char* sides : {"2.5", "2", "0", "-5", "3.0001"})
        frameError(fmt::format("layer {{ family = ngon; sides = @{} }}", sides),
                   "'sides' must be a whole number of sides, 3 or more");
    // In a morph, the member that takes the parameter is checked.
    frameError("timing m { period = 4 }\nlayer { family = morph(m, circles, ngon); sides = @2.5 }",
               "'sides' must be");
    // The edges of the ranges are allowed.
    CHECK(frameOk("layer { family = circles; spacing = 1e-6; stroke = 1e12; opacity = 0 }"));
    CHECK(frameOk("layer { family = ngon; sides = 3; spacing = 1e12; opacity = 1 }"));
    CHECK(frameOk("camera { zoom = 1e-6 }\nlayer { family = circles; origin = (1e12, -1e12) }"));
    CHECK(frameOk("camera { zoom = 1e6 }\nlayer { family = squares; offset = (1, 0); turn = "
                  "1e12rad }"));
}

TEST_CASE("value limits: a value that moves with t is checked at every frame, located") {
    // Fine at t = 0, out of range from t = 4 on.
    const std::string marked = "layer { family = circles; spacing = @8 - 2 * t }";
    std::string text = marked;
    text.erase(text.find('@'), 1);
    CHECK(frameOk(text, 0.0));
    CHECK(frameOk(text, 3.9));
    frameError(marked, "'spacing' must be from 1e-6 to 1e12, not -2", 5.0);
    frameError("timing s { period = 2 }\nlayer { family = lines; opacity = @ramp(s, 0, 3) }",
               "'opacity' must be from 0 to 1", 1.5);
}

TEST_CASE("value limits: a value that depends on the position is not checked per frame") {
    // It has no one value per frame; the kernel still draws it (and must not crash the split).
    CHECK(frameOk("layer { family = circles; stroke = 1 + x / 1000; spacing = 6 + y / 100 }"));
    CHECK(frameOk("layer { family = ngon; sides = 5 + floor(x / 1000) }"));
}

TEST_CASE("value limits: `moire check` and `moire render` report them and write nothing") {
    test::TempDir dir("value_limits");
    dir.write("bad.moire", "layer { family = circles\n  stroke = -2 }\n");
    test::CommandResult check =
        test::runCommand(test::moireBinary() + " check " + dir.file("bad.moire"));
    CHECK(check.status == 1);
    CHECK(check.err.find("bad.moire:2:12: error: 'stroke' must be more than 0") !=
          std::string::npos);
    dir.write("huge.moire", "scene { size = (9e30, 800) }\nlayer { family = circles }\n");
    test::CommandResult render =
        test::runCommand(test::moireBinary() + " render " + dir.file("huge.moire") + " -o " +
                         dir.file("out.png") + " --size 64x48 --backend interp");
    CAPTURE(render.err);
    CHECK(render.status != 0);
    CHECK(render.err.find("huge.moire:1:16: error: image size must be whole numbers") !=
          std::string::npos);
    CHECK(dir.names() == std::vector<std::string>{"bad.moire", "huge.moire"});
}
