// `moire check` run as a user runs it, against the hand-written error catalogue: the same
// diagnostics on stderr as the compiler gives in-process (tests/errors_test.cpp), exit
// status 1 for a scene with errors, 0 and an "ok" line for a valid one, and one clear line
// for a file that cannot be read.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <unistd.h>

using namespace moire;
namespace fs = std::filesystem;

namespace {

// Runs `moire check <args>` from the source root, so that tests/errors/x.moire is named in
// the diagnostics exactly as the .expected files name it.
test::CommandResult check(const std::string& args) {
    return test::runCommand("cd '" + test::sourcePath("") + "' && '" + test::moireBinary() +
                            "' check " + args);
}

// A scene file in a fresh temporary directory, removed with this object.
struct TempScene : test::TempDir {
    std::string scene;
    explicit TempScene(const std::string& text)
        : test::TempDir("check"), scene(file("scene.moire")) {
        write("scene.moire", text);
    }
};

} // namespace

TEST_CASE("moire check: a scene with errors exits 1 with exactly the catalogue's diagnostics") {
    // One lexer case, one with a note, and one found only when the frame is evaluated.
    for (const char* name :
         {"unknown_unit", "duplicate_property", "bad_size", "unknown_property_family"}) {
        CAPTURE(name);
        std::string scene = std::string("tests/errors/") + name + ".moire";
        test::CommandResult r = check(scene);
        CHECK(r.status == 1);
        CHECK(r.err ==
              test::readFile(test::sourcePath(std::string("tests/errors/") + name + ".expected")));
        CHECK(r.out.empty()); // nothing claimed "ok"
    }
}

TEST_CASE("moire check: a valid scene exits 0 and says so") {
    TempScene scene("// two ring families\n"
                    "scene { size = (200, 100) }\n"
                    "layer { family = circles; spacing = 6; origin = (-10, 0) }\n"
                    "layer { family = circles; spacing = 6; origin = (10, 0) }\n");
    test::CommandResult r = check("'" + scene.scene + "'");
    CHECK(r.status == 0);
    CHECK(r.out == scene.scene + ": ok\n");
    CHECK(r.err.empty());
    // --quiet keeps only errors.
    test::CommandResult quiet = check("-q '" + scene.scene + "'");
    CHECK(quiet.status == 0);
    CHECK(quiet.out.empty());
    CHECK(quiet.err.empty());
}

TEST_CASE("moire check: several scenes are all checked, and any error makes the status 1") {
    TempScene good("layer { family = circles }\n");
    test::CommandResult r =
        check("'" + good.scene + "' tests/errors/missing_family.moire '" + good.scene + "'");
    CHECK(r.status == 1);
    CHECK(r.out == good.scene + ": ok\n" + good.scene + ": ok\n");
    CHECK(r.err == test::readFile(test::sourcePath("tests/errors/missing_family.expected")));
}

TEST_CASE("moire check: a file that cannot be read is one clear line, and status 3") {
    std::string missing = "/nonexistent-moire-dir/none.moire";
    test::CommandResult r = check(missing);
    CHECK(r.status == 3);
    CHECK(r.err == "moire: error: cannot read '" + missing + "': No such file or directory\n");
    CHECK(r.out.empty());
    TempScene scene("layer { family = circles }\n");
    std::string dirPath = scene.path();
    test::CommandResult dir = check(fmt::format("'{}'", dirPath));
    CHECK(dir.status == 3);
    CHECK(dir.err == fmt::format("moire: error: cannot read '{}': it is a directory\n", dirPath));
}
