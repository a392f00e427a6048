// The viewer's overlay: which lines of a diagnostic make the error box, and where the status
// line and the box are drawn.
#include "compiler/Compile.h"
#include "runtime/view/Overlay.h"

#include <doctest/doctest.h>
#include <regex>
#include <vector>

using namespace moire::view;

TEST_CASE("overlay: the error box shows each diagnostic whole: headline, source and caret") {
    const std::string diags = "s.moire:2:23: error: expected an expression, found '}'\n"
                              "    2 | layer b { spacing = 5 + }\n"
                              "      |                       ^\n"
                              "s.moire:3:1: error: unknown family 'circels'\n"
                              "    3 | layer { family = circels }\n"
                              "s.moire:3:1: note: did you mean 'circles'?\n";
    std::vector<std::string> lines = errorLines(diags);
    REQUIRE(lines.size() == 6);
    CHECK(lines[0] == "s.moire:2:23: error: expected an expression, found '}'");
    CHECK(lines[1] == "    2 | layer b { spacing = 5 + }");
    CHECK(lines[2] == "      |                       ^");
    CHECK(lines[5] == "s.moire:3:1: note: did you mean 'circles'?");
    // Capped by whole diagnostics, saying how many more there were.
    lines = errorLines(diags, 5);
    REQUIRE(lines.size() == 4);
    CHECK(lines[2] == "      |                       ^");
    CHECK(lines[3] == "(and 2 more)");
    // A first diagnostic longer than the box is cut, never dropped.
    lines = errorLines(diags, 2);
    REQUIRE(lines.size() == 2);
    CHECK(lines[0] == "s.moire:2:23: error: expected an expression, found '}'");
    CHECK(lines[1] == "(and 2 more)");
    // Something that is not a diagnostic (a backend's failure) is shown as it is.
    lines = errorLines("moire: error: device lost\n");
    REQUIRE(lines.size() == 1);
    CHECK(lines[0] == "moire: error: device lost");
    CHECK(errorLines("").empty());
}

TEST_CASE("overlay: a compiler diagnostic's caret stands under the column it names") {
    // The compiler's own rendering, not a copy of it: the box shows what the terminal shows.
    const char* scene = "scene { size = (64, 64) }\nlayer a { family = circles; spacing = 6 + }\n";
    moire::CompileResult r = moire::compileScene("s.moire", scene);
    REQUIRE(!r.program);
    std::vector<std::string> lines = errorLines(r.diagnostics);
    REQUIRE(lines.size() >= 3);
    std::smatch m;
    REQUIRE(std::regex_match(lines[0], m, std::regex(R"(s\.moire:2:(\d+): error: .*)")));
    const size_t column = std::stoul(m[1]);
    CHECK(lines[1].find("layer a { family = circles; spacing = 6 + }") != std::string::npos);
    // The source text starts after "NNNN | "; the caret's offset past the bar is the column.
    const size_t bar = lines[1].find(" | ");
    REQUIRE(bar != std::string::npos);
    REQUIRE(lines[2].size() > bar + 3);
    CHECK(lines[2].substr(0, bar + 3).find('|') == bar + 1);
    CHECK(lines[2].find('^') == bar + 3 + column - 1);
}

TEST_CASE("overlay: the status line sits along the bottom, the error box along the top") {
    const int w = 200, h = 100;
    std::vector<uint8_t> px(w * h * 4, 255);
    Canvas canvas{px.data(), w, h};
    OverlayText text;
    text.status = "t=1.000  paused";
    text.errorLines = {"a.moire:1:1: error: something"};
    drawOverlay(canvas, text, 1);
    auto pixel = [&](int x, int y) { return &px[(y * w + x) * 4]; };
    // Darkened behind the status line, reddened behind the errors, untouched between.
    CHECK(pixel(w - 1, h - 1)[0] < 100);
    CHECK(pixel(w - 1, 1)[0] > pixel(w - 1, 1)[2] + 20);
    CHECK(pixel(w / 2, h / 2)[0] == 255);
    CHECK(h - statusHeight(1) > 20);
    // A line too long for the window is cut, not drawn past its edge.
    text.status = std::string(500, 'x');
    drawOverlay(canvas, text, 2);
}
