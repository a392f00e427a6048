// The command line's conventions, the same in every command (docs/cli.md): one exit status
// per kind of failure, - for standard input and output, compile -o, -q and -v everywhere, and
// a --help that speaks of its own command. The real binary, run as a user runs it.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace moire;

namespace {

struct Dir : test::TempDir {
    Dir() : test::TempDir("conventions") {
        write("s.moire", "scene { size = (48, 32) }\nlayer { family = circles; spacing = 4 }\n");
        write("bad.moire", "layer { family = circels }\n");
    }
    test::CommandResult moire(const std::string& args, const std::string& env = "") const {
        // In braces, so that a redirection in `args` wins over runCommand's own.
        return test::runCommand("cd '" + path() + "' && { " + env + " '" + test::moireBinary() +
                                "' " + args + "; }");
    }
};

// A user-facing failure of the machine or a file: one line, "moire: error: ...".
bool oneErrorLine(const test::CommandResult& r) {
    return r.err.rfind("moire: error: ", 0) == 0 &&
           std::count(r.err.begin(), r.err.end(), '\n') == 1;
}

} // namespace

TEST_CASE("exit status 1: the scene has errors, in every command that reads one") {
    Dir d;
    for (const char* args :
         {"render bad.moire -o o.png", "check bad.moire", "compile bad.moire",
          "clip bad.moire --fps 2 --frames 2 -o f%d.png", "watch --once bad.moire -o o.png"}) {
        CAPTURE(args);
        test::CommandResult r = d.moire(args);
        CHECK(r.status == 1);
        CHECK(r.err.find("bad.moire:1:18: error: unknown family 'circels'") != std::string::npos);
    }
    CHECK(d.names() == std::vector<std::string>{"bad.moire", "s.moire"});
}

TEST_CASE("exit status 2: a command line moire cannot follow, found before any work") {
    Dir d;
    for (const char* args :
         {"render s.moire --size 0x10", "render s.moire -o o.bmpx",
          "render s.moire -o f.png "
          "--depth float",
          "render s.moire -o o.exr --depth 8", "clip s.moire --frames 2 -o f%d.png", // no --fps
          "clip s.moire --fps 2 --frames 2 -o -", "compile s.moire --dump=asm", "check",
          "devices --nonsense", "watch - -o o.png", "view -", "render -q -v s.moire -o o.png"}) {
        CAPTURE(args);
        test::CommandResult r = d.moire(args);
        CHECK(r.status == 2);
        CHECK_FALSE(r.err.empty());
        CHECK(r.out.empty());
    }
    CHECK(d.names() == std::vector<std::string>{"bad.moire", "s.moire"});
}

TEST_CASE("exit status 3: a file that cannot be read or written") {
    Dir d;
    d.write("blocker", "a file where a directory should be");
    for (const char* args :
         {"render none.moire -o o.png", "check none.moire", "compile none.moire",
          "clip none.moire --fps 2 --frames 2 -o f%d.png", "watch --once none.moire -o o.png",
          "render s.moire -o blocker/o.png", "compile s.moire -o blocker/ir.txt",
          "clip s.moire --fps 2 --frames 2 -o blocker/f%d.png"}) {
        CAPTURE(args);
        test::CommandResult r = d.moire(args);
        CHECK(r.status == 3);
        const bool reading = r.err.find("none.moire") != std::string::npos;
        if (reading)
            CHECK(r.err.find("cannot read") != std::string::npos);
        else
            CHECK((oneErrorLine(r) && r.err.find("blocker") != std::string::npos));
    }
    CHECK(d.names() == std::vector<std::string>{"bad.moire", "blocker", "s.moire"});
    // check goes on past a scene it cannot read, and answers with the first failure's status.
    CHECK(d.moire("check none.moire bad.moire").status == 3);
    CHECK(d.moire("check bad.moire none.moire").status == 1);
    CHECK(d.moire("check --format=json none.moire bad.moire").status == 3);
    CHECK(d.moire("check --format=json bad.moire none.moire").status == 1);
}

