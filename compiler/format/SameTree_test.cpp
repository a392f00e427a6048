// The formatter's comparison of two parsed modules: equal when only the layout differs,
// unequal for any change of meaning, and a long chain compared without recursion.
#include "compiler/format/SameTree.h"
#include "compiler/parse/Parser.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {
ast::Module parse(const std::string& text) {
    SourceManager sm;
    uint32_t id = sm.add("t.moire", text);
    DiagEngine diags(sm);
    ast::Module m = Parser(sm, id, diags).parseModule();
    INFO(diags.render());
    REQUIRE_FALSE(diags.hasErrors());
    return m;
}

bool same(const std::string& a, const std::string& b) {
    return format::sameModule(parse(a), parse(b));
}

const char* kScene = "field f = -x^2 + max(1, y) * (x, y)\n"
                     "family g(a = 2, b) { let w = a * 2; phase = r - w }\n"
                     "layer l { family = g; b = 3deg; color = #102030 }\n";
} // namespace

TEST_CASE("format same tree: a file and its relaid self are the same") {
    CHECK(same(kScene, kScene));
    CHECK(same(kScene, "field f=-x ^ 2+max( 1,y )*( x,y )\n\n"
                       "family g( a=2,b ){\nlet w=a*2\nphase=r-w}\n"
                       "layer l {family=g,b=3deg;color=#102030}"));
    // Parentheses that group as the grammar would anyway are not in the tree.
    CHECK(same("field f = (a * b) + c", "field f = a * b + c"));
}

TEST_CASE("format same tree: any change of meaning is a difference") {
    const std::string base = "field f = a - 2 * x\nlayer { family = circles; color = #102030 }";
    CHECK_FALSE(same(base, "field f = a + 2 * x\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 3 * x\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 2deg * x\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = (a - 2) * x\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 2 * y\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 2 * x\nlayer { family = circles; color = #102031 }"));
    CHECK_FALSE(same(base, "field f = a - 2 * x\nlayer { family = squares; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 2 * x\nlayer a { family = circles; color = #102030 }"));
    CHECK_FALSE(same(base, "field f = a - 2 * x\nlayer { family = circles }"));
    CHECK_FALSE(same(base, "field f = -(a - 2 * x)\nlayer { family = circles; color = #102030 }"));
    CHECK_FALSE(same("family g(a = 1) = r", "family g(a) = r"));
    CHECK_FALSE(same("family g { let w = 1; phase = r }", "family g { let v = 1; phase = r }"));
}

TEST_CASE("format same tree: a chain of a hundred thousand terms is compared in a loop") {
    std::string chain = "field f = x";
    for (int i = 0; i < 100000; ++i) chain += " + x";
    CHECK(same(chain, chain));
    CHECK_FALSE(same(chain, chain + " + x"));
}
