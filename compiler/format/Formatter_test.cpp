// `moire fmt`'s layout, case by case against layouts written out by hand (docs/formatting.md),
// each one also formatted a second time to show that formatting twice changes nothing.
#include "compiler/Compile.h"
#include "compiler/format/Formatter.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;
using moire::format::formatSource;

namespace {
std::string formatted(const std::string& text, const std::string& name = "t.moire") {
    format::FormatResult r = formatSource(name, text);
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    CHECK(r.diagnostics.empty());
    format::FormatResult again = formatSource(name, r.text);
    REQUIRE(again.ok);
    CHECK(again.text == r.text);
    return r.text;
}
} // namespace

TEST_CASE("fmt: one property a line, four spaces, spaces about '=' and the operators") {
    CHECK(formatted("scene{size=(1200,800)\nbackground=#f6f3ec}") ==
          "scene {\n    size = (1200, 800)\n    background = #f6f3ec\n}\n");
    CHECK(formatted("field  f=2*x+y/3-4") == "field f = 2 * x + y / 3 - 4\n");
}

TEST_CASE("fmt: signs, powers and calls are written tight") {
    CHECK(formatted("field f = - x ^ 2 + max( - 1 , + y ) * (x , y) ^ - 2") ==
          "field f = -x^2 + max(-1, +y) * (x, y)^-2\n");
    CHECK(formatted("field f = 2 - - x") == "field f = 2 - -x\n");
}

TEST_CASE("fmt: numbers, units and colours are kept as written") {
    CHECK(formatted("field f = 1.50e+2 + 30deg + 1rad\nscene { background = #FfFf00aa }") ==
          "field f = 1.50e+2 + 30deg + 1rad\nscene { background = #FfFf00aa }\n");
}

TEST_CASE("fmt: a block written on one line stays on one line, semicolons between properties") {
    CHECK(formatted("layer a {family=circles , spacing=6}") ==
          "layer a { family = circles; spacing = 6 }\n");
    CHECK(formatted("timing t { period = 12; mode = loop; }") ==
          "timing t { period = 12; mode = loop }\n");
    CHECK(formatted("family f { let a = 2; phase = r * a }") ==
          "family f { let a = 2; phase = r * a }\n");
}

TEST_CASE("fmt: a block on one line past 100 columns is split, one property a line") {
    std::string props = "family = circles; spacing = 8; offset = (1.2, 0.5); turn = 1.0deg";
    std::string fits = "layer { " + props + "; stroke = 1.5 }"; // 89 columns
    CHECK(formatted(fits) == fits + "\n");
    std::string wide = "layer wide { " + props + "; stroke = 1.5; sides = 9; gain = 1 }"; // 115
    CHECK(formatted(wide) == "layer wide {\n    family = circles\n    spacing = 8\n"
                             "    offset = (1.2, 0.5)\n    turn = 1.0deg\n    stroke = 1.5\n"
                             "    sides = 9\n    gain = 1\n}\n");
    // Exactly 100 columns is kept.
    std::string hundred = "layer { family = circles; spacing = 8; offset = (1.2, 0.5); "
                          "turn = 1.0deg; stroke = 1.5; gain = 12 }";
    REQUIRE(hundred.size() == 100);
    CHECK(formatted(hundred) == hundred + "\n");
    CHECK(formatted("layer { family = circles; spacing = 8; offset = (1.2, 0.5); "
                    "turn = 1.0deg; stroke = 1.5; gain = 123 }")
              .find("{\n") != std::string::npos);
}

TEST_CASE("fmt: a block written on several lines stays on several, an empty one is {}") {
    CHECK(formatted("camera {\nzoom = 1.2 }") == "camera {\n    zoom = 1.2\n}\n");
    CHECK(formatted("scene {\n\n}\ncamera{ }") == "scene {}\ncamera {}\n");
}

TEST_CASE("fmt: blank lines between declarations and properties are kept, runs collapsed") {
    CHECK(formatted("\n\nfield a = 1\n\n\n\nfield b = 2\nfield c = 3\n\n\n") ==
          "field a = 1\n\nfield b = 2\nfield c = 3\n");
    CHECK(formatted("layer {\n\n  family = circles\n\n\n  spacing = 6\n\n}") ==
          "layer {\n    family = circles\n\n    spacing = 6\n}\n");
}

TEST_CASE("fmt: separators after a property on its own line are dropped") {
    CHECK(formatted("field a = 1;\nlayer {\nfamily = circles;\nspacing = 6,\n}") ==
          "field a = 1\nlayer {\n    family = circles\n    spacing = 6\n}\n");
}

TEST_CASE("fmt: families: parameters, lets, the phase shorthand") {
    CHECK(formatted("family bent ( bowl=0.0006 ,b ) {\nlet w=1\nphase = y+bowl*w }") ==
          "family bent(bowl = 0.0006, b) {\n    let w = 1\n    phase = y + bowl * w\n}\n");
    CHECK(formatted("family f()=r;") == "family f() = r\n");
}

TEST_CASE("fmt: a file in a folder named stdlib may declare builtin families") {
    const std::string text = "builtin family hex_lattice ( scale=(1,1), edges=0 )\n";
    CHECK(formatted(text, "stdlib/families.moire") ==
          "builtin family hex_lattice(scale = (1, 1), edges = 0)\n");
    CHECK_FALSE(formatSource("scenes/families.moire", text).ok);
}

