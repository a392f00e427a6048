// `moire fmt` as a user runs it: --check writes nothing and names what it would change (exit
// 1), files are rewritten in place only when formatting changes them, - goes from standard
// input to standard output, and a file with errors gets located diagnostics and is left as
// it was.
#include "compiler/format/Formatter.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <string>
#include <sys/stat.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

const char* kMessy = "scene{size=(48,32)}\nlayer { family=circles; spacing=4 }\n";
const char* kTidy = "scene { size = (48, 32) }\nlayer { family = circles; spacing = 4 }\n";
const char* kBroken = "layer {\n    family = circles\n    spacing = (4\n}\n";

struct Dir : test::TempDir {
    Dir() : test::TempDir("fmt") {
        write("messy.moire", kMessy);
        write("tidy.moire", kTidy);
        write("broken.moire", kBroken);
    }
    test::CommandResult moire(const std::string& args) const {
        return test::runCommand("cd '" + path() + "' && { '" + test::moireBinary() + "' " + args +
                                "; }");
    }
    std::string read(const std::string& name) const { return test::readFile(file(name)); }
    ino_t inode(const std::string& name) const {
        struct stat st {};
        REQUIRE(::stat(file(name).c_str(), &st) == 0);
        return st.st_ino;
    }
};

} // namespace

TEST_CASE("fmt cli: the layout expected here is the formatter's") {
    format::FormatResult r = format::formatSource("messy.moire", kMessy);
    REQUIRE(r.ok);
    CHECK(r.text == kTidy);
}

TEST_CASE("fmt cli: --check writes nothing, names the files it would change, exits 1") {
    Dir d;
    test::CommandResult r = d.moire("fmt --check tidy.moire messy.moire");
    CHECK(r.status == 1);
    CHECK(r.out == "messy.moire\n");
    CHECK(r.err.empty());
    CHECK(d.read("messy.moire") == kMessy);
    CHECK(d.names() == std::vector<std::string>{"broken.moire", "messy.moire", "tidy.moire"});

    r = d.moire("fmt --check tidy.moire");
    CHECK(r.status == 0);
    CHECK(r.out.empty());

    r = d.moire("fmt --check -q messy.moire"); // the status alone
    CHECK(r.status == 1);
    CHECK(r.out.empty());
}

TEST_CASE("fmt cli: files are rewritten in place, and only those that change") {
    Dir d;
    ::chmod(d.file("messy.moire").c_str(), 0640);
    ino_t tidyBefore = d.inode("tidy.moire");
    test::CommandResult r = d.moire("fmt -v messy.moire tidy.moire");
    CHECK(r.status == 0);
    CHECK(r.out.empty());
    CHECK(r.err == "moire: formatted messy.moire\nmoire: already formatted: tidy.moire\n");
    CHECK(d.read("messy.moire") == kTidy);
    CHECK(d.inode("tidy.moire") == tidyBefore); // not written at all
    CHECK((fs::status(d.file("messy.moire")).permissions() & fs::perms::all) ==
          (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
    // No temporary is left beside them.
    CHECK(d.names() == std::vector<std::string>{"broken.moire", "messy.moire", "tidy.moire"});
    // Formatting again changes nothing.
    CHECK(d.moire("fmt --check messy.moire").status == 0);
}

TEST_CASE("fmt cli: - reads standard input and writes the formatted text to standard output") {
    Dir d;
    test::CommandResult r = d.moire("fmt - < messy.moire");
    CHECK(r.status == 0);
    CHECK(r.out == kTidy);
    CHECK(d.read("messy.moire") == kMessy);
    r = d.moire("fmt --check - < messy.moire");
    CHECK(r.status == 1);
    CHECK(r.out == "-\n");
    r = d.moire("fmt - < broken.moire");
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    CHECK(r.err.find("<stdin>:4:1: error:") != std::string::npos);
}

TEST_CASE("fmt cli: a file with errors gets located diagnostics and is left untouched") {
    Dir d;
    test::CommandResult r = d.moire("fmt broken.moire messy.moire");
    CHECK(r.status == 1);
    // The diagnostics of moire check, word for word.
    test::CommandResult check = d.moire("check broken.moire");
    CHECK(check.status == 1);
    CHECK(r.err == check.err);
    CHECK(r.err.find("broken.moire:4:1: error: expected ')'") != std::string::npos);
    CHECK(r.err.find("    4 | }\n      | ^") != std::string::npos);
    CHECK(d.read("broken.moire") == kBroken);
    CHECK(d.read("messy.moire") == kTidy); // the other files are still formatted
}

TEST_CASE("fmt cli: a file that cannot be read is status 3, with one line saying why") {
    Dir d;
    test::CommandResult r = d.moire("fmt none.moire messy.moire");
    CHECK(r.status == 3);
    CHECK(r.err.rfind("moire: error: cannot read 'none.moire'", 0) == 0);
    CHECK(d.moire("fmt").status == 2); // no file named
}

TEST_CASE("fmt cli: --help says what the command does and its exit statuses") {
    Dir d;
    test::CommandResult r = d.moire("fmt --help");
    CHECK(r.status == 0);
    CHECK(r.out.find("--check") != std::string::npos);
    CHECK(r.out.find("-q,--quiet") != std::string::npos);
    CHECK(r.out.find("Exit status") != std::string::npos);
    CHECK(d.moire("--help").out.find("fmt") != std::string::npos);
}
