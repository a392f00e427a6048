// --region's reading and its check against the frame.
#include "runtime/cli/Region.h"

#include <doctest/doctest.h>

namespace moire::cli {

TEST_CASE("parseRegion reads four whole numbers and refuses anything else") {
    std::string error;
    auto r = parseRegion("0,10,300,217", error);
    REQUIRE(r);
    CHECK(r->x0 == 0);
    CHECK(r->y0 == 10);
    CHECK(r->x1 == 300);
    CHECK(r->y1 == 217);
    CHECK(r->width() == 300);
    CHECK(r->height() == 207);
    for (const char* bad : {"", "1,2,3", "1,2,3,4,5", "-1,0,4,4", "0,0,4,4x", " 0,0,4,4", "0,,4,4",
                            "0,0,4.5,4", "0,0,9999999999,4"}) {
        CAPTURE(bad);
        error.clear();
        CHECK_FALSE(parseRegion(bad, error));
        CHECK(error.find("must be X0,Y0,X1,Y1") != std::string::npos);
    }
    for (const char* empty : {"4,0,4,8", "0,8,4,8", "5,0,4,8"}) {
        CAPTURE(empty);
        error.clear();
        CHECK_FALSE(parseRegion(empty, error));
        CHECK(error.find("is empty") != std::string::npos);
    }
}

TEST_CASE("regionProblem: a region must lie inside the frame, its far edges included") {
    CHECK(regionProblem(Region{0, 0, 640, 480}, 640, 480).empty());
    CHECK(regionProblem(Region{639, 479, 640, 480}, 640, 480).empty());
    CHECK(regionProblem(Region{0, 0, 641, 480}, 640, 480).find("reaches past the 640x480 frame") !=
          std::string::npos);
    CHECK_FALSE(regionProblem(Region{0, 0, 640, 481}, 640, 480).empty());
    CHECK_FALSE(regionProblem(Region{700, 500, 800, 600}, 640, 480).empty());
}

} // namespace moire::cli
