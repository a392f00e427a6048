// `moire serve` on the command line: what it refuses before serving (exit 2, a wrong -D
// among them), a folder it
// cannot watch or a port it cannot have (exit 3), the address on the first line of standard
// output, a warning for an address other than this machine's, and exit 0 on SIGTERM. The page
// itself is tested in a browser (tests/web/serve.test.js).
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <regex>

using namespace moire;

namespace {

// Serves `args` for a second and a half, then sends SIGTERM.
test::CommandResult serveBriefly(const std::string& args) {
    return test::runCommand("timeout --preserve-status -s TERM 1.5 " + test::moireBinary() +
                            " serve " + args);
}

} // namespace

TEST_CASE("serve: the page's address with a token on the first line, and SIGTERM stops it") {
    test::TempDir dir("serve-cli");
    dir.write("s.moire", "param gap = 6 in 2 .. 20\nlayer { family = circles; spacing = gap }\n");
    test::CommandResult r = serveBriefly(dir.file("s.moire") + " --port 0 --paused");
    CHECK(r.status == 0);
    const std::vector<std::string> out = test::lines(r.out);
    REQUIRE(out.size() == 1);
    CHECK(std::regex_match(out[0],
                           std::regex(R"(http://127\.0\.0\.1:[0-9]{2,5}/\?token=[0-9a-f]{32})")));
    CHECK(r.err.find("warning") == std::string::npos);

    // Another address: served, with a warning.
    r = serveBriefly(dir.file("s.moire") + " --host 0.0.0.0 --paused");
    CHECK(r.status == 0);
    CHECK(r.out.rfind("http://0.0.0.0:", 0) == 0);
    CHECK(r.err.find("moire: warning: serving on 0.0.0.0") != std::string::npos);

    // -D in range: served.
    r = serveBriefly(dir.file("s.moire") + " -D gap=8 --paused -q");
    CHECK(r.status == 0);
    CHECK(r.err.empty());

    // A scene with errors is served all the same: the page shows them.
    dir.write("bad.moire", "layer { family = circls }\n");
    r = serveBriefly(dir.file("bad.moire") + " --paused");
    CHECK(r.status == 0);
    CHECK(r.err.find("bad.moire:1:") != std::string::npos);
}

TEST_CASE("serve: what it refuses, and why") {
    test::TempDir dir("serve-cli-errors");
    dir.write("s.moire", "param gap = 6 in 2 .. 20\nlayer { family = circles; spacing = gap }\n");
    const std::string bin = test::moireBinary();
    struct Case {
        std::string args;
        int status;
        std::string message;
    };
    const Case cases[] = {
        {"-", 2, "standard input ('-') cannot be watched"},
        {"", 2, "scene is required"},
        {dir.file("s.moire") + " --port 70000", 2, "--port must be 0"},
        {dir.file("s.moire") + " --size 0x10", 2, "--size must be WIDTHxHEIGHT"},
        {dir.file("s.moire") + " --backend nonesuch", 2, "nonesuch"},
        {dir.file("s.moire") + " --time nan", 2, "--time"},
        {dir.file("nowhere/s.moire"), 3, "nowhere"},
        {dir.file("s.moire") + " --host 203.0.113.7", 3, "cannot listen on 203.0.113.7"},
        // -D is the command line's: no save can fix it.
        {dir.file("s.moire") + " -D gap=50", 2, "<command line>:1:"},
        {dir.file("s.moire") + " -D gape=5", 2, "<command line>:1:"},
        {dir.file("s.moire") + " -D gap", 2, "NAME=VALUE"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.args);
        test::CommandResult r = test::runCommand(bin + " serve " + c.args);
        CHECK(r.status == c.status);
        CHECK(r.out.empty());
        CHECK(r.err.find(c.message) != std::string::npos);
    }
}
