// The sheet's layout: papers in pixels (against values worked by hand from round(mm / 25.4 *
// dpi)), the orientation rule, the bleed and the marks' margin, and the pixel's world size.
#include "runtime/print/SheetLayout.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire::print;

namespace {

SheetLayout sheet(const std::string& paper, double dpi, Orientation o = Orientation::Portrait) {
    SheetRequest r;
    std::string why;
    REQUIRE_MESSAGE(parsePaper(paper, r.paper, why), why);
    r.dpi = dpi;
    r.orientation = o;
    r.sceneWidth = 800;
    r.sceneHeight = 1200;
    return layoutSheet(r);
}

} // namespace

TEST_CASE("papers are their millimetres at the resolution, rounded") {
    struct Case {
        const char* paper;
        double dpi;
        long long w, h;
    };
    // A0 is 841 x 1189 mm: 841 / 25.4 * 600 = 19866.14, 1189 / 25.4 * 600 = 28086.61.
    // A3 is 297 x 420 mm: 3507.87 x 4960.63 at 300 dpi. Letter is 8.5 x 11 in exactly.
    const Case cases[] = {
        {"A0", 600, 19866, 28087}, {"a0", 300, 9933, 14043},      {"A3", 300, 3508, 4961},
        {"A3", 600, 7016, 9921},   {"letter", 300, 2550, 3300},   {"Letter", 600, 5100, 6600},
        {"A4", 100, 827, 1169},    {"210x297mm", 100, 827, 1169},
    };
    for (const Case& c : cases) {
        CAPTURE(c.paper);
        CAPTURE(c.dpi);
        const SheetLayout s = sheet(c.paper, c.dpi);
        CHECK(s.width == c.w);
        CHECK(s.height == c.h);
        CHECK(s.trim.width() == c.w);
        CHECK(s.trim.x0 == 0);
        CHECK(s.bleed == 0);
        CHECK(s.margin == 0);
    }
}

TEST_CASE("the paper turns to the scene's frame unless told") {
    SheetRequest r;
    std::string why;
    REQUIRE(parsePaper("A4", r.paper, why));
    r.dpi = 100;
    r.sceneWidth = 1200;
    r.sceneHeight = 800;
    SheetLayout s = layoutSheet(r); // a wide frame: landscape
    CHECK(s.landscape);
    CHECK(s.width == 1169);
    CHECK(s.height == 827);
    r.orientation = Orientation::Portrait;
    s = layoutSheet(r);
    CHECK_FALSE(s.landscape);
    CHECK(s.width == 827);
    r.sceneWidth = 800;
    r.sceneHeight = 1200;
    r.orientation = Orientation::Landscape;
    CHECK(layoutSheet(r).width == 1169);
    // A square frame leaves the paper as given, a custom one as written.
    r.sceneWidth = r.sceneHeight = 500;
    r.orientation = Orientation::Auto;
    REQUIRE(parsePaper("300x200mm", r.paper, why));
    s = layoutSheet(r);
    CHECK(s.paperWidthMm == 300);
    CHECK(s.paperHeightMm == 200);
}

TEST_CASE("bleed and marks grow the sheet around a centred trim") {
    // 10 pixels a millimetre.
    SheetRequest r{.paper = {100, 50},
                   .dpi = 254,
                   .bleedMm = 3,
                   .marks = true,
                   .sceneWidth = 200,
                   .sceneHeight = 100};
    const SheetLayout s = layoutSheet(r);
    CHECK(s.bleed == 30);
    CHECK(s.margin == 120); // 12 mm
    CHECK(s.width == 1000 + 2 * 150);
    CHECK(s.height == 500 + 2 * 150);
    CHECK(s.trim.x0 == 150);
    CHECK(s.trim.y0 == 150);
    CHECK(s.trim.x1 == 1150);
    CHECK(s.trim.y1 == 650);
    CHECK(s.art.x0 == 120);
    CHECK(s.art.x1 == 1180);
    CHECK(s.art.y1 == 680);
    // The frame (200 x 100) fitted to the trim (1000 x 500 px): 0.2 world units a pixel, and
    // the bleed continues at that scale.
    CHECK(s.pixelSize == doctest::Approx(0.2));
    r.zoom = 2;
    CHECK(layoutSheet(r).pixelSize == doctest::Approx(0.1));
    // A stated scale: 3 world units a millimetre at 10 pixels a millimetre.
    r.scale = 3;
    CHECK(layoutSheet(r).pixelSize == doctest::Approx(0.3));
}

TEST_CASE("an unknown paper is refused with the papers named") {
    PaperSize p;
    std::string why;
    CHECK_FALSE(parsePaper("B5", p, why));
    CHECK(why.find("unknown paper 'B5'") != std::string::npos);
    CHECK(why.find("letter") != std::string::npos);
    CHECK_FALSE(parsePaper("0x10mm", p, why));
    CHECK(why.find("'0x10mm'") != std::string::npos);
}
