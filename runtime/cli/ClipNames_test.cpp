// What `moire clip` reads from its command line: --frames and the numbered output name.
#include "runtime/cli/ClipNames.h"

#include <doctest/doctest.h>

using namespace moire::cli;

TEST_CASE("--frames: a count or a range") {
    std::string why;
    auto r = parseFrames("10", why);
    REQUIRE(r);
    CHECK((r->first == 0 && r->last == 9));
    r = parseFrames("5..7", why);
    REQUIRE(r);
    CHECK((r->first == 5 && r->last == 7 && r->count() == 3));
    for (const char* bad : {"0", "7..5", "a", "3..", "..4", "-1..2", "1.5", "2..3..4", "",
                            "0..9223372036854775807"}) {
        CAPTURE(bad);
        CHECK_FALSE(parseFrames(bad, why));
        CHECK(why.find("--frames") != std::string::npos);
    }
}

TEST_CASE("output names: a printf-style frame number in the file name") {
    std::string why;
    auto p = parseNamePattern("out/frame_%04d.png", why);
    REQUIRE(p);
    CHECK(p->name(7) == "out/frame_0007.png");
    CHECK(p->name(12345) == "out/frame_12345.png");
    p = parseNamePattern("f%d.exr", why);
    REQUIRE(p);
    CHECK(p->name(42) == "f42.exr");
    p = parseNamePattern("f%3d.png", why);
    REQUIRE(p);
    CHECK(p->name(5) == "f  5.png");
    p = parseNamePattern("100%%/at_%%_%02d.png", why);
    REQUIRE(p);
    CHECK(p->name(3) == "100%%/at_%_03.png"); // the directory is taken as written
    p = parseNamePattern("still.png", why);
    REQUIRE(p);
    CHECK_FALSE(p->numbered);
    CHECK(p->name(9) == "still.png");
    for (const char* bad : {"f_%s.png", "f_%d_%d.png", "f_%.png", "f_%x.png", "f_%-4d.png"}) {
        CAPTURE(bad);
        CHECK_FALSE(parseNamePattern(bad, why));
    }
}
