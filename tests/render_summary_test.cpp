// `moire render`'s summary line says where the time went: compiling, rendering, and encoding
// and writing the file. The parts are measured apart from the whole, so they are held to it:
// each at most the whole, and together the whole within rounding.
#include "tests/support/Support.h"

#include <cstdlib>
#include <doctest/doctest.h>
#include <regex>
#include <string>

using namespace moire;

TEST_CASE("render's summary line splits the time into compile, render, and encode and write") {
    test::TempDir d("render_summary");
    d.write("s.moire", "scene { size = (160, 120) }\nlayer { family = circles; spacing = 4 }\n");
    for (const char* format : {"png", "tif", "exr"}) {
        CAPTURE(format);
        test::CommandResult r =
            test::runCommand("cd '" + d.path() + "' && '" + test::moireBinary() +
                             "' render s.moire -o out." + format);
        REQUIRE(r.status == 0);
        std::smatch m;
        std::regex line(R"(moire: wrote out\.\w+ \(160x120, [^,]+, (\d+) ms: compile (\d+), )"
                        R"(render (\d+), encode and write (\d+)\)\n)");
        REQUIRE_MESSAGE(std::regex_search(r.err, m, line), r.err);
        long total = std::stol(m[1]), compile = std::stol(m[2]), render = std::stol(m[3]),
             write = std::stol(m[4]);
        CHECK(compile <= total);
        CHECK(render <= total);
        CHECK(write <= total);
        // Each part is rounded on its own: the sum may be off the whole by one per part.
        CHECK(std::labs(compile + render + write - total) <= 2);
    }
    // -q says nothing.
    test::CommandResult q = test::runCommand("cd '" + d.path() + "' && '" + test::moireBinary() +
                                             "' render -q s.moire -o quiet.png");
    CHECK(q.status == 0);
    CHECK(q.err.empty());
}
