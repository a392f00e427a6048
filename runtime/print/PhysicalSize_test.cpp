// Sizes on paper: the units, the rounding to pixels, and what is refused.
#include "runtime/print/PhysicalSize.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire::print;

TEST_CASE("a size on paper reads in millimetres, centimetres and inches") {
    PaperSize s;
    std::string why;
    REQUIRE(parsePhysicalSize("610x406mm", s, why));
    CHECK(s.widthMm == 610.0);
    CHECK(s.heightMm == 406.0);
    REQUIRE(parsePhysicalSize("61x40.6cm", s, why));
    CHECK(s.widthMm == doctest::Approx(610.0));
    CHECK(s.heightMm == doctest::Approx(406.0));
    REQUIRE(parsePhysicalSize("8.5X11in", s, why));
    CHECK(s.widthMm == doctest::Approx(215.9));
    CHECK(s.heightMm == doctest::Approx(279.4));
    CHECK(hasLengthUnit("10x10cm"));
    CHECK_FALSE(hasLengthUnit("1200x800"));
}

TEST_CASE("a size on paper is refused with the text named") {
    PaperSize s;
    for (const char* bad : {"610x406", "x406mm", "610xmm", "-610x406mm", "610x406ft", "6.1.0x406mm",
                            "1e3x406mm", "0x406mm", "610x0in", "200000x1mm"}) {
        CAPTURE(bad);
        std::string why;
        CHECK_FALSE(parsePhysicalSize(bad, s, why));
        CHECK(why.find(bad) != std::string::npos);
    }
}

TEST_CASE("millimetres become pixels rounded to the nearest") {
    // 610 mm at 300 dpi: 610 / 25.4 * 300 = 7204.72 -> 7205; 406 mm: 4795.28 -> 4795.
    CHECK(pixelsFor(610, 300) == 7205);
    CHECK(pixelsFor(406, 300) == 4795);
    CHECK(pixelsFor(25.4, 72) == 72);
    CHECK(pixelsFor(0, 600) == 0);
}

TEST_CASE("render's --size on paper is pixels at the resolution, with clear refusals") {
    std::string px, why;
    REQUIRE(sizeInPixels("610x406mm", 300, 32768, px, why));
    CHECK(px == "7205x4795");
    REQUIRE(sizeInPixels("2x1in", 100, 32768, px, why));
    CHECK(px == "200x100");
    REQUIRE(sizeInPixels("640x480", 0, 32768, px, why)); // pixels pass through
    CHECK(px == "640x480");
    CHECK_FALSE(sizeInPixels("610x406mm", 0, 32768, px, why));
    CHECK(why == "--size 610x406mm is a size on paper: it needs --dpi, the dots per inch to "
                 "render it at");
    CHECK_FALSE(sizeInPixels("610x406mm", 3000, 32768, px, why));
    CHECK(why == "--size 610x406mm at 3000 dpi is 72047x47953 pixels; each side must be 1 to "
                 "32768");
    CHECK_FALSE(sizeInPixels("0.1x10mm", 10, 32768, px, why));
    CHECK(why.find("0x4 pixels") != std::string::npos);
    CHECK_FALSE(sizeInPixels("ax4cm", 10, 32768, px, why));
    CHECK(why.find("'ax4cm' is not a size on paper") != std::string::npos);
}
