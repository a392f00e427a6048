// Positions in UTF-16 code units against byte offsets, and the URIs of files and of the
// library.
#include "compiler/stdlib/Embedded.h"
#include "lsp/Protocol.h"

#include <doctest/doctest.h>

using namespace moire::lsp;

TEST_CASE("lsp protocol: a position counts UTF-16 code units, an offset bytes") {
    // "é" is 2 bytes and 1 unit; "😀" 4 bytes and 2 units (a surrogate pair).
    std::string text = "ab\n\xc3\xa9x\xf0\x9f\x98\x80y\r\nz";
    LineIndex index(text);
    CHECK(index.lineCount() == 3);
    auto pos = [&](uint32_t off) {
        Position p = index.position(off);
        return std::make_pair(p.line, p.character);
    };
    CHECK(pos(0) == std::make_pair(0u, 0u));
    CHECK(pos(3) == std::make_pair(1u, 0u));
    CHECK(pos(5) == std::make_pair(1u, 1u));  // after é
    CHECK(pos(6) == std::make_pair(1u, 2u));  // after x
    CHECK(pos(10) == std::make_pair(1u, 4u)); // after the emoji
    CHECK(pos(11) == std::make_pair(1u, 5u));
    // Every offset that starts a character comes back from its position.
    for (uint32_t off : {0u, 1u, 2u, 3u, 5u, 6u, 10u, 11u, 12u, 13u, 14u})
        CHECK(index.offset(index.position(off)) == off);
    // Past the end of a line or of the text: clamped.
    CHECK(index.offset({0, 99}) == 2);
    CHECK(index.offset({9, 0}) == text.size());
}

TEST_CASE("lsp protocol: file URIs and paths") {
    CHECK(uriToPath("file:///home/a%20b/c.moire") == "/home/a b/c.moire");
    CHECK(uriToPath("untitled:Untitled-1") == "untitled:Untitled-1");
    CHECK(pathToUri("/home/a b/c.moire") == "file:///home/a%20b/c.moire");
    CHECK(uriToPath(pathToUri("/x/\xc3\xa9 y#1.moire")) == "/x/\xc3\xa9 y#1.moire");
}

TEST_CASE("lsp protocol: the library's files are served under moire-stdlib:///") {
    CHECK(stdlibUri("<stdlib>/families.moire") == "moire-stdlib:///families.moire");
    const std::string_view* text = stdlibText("moire-stdlib:///families.moire");
    REQUIRE(text);
    bool found = false;
    for (const moire::embedded::File& f : moire::embedded::files())
        if (std::string_view(f.path) == "stdlib/families.moire") found = f.text == *text;
    CHECK(found);
    CHECK(!stdlibText("moire-stdlib:///nothing.moire"));
    CHECK(!stdlibText("file:///families.moire"));
}
