// ctest runs each doctest case by name, and cuts a name at ';' (a CMake list separator): a
// case named with a ';' would match nothing and pass without running. This keeps such names
// out of the suite.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <regex>

namespace fs = std::filesystem;

TEST_CASE("test names: no test case name contains a semicolon") {
    const std::regex testCase(R"(TEST_CASE\(\s*"([^"]*)\")");
    int files = 0;
    for (const char* dir : {"compiler", "runtime", "tests"}) {
        for (const auto& entry : fs::recursive_directory_iterator(moire::test::sourcePath(dir))) {
            const std::string name = entry.path().filename().string();
            if (!entry.is_regular_file() || name.size() < 9 ||
                name.substr(name.size() - 9) != "_test.cpp")
                continue;
            ++files;
            const std::string text = moire::test::readFile(entry.path().string());
            for (auto it = std::sregex_iterator(text.begin(), text.end(), testCase);
                 it != std::sregex_iterator(); ++it) {
                CAPTURE(name);
                CHECK((*it)[1].str().find(';') == std::string::npos);
            }
        }
    }
    CHECK(files > 10);
}
