#include "runtime/serve/PageFiles.h"
#include "runtime/TextFile.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire::serve;

// The embedded bytes are the files in the repository, byte for byte.
TEST_CASE("serve page: the embedded files are the page's sources") {
    for (const char* name : {"index.html", "page.js", "page.css"}) {
        CAPTURE(name);
        std::optional<page::Asset> a = page::asset(name);
        REQUIRE(a);
        std::string text, reason;
        REQUIRE(moire::readWholeFile(std::string(MOIRE_SOURCE_DIR) + "/runtime/serve/page/" + name,
                                     text, reason));
        CHECK(a->text == text);
    }
    CHECK(std::string(page::asset("index.html")->contentType).rfind("text/html", 0) == 0);
    CHECK(std::string(page::asset("page.js")->contentType).rfind("text/javascript", 0) == 0);
    CHECK_FALSE(page::asset("../../CMakeLists.txt"));
    CHECK_FALSE(page::asset(""));
}
