// The compiler's limits: how long a chain of operators, how long a name and how deeply
// nested an expression may be, each checked against a value computed here independently or
// against the exact diagnostic, never against a timing.
#include "compiler/Compile.h"
#include "compiler/lex/Lexer.h"
#include "compiler/parse/Parser.h"
#include "runtime/FrameEval.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {

// `field f = t0 + t1 * a1 / b1 - t2 + ...` with `terms` terms, and its value summed here in
// double precision, left to right as the language reads it.
struct Chain {
    std::string text;
    double value = 0.0;
};

Chain chainOf(int terms) {
    Chain c;
    c.text = "field f = 5";
    c.value = 5;
    for (int i = 1; i < terms; ++i) {
        int a = i % 13, b = 1 + (i * 7) % 11, d = 1 + i % 4;
        switch (i % 3) {
        case 0:
            c.text += " + " + std::to_string(a);
            c.value += a;
            break;
        case 1:
            c.text += " - " + std::to_string(a) + " * " + std::to_string(b);
            c.value -= static_cast<double>(a) * b;
            break;
        default: // a product chain inside the sum: (a * b) / d
            c.text +=
                " + " + std::to_string(a) + " * " + std::to_string(b) + " / " + std::to_string(d);
            c.value += static_cast<double>(a) * b / d;
            break;
        }
    }
    return c;
}

// The camera centre's x, which the frame program computes from `f`.
double centreOf(const std::string& fieldText, std::string& diagnostics) {
    std::string scene = fieldText + "\ncamera { center = (f, 0) }\nlayer { family = circles }\n";
    CompileResult r = compileScene("chain.moire", scene);
    diagnostics = r.diagnostics;
    if (!r.program) return 0.0;
    FrameValues frame;
    FrameRequest request;
    if (!evaluateFrame(*r.program, request, frame, diagnostics)) return 0.0;
    return frame.centerX;
}

} // namespace

TEST_CASE("limits: a flat chain of operators is not nesting, however long") {
    // Before, each '+' counted as a level of nesting and 300 terms were "nested too deeply".
    // 10,000 levels of recursion down the chain would be near the end of a sanitizer build's
    // stack; every stage walks a chain in a loop. (100,000 terms work too, in a few seconds.)
    for (int terms : {300, 10000}) {
        CAPTURE(terms);
        Chain c = chainOf(terms);
        std::string diagnostics;
        double got = centreOf(c.text, diagnostics);
        CHECK(diagnostics.empty());
        CHECK(got == c.value);
    }
}

TEST_CASE("limits: a sum of 300 ones is 300") {
    std::string text = "field f = 1";
    for (int i = 1; i < 300; ++i) text += " + 1";
    std::string diagnostics;
    CHECK(centreOf(text, diagnostics) == 300.0);
    CHECK(diagnostics.empty());
}

TEST_CASE("limits: real nesting past the limit is still refused, once") {
    int over = Parser::kMaxDepth + 10;
    std::string nested = "field f = " + std::string(over, '(') + "1" + std::string(over, ')');
    std::string errors = test::compileErrors(nested + "\nlayer { family = circles }\n");
    CHECK(errors.find("error: this expression is nested too deeply (more than 256 levels)") !=
          std::string::npos);
    CHECK(errors.find("error:") == errors.rfind("error:")); // one error
    // A chain inside the nesting does not add to it.
    std::string inside = "field f = " + std::string(Parser::kMaxDepth - 1, '(') + "1";
    for (int i = 0; i < 1000; ++i) inside += " + 1";
    inside += std::string(Parser::kMaxDepth - 1, ')');
    std::string diagnostics;
    CHECK(centreOf(inside, diagnostics) == 1001.0);
    CHECK(diagnostics.empty());
}

TEST_CASE("limits: a name of a megabyte is one located error") {
    // The "did you mean" search compared it with every known name by a full edit-distance
    // table (a megabyte by each name's length); now the name is refused as it is read.
    const size_t length = 1 << 20;
    std::string text = "layer { family = circles; spacing = " + std::string(length, 'q') + " }\n";
    std::string errors = test::compileErrors(text);
    CHECK(errors.rfind("test.moire:1:37: error: this name is 1048576 characters long; names are "
                       "at most 256\n",
                       0) == 0);
    CHECK(errors.find("error:") == errors.rfind("error:")); // one error: no "unknown name" too
    // The longest name allowed is an ordinary name.
    std::string longest(Lexer::kMaxNameLength, 'w');
    std::string diagnostics;
    CHECK(centreOf("field " + longest + " = 2\nfield f = " + longest + " * 3", diagnostics) == 6.0);
    CHECK(diagnostics.empty());
}