TEST_CASE("exit status 4: the machine cannot do it (no Vulkan device)") {
    Dir d;
    for (const char* args : {"render s.moire -o o.png --backend vulkan", "devices",
                             "clip s.moire --fps 2 --frames 2 -o f%d.png --backend vulkan"}) {
        CAPTURE(args);
        // No Vulkan driver (the variables of the older loader and of the newer).
        test::CommandResult r =
            d.moire(args, "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
        CHECK(r.status == 4);
        CHECK(oneErrorLine(r));
    }
    CHECK(d.names() == std::vector<std::string>{"bad.moire", "s.moire"});
}

TEST_CASE("exit status 4: a frame larger than the memory the process may have") {
    if (test::skipUnderAddressSanitizer()) return;
    Dir d;
    // An image far larger than any memory a process here may have (ulimit -v: 2 GiB), held
    // whole: a PNG to standard output is assembled in memory (a file streams its bands and
    // needs no frame).
    test::CommandResult r =
        test::runCommand("cd '" + d.path() + "' && ulimit -v 2097152 && '" + test::moireBinary() +
                         "' render s.moire --size 30000x30000 -o - > /dev/null");
    CHECK(r.status == 4);
    CHECK(r.err.find("needs about") != std::string::npos);
    CHECK(d.names() == std::vector<std::string>{"bad.moire", "s.moire"});
}

TEST_CASE("- is standard input for the scene and standard output for the image") {
    Dir d;
    REQUIRE(d.moire("render s.moire -o ref.png -q").status == 0);
    test::CommandResult r = d.moire("render - -o - < s.moire > piped.png");
    CHECK(r.status == 0);
    CHECK(r.err.find("wrote standard output") != std::string::npos);
    const Image ref = readImage(d.file("ref.png")), piped = readImage(d.file("piped.png"));
    CHECK(piped.width == 48);
    CHECK(piped.height == 32);
    CHECK(piped.pixels == ref.pixels);
    // 16 bits through the pipe too; the file is a PNG whatever it is called.
    CHECK(d.moire("render s.moire --depth 16 -o - > deep.bin").status == 0);
    CHECK(readImage(d.file("deep.bin")).width == 48);
    // A scene with errors on standard input writes nothing to standard output.
    test::CommandResult bad = d.moire("render - -o - < bad.moire");
    CHECK(bad.status == 1);
    CHECK(bad.out.empty());
    CHECK(bad.err.find("<stdin>:1:18: error:") != std::string::npos);
    // A reader that goes away early is an error about the output, not a crash.
    // (moire's own status is kept in a file: the pipeline's is that of `true`.)
    d.moire("render s.moire --size 2000x2000 -o - 2>err.txt; echo $? >status.txt; } | { true");
    CHECK(test::readFile(d.file("status.txt")) == "3\n");
    CHECK(test::readFile(d.file("err.txt")).find("cannot write to standard output") !=
          std::string::npos);
}

TEST_CASE("compile -o FILE writes what standard output shows, and - is standard output") {
    Dir d;
    test::CommandResult shown = d.moire("compile s.moire --dump=kernel");
    REQUIRE(shown.status == 0);
    CHECK(shown.out.find("func ") != std::string::npos);
    CHECK(d.moire("compile s.moire --dump=kernel -o -").out == shown.out);
    CHECK(d.moire("compile - --dump=kernel < s.moire").out == shown.out);
    test::CommandResult written = d.moire("compile s.moire --dump=kernel -o dumps/kernel.txt");
    CHECK(written.status == 0);
    CHECK(written.out.empty());
    CHECK(test::readFile(d.file("dumps/kernel.txt")) == shown.out);
    // A scene with errors leaves no file.
    CHECK(d.moire("compile bad.moire -o bad.txt").status == 1);
    CHECK_FALSE(fs::exists(d.file("bad.txt")));
}

TEST_CASE("-q and -v: every command takes them, -q prints nothing but errors, -v each stage") {
    Dir d;
    for (const char* verb : {"render", "clip", "watch", "view", "check", "compile", "devices"}) {
        CAPTURE(verb);
        const std::string help = d.moire(std::string(verb) + " --help").out;
        CHECK(help.find("-q,--quiet") != std::string::npos);
        CHECK(help.find("-v,--verbose") != std::string::npos);
    }
    struct Case {
        const char* args;
        const char* stage; // a line -v adds on stderr
    };
    for (const Case& c : {Case{"render s.moire -o o.png", "moire: rendered 48x32 on jit ("},
                          Case{"clip s.moire --fps 2 --frames 2 -o f%d.png",
                               "moire: rendered and wrote 2 frames ("},
                          Case{"watch --once s.moire -o w.png", "read and checked the scene in"},
                          Case{"check s.moire", "moire: checked s.moire: 48x32, timings: none ("},
                          Case{"compile s.moire", "moire: compiled s.moire ("}}) {
        CAPTURE(c.args);
        test::CommandResult quiet = d.moire(std::string(c.args) + " -q");
        CHECK(quiet.status == 0);
        CHECK(quiet.err.empty());
        test::CommandResult normal = d.moire(c.args);
        CHECK(normal.status == 0);
        CHECK(normal.err.find(c.stage) == std::string::npos);
        test::CommandResult verbose = d.moire(std::string(c.args) + " -v");
        CHECK(verbose.status == 0);
        CHECK(verbose.err.find(c.stage) != std::string::npos);
    }
    // check -q says nothing of good scenes; compile -q still prints the dump it was asked for.
    CHECK(d.moire("check -q s.moire").out.empty());
    CHECK_FALSE(d.moire("compile -q s.moire").out.empty());
}

TEST_CASE("each command's --help speaks of that command, and says its exit statuses") {
    Dir d;
    const std::string top = d.moire("--help").out;
    CHECK(top.find("Run 'moire COMMAND --help'") != std::string::npos);
    for (const char* verb : {"render", "clip", "watch", "view", "check", "compile", "devices"}) {
        CAPTURE(verb);
        test::CommandResult r = d.moire(std::string(verb) + " --help");
        CHECK(r.status == 0);
        // Nothing of the top level's footer, nor of render's default scene outside the
        // commands that have one.
        CHECK(r.out.find("Run 'moire COMMAND --help'") == std::string::npos);
        CHECK(r.out.find("render uses") == std::string::npos);
        const std::string v = verb;
        if (v == "watch" || v == "check" || v == "devices")
            CHECK(r.out.find("default scene") == std::string::npos);
        if (v != "view") CHECK(r.out.find("Exit status:") != std::string::npos);
    }
}