TEST_CASE("fmt: line breaks written inside a value are kept, continuation lines aligned") {
    // Outside parentheses a continuation lines up with the value, an operator that begins
    // it standing to the left; inside parentheses, with what follows the '('.
    CHECK(formatted("field bumps = 6 * a\n+ 4 * b\n  - 5 * c") ==
          "field bumps = 6 * a\n            + 4 * b\n            - 5 * c\n");
    CHECK(formatted("field s = 2 * (log(a) - log(b)\n+ log(c))") ==
          "field s = 2 * (log(a) - log(b)\n             + log(c))\n");
    CHECK(formatted("field p = max(a,\nb)") == "field p = max(a,\n              b)\n");
    // A '(' that ends its line: the next lines one step in, the ')' back with its line.
    CHECK(formatted("field p = max(\na,\nb\n)") == "field p = max(\n    a,\n    b\n)\n");
    // A break right after '=': the value on the next line, one step in.
    CHECK(formatted("layer {\nspacing =\n  6 + x\n}") ==
          "layer {\n    spacing =\n        6 + x\n}\n");
}

TEST_CASE("fmt: line breaks outside values are not kept") {
    CHECK(formatted("layer\nname\n{ family\n=\ncircles }") ==
          "layer name {\n    family =\n        circles\n}\n");
    CHECK(formatted("family f(a = 1,\nb = 2) = r") == "family f(a = 1,\n         b = 2) = r\n");
}

TEST_CASE("fmt: comments on their own line stay on their own line, at the indentation") {
    CHECK(formatted("// head\n\n// about a\nfield a = 1\n  // about b\nfield b = 2") ==
          "// head\n\n// about a\nfield a = 1\n// about b\nfield b = 2\n");
    CHECK(formatted("layer {\n      // first\n  family = circles\n// last\n}") ==
          "layer {\n    // first\n    family = circles\n    // last\n}\n");
}

TEST_CASE("fmt: a comment after code stays at the end of its line") {
    CHECK(formatted("layer { // the figure\nfamily = circles;   // rings\nspacing = 6 } // end") ==
          "layer { // the figure\n    family = circles // rings\n    spacing = 6\n} // end\n");
    CHECK(formatted("field a = 1 // one   \r\nfield b = 2") == "field a = 1 // one\nfield b = 2\n");
}

TEST_CASE("fmt: a comment inside a value keeps its place, a line comment ends the line") {
    CHECK(formatted("field f = a + /* why */ b") == "field f = a + /* why */ b\n");
    CHECK(formatted("field f = a + // why\n b") == "field f = a + // why\n          b\n");
    CHECK(formatted("family f {\nphase = max(a, // first\n b)\n}") ==
          "family f {\n    phase = max(a, // first\n                b)\n}\n");
}

TEST_CASE("fmt: a block with a comment inside is never kept on one line") {
    CHECK(formatted("layer { family = circles /* rings */; spacing = 6 }") ==
          "layer {\n    family = circles /* rings */\n    spacing = 6\n}\n");
    CHECK(formatted("scene {\n/* nothing yet */ }") == "scene {\n    /* nothing yet */\n}\n");
    CHECK(formatted("scene { /* nothing yet */ }") == "scene { /* nothing yet */\n}\n");
}

TEST_CASE("fmt: block comments spanning lines are kept as written") {
    const std::string text = "/* A scene.\n *   indented inside\n */\nfield a = 1\n";
    CHECK(formatted(text) == text);
    CHECK(formatted("field a = 1 /* x\n   y */ + 2") == "field a = 1 /* x\n   y */ + 2\n");
}

TEST_CASE("fmt: comments before the end of the file, and files of comments only") {
    CHECK(formatted("field a = 1\n\n\n// the end\n") == "field a = 1\n\n// the end\n");
    CHECK(formatted("// only a comment") == "// only a comment\n");
    CHECK(formatted("") == "");
    CHECK(formatted(" \n\n\t\n") == "");
}

TEST_CASE("fmt: a byte-order mark and CRLF line ends give a plain LF file") {
    CHECK(formatted("\xEF\xBB\xBF"
                    "field a = 1\r\n\r\n\r\nfield b = 2\r\n") == "field a = 1\n\nfield b = 2\n");
}

TEST_CASE("fmt: a file that does not parse is not formatted, and says what moire check says") {
    const std::string text = "layer {\n    family = circles\n    spacing = (6\n}\n";
    format::FormatResult r = formatSource("bad.moire", text);
    CHECK_FALSE(r.ok);
    CHECK(r.text.empty());
    CompileResult checked = compileScene("bad.moire", text);
    REQUIRE_FALSE(checked.diagnostics.empty());
    CHECK(r.diagnostics == checked.diagnostics);
    CHECK(r.diagnostics.find("bad.moire:4:1: error:") != std::string::npos);
}

TEST_CASE("fmt: a scene with errors past parsing is still formatted") {
    // An unknown family is the checks' to report, not the formatter's.
    CHECK(formatted("layer{family=circels}") == "layer { family = circels }\n");
}

TEST_CASE("fmt: a chain of fifty thousand terms is formatted (no recursion, no quadratic check)") {
    std::string chain = "field f = x";
    for (int i = 0; i < 50000; ++i) chain += "+x";
    std::string expected = "field f = x";
    for (int i = 0; i < 50000; ++i) expected += " + x";
    CHECK(formatted(chain) == expected + "\n");
}
