// The printer's marks: where the layout says, inside the margin, never over the artwork, and
// finishRows lays exactly markCoverage's ink in black over a cleared margin.
#include "runtime/print/Marks.h"

#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire::print;

namespace {

SheetLayout markedSheet(double bleedMm) {
    // 10 pixels a millimetre: a 600 x 400 trim.
    return layoutSheet({.paper = {60, 40},
                        .dpi = 254,
                        .bleedMm = bleedMm,
                        .marks = true,
                        .sceneWidth = 60,
                        .sceneHeight = 40});
}

} // namespace

TEST_CASE("every mark lies in the margin, and the marks stand where the layout puts them") {
    for (double bleed : {0.0, 3.0}) {
        CAPTURE(bleed);
        const SheetLayout s = markedSheet(bleed);
        const auto marks = sheetMarks(s, 254);
        REQUIRE(marks.size() == 8 + 4 * 3);
        long long inked = 0;
        for (long long y = 0; y < s.height; ++y)
            for (long long x = 0; x < s.width; ++x) {
                const float c = markCoverage(s, marks, x, y);
                if (c <= 0) continue;
                ++inked;
                CHECK_FALSE(s.art.contains(x, y));
            }
        CHECK(inked > 0);
        // A crop mark continues the trim's left edge above the sheet: the pixels either side
        // of the line x = trim.x0, from a gap (2 mm) above the artwork to the sheet's edge.
        const long long gap = 20, y = s.art.y0 - gap - 10;
        CHECK(markCoverage(s, marks, s.trim.x0, y) > 0.9f);
        CHECK(markCoverage(s, marks, s.trim.x0 - 1, y) > 0.9f);
        CHECK(markCoverage(s, marks, s.trim.x0 + 5, y) == 0.0f);
        CHECK(markCoverage(s, marks, s.trim.x0, s.art.y0 - gap + 5) == 0.0f); // the gap
        // The same at the bottom right, horizontally.
        CHECK(markCoverage(s, marks, s.art.x1 + gap + 10, s.trim.y1) > 0.9f);
        // A registration target in the middle of the top margin: its circle's top (3.5 mm
        // above the centre) and its cross's centre, nothing in the ring's hollow off the cross.
        const long long cx = (s.trim.x0 + s.trim.x1) / 2, cy = s.margin / 2;
        CHECK(markCoverage(s, marks, cx, cy) > 0.9f);
        CHECK(markCoverage(s, marks, cx, cy - 35) > 0.4f);
        CHECK(markCoverage(s, marks, cx + 15, cy + 15) == 0.0f);
        // And in the middle of the left margin.
        CHECK(markCoverage(s, marks, s.margin / 2 + 35, (s.trim.y0 + s.trim.y1) / 2) > 0.4f);
    }
}

TEST_CASE("a sheet without marks has none") {
    const SheetLayout plain =
        layoutSheet({.paper = {60, 40}, .dpi = 254, .sceneWidth = 60, .sceneHeight = 40});
    CHECK(plain.margin == 0);
    CHECK(sheetMarks(plain, 254).empty());
}

TEST_CASE("finishing rows clears the margin and lays the marks in black, the artwork untouched") {
    const SheetLayout s = markedSheet(2.0);
    const auto marks = sheetMarks(s, 254);
    const int channels = 5; // RGBA and a channel the sheet does not read
    const size_t stride = static_cast<size_t>(s.width) * channels;
    const float art[5] = {0.2f, 0.4f, 0.6f, 0.8f, 7.0f};
    const float clear[4] = {0, 0, 0, 0}, white[4] = {1, 1, 1, 1};
    for (const float* margin : {clear, white}) {
        // Rows 140 to 160: across the top of the artwork (y0 = 140) and the left target.
        const long long y0 = s.art.y0 - 6;
        const int count = 20;
        std::vector<float> rows(stride * count);
        for (size_t i = 0; i < rows.size(); i += channels)
            std::copy(art, art + channels, rows.begin() + static_cast<long>(i));
        finishRows(s, marks, margin, y0, count, rows.data(), stride, channels);
        for (int r = 0; r < count; ++r)
            for (long long x = 0; x < s.width; ++x) {
                const float* p = rows.data() + r * stride + x * channels;
                const long long y = y0 + r;
                if (s.art.contains(x, y)) {
                    CHECK(p[0] == art[0]);
                    CHECK(p[3] == art[3]);
                    continue;
                }
                const float cov = markCoverage(s, marks, x, y);
                // Black with coverage cov over the margin: alpha a + cov (1 - a), colour
                // scaled by what shows through.
                const float a = cov + margin[3] * (1 - cov);
                CHECK(p[3] == doctest::Approx(a));
                const float c = a > 0 ? margin[0] * margin[3] * (1 - cov) / a : 0.0f;
                CHECK(p[0] == doctest::Approx(c));
                CHECK(p[4] == art[4]);
            }
    }
}
