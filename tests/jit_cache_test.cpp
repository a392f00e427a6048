// The JIT's on-disk cache as the command line uses it (runtime/output/JitCache.h): the
// second render of a scene loads its compiled code and draws the same image; a cache
// file that is not an object is compiled again and replaced; the cache can be moved or
// turned off, and a cache that cannot be written never fails a render.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace moire;

namespace {

struct Dir : test::TempDir {
    Dir() : test::TempDir("jit_cache") {
        write("s.moire", "scene { size = (64, 48) }\nlayer { family = circles; spacing = 4 }\n"
                         "layer { family = squares; spacing = 7; turn = 5deg }\n");
    }
    test::CommandResult render(const std::string& env, const std::string& out) const {
        return test::runCommand("cd '" + path() + "' && env -u XDG_CACHE_HOME " + env + " '" +
                                test::moireBinary() + "' render -v s.moire -o " + out);
    }
    // The cached objects under `root` (every build's folder).
    std::vector<fs::path> objects(const std::string& root) const {
        std::vector<fs::path> found;
        if (!fs::exists(file(root))) return found;
        for (const auto& e : fs::recursive_directory_iterator(file(root)))
            if (e.path().extension() == ".o") found.push_back(e.path());
        return found;
    }
};

bool fromCache(const test::CommandResult& r) {
    return r.err.find("from the cache") != std::string::npos;
}

} // namespace

TEST_CASE("jit cache: the second render loads the code and draws the same image") {
    Dir d;
    std::string env = "MOIRE_CACHE_DIR='" + d.file("cache") + "'";
    test::CommandResult first = d.render(env, "a.png");
    REQUIRE(first.status == 0);
    CHECK(!fromCache(first));
    std::vector<fs::path> objects = d.objects("cache");
    REQUIRE(!objects.empty());

    test::CommandResult second = d.render(env, "b.png");
    REQUIRE(second.status == 0);
    CHECK(fromCache(second));
    CHECK(test::readFile(d.file("a.png")) == test::readFile(d.file("b.png")));

    // Not objects: compiled again, the same image, and the files replaced.
    for (const fs::path& o : objects) std::ofstream(o, std::ios::trunc) << "garbage";
    test::CommandResult third = d.render(env, "c.png");
    REQUIRE(third.status == 0);
    CHECK(!fromCache(third));
    CHECK(test::readFile(d.file("a.png")) == test::readFile(d.file("c.png")));
    for (const fs::path& o : objects) CHECK(test::readFile(o.string()) != "garbage");
}

TEST_CASE("jit cache: under HOME by default, moved by MOIRE_CACHE_DIR, off with 'off'") {
    Dir d;
    fs::create_directories(d.file("home"));
    REQUIRE(d.render("-u MOIRE_CACHE_DIR HOME='" + d.file("home") + "'", "a.png").status == 0);
    CHECK(!d.objects("home/.cache/moire/jit").empty());

    fs::create_directories(d.file("home2"));
    REQUIRE(d.render("HOME='" + d.file("home2") + "' MOIRE_CACHE_DIR=off", "b.png").status == 0);
    CHECK(!fs::exists(d.file("home2/.cache")));
}

TEST_CASE("jit cache: a cache that cannot be written never fails a render") {
    Dir d;
    d.write("not-a-folder", "x");
    test::CommandResult r = d.render("MOIRE_CACHE_DIR='" + d.file("not-a-folder") + "'", "a.png");
    CHECK(r.status == 0);
    CHECK(fs::file_size(d.file("a.png")) > 0);
}
