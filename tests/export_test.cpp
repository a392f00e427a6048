// `moire export` as a user runs it: where the page goes, what it says, and the exit statuses
// of the command-line conventions (docs/cli.md). What the page draws: tests/web/export.test.js.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>

namespace fs = std::filesystem;
using namespace moire;

namespace {

struct Workdir : test::TempDir {
    Workdir() : test::TempDir("export") {}
    test::CommandResult moire(const std::string& args) const {
        return test::runCommand("cd '" + path() + "' && '" + test::moireBinary() + "' " + args);
    }
};

const char* kScene = "scene { size = (64, 40) }\nlayer { family = circles; spacing = 4 }\n";

} // namespace

TEST_CASE("export writes <scene>.html at the scene's size, or --size, or where -o says") {
    Workdir w;
    w.write("rings.moire", kScene);
    test::CommandResult r = w.moire("export rings.moire");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("moire: wrote rings.html (64x40") != std::string::npos);
    std::string page = test::readFile(w.file("rings.html"));
    CHECK(page.rfind("<!doctype html>", 0) == 0);
    CHECK(page.find("<canvas id=\"picture\" width=\"64\" height=\"40\">") != std::string::npos);
    CHECK(page.find("#version 300 es") != std::string::npos);

    r = w.moire("export rings.moire --size 300x200 -o out/deeper/piece.html -q");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    CHECK(test::readFile(w.file("out/deeper/piece.html")).find("width=\"300\" height=\"200\"") !=
          std::string::npos);
    // The same scene gives the same page, byte for byte.
    REQUIRE(w.moire("export rings.moire -o again.html -q").status == 0);
    CHECK(test::readFile(w.file("again.html")) == page);
}

TEST_CASE("export - reads standard input, -o - writes the page to standard output") {
    Workdir w;
    w.write("s.moire", kScene);
    test::CommandResult r = w.moire("export - -o - < s.moire");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.out.rfind("<!doctype html>", 0) == 0);
    CHECK(r.out.find("<title>stdin</title>") != std::string::npos);
    CHECK(w.names() == std::vector<std::string>{"s.moire"});
}

TEST_CASE("export: a bad scene, a bad option, a file it cannot read or write: no page") {
    Workdir w;
    w.write("bad.moire", "layer { family = circles; spacing = }\n");
    w.write("s.moire", kScene);
    test::CommandResult r = w.moire("export bad.moire");
    CHECK(r.status == 1);
    CHECK(r.err.find("bad.moire:1:") != std::string::npos);

    r = w.moire("export s.moire --size 0x10");
    CHECK(r.status == 2);
    CHECK(r.err.find("--size must be WIDTHxHEIGHT") != std::string::npos);
    r = w.moire("export s.moire --time inf");
    CHECK(r.status == 2);
    r = w.moire("export s.moire --no-such-option");
    CHECK(r.status == 2);

    r = w.moire("export missing.moire");
    CHECK(r.status == 3);
    CHECK(r.err.find("cannot read 'missing.moire'") != std::string::npos);
    // A directory where the page should go: the write fails, and nothing is left beside it.
    fs::create_directory(w.file("taken.html"));
    r = w.moire("export s.moire -o taken.html");
    CHECK(r.status == 3);
    CHECK(r.err.find("cannot write 'taken.html'") != std::string::npos);
    CHECK(w.names() == std::vector<std::string>{"bad.moire", "s.moire", "taken.html"});
}

TEST_CASE("export -v names each stage, and --help says what the page holds and the exit statuses") {
    Workdir w;
    w.write("s.moire", kScene);
    test::CommandResult r = w.moire("export s.moire -v");
    REQUIRE(r.status == 0);
    for (const char* stage : {"compiled s.moire", "GLSL ES", "JavaScript", "wrote s.html"})
        CHECK(r.err.find(stage) != std::string::npos);
    r = w.moire("export --help");
    CHECK(r.status == 0);
    CHECK(r.out.find("WebGL2") != std::string::npos);
    CHECK(r.out.find("Exit status") != std::string::npos);
}

TEST_CASE("compile --dump=glsl-es and --dump=js show the page's two translations") {
    Workdir w;
    w.write("s.moire", kScene);
    test::CommandResult es = w.moire("compile s.moire --dump=glsl-es");
    REQUIRE(es.status == 0);
    CHECK(es.out.rfind("#version 300 es\n", 0) == 0);
    CHECK(es.out.find("out vec4 m_color;") != std::string::npos);
    test::CommandResult js = w.moire("compile s.moire --dump=js");
    REQUIRE(js.status == 0);
    CHECK(js.out.find("return (literals, time, out) =>") != std::string::npos);
    // Both are what the page carries.
    REQUIRE(w.moire("export s.moire -q").status == 0);
    const std::string page = test::readFile(w.file("s.html"));
    CHECK(page.find(js.out.substr(0, js.out.size() - 1)) != std::string::npos);
    test::CommandResult bad = w.moire("compile s.moire --dump=webgl");
    CHECK(bad.status == 2);
    CHECK(bad.err.find("glsl-es, js") != std::string::npos);
}

TEST_CASE(
    "export -D sets where a param's slider starts, and a wrong -D points into the command line") {
    Workdir w;
    w.write("p.moire", "scene { size = (64, 40) }\nparam gap = 8 in 4 .. 20\n"
                       "layer { family = circles; spacing = gap }\n");
    test::CommandResult r = w.moire("export p.moire -D gap=40");
    CHECK(r.status == 1);
    CHECK(r.err.find("<command line>:1:") != std::string::npos);
    CHECK(r.err.find("param 'gap' must be from 4 to 20, not 40") != std::string::npos);
    r = w.moire("export p.moire -D gap");
    CHECK(r.status == 2);
    CHECK(w.names() == std::vector<std::string>{"p.moire"});
    // The literal table the page starts from holds the value -D gave.
    REQUIRE(w.moire("export p.moire -q -o plain.html").status == 0);
    REQUIRE(w.moire("export p.moire -q -D gap=13.25 -o set.html").status == 0);
    CHECK(test::readFile(w.file("plain.html")).find("13.25") == std::string::npos);
    CHECK(test::readFile(w.file("set.html")).find("13.25") != std::string::npos);
}
