// The viewer's bitmap font: every printable character has a glyph of its own, text is as wide
// as it says, and drawing stays inside the canvas.
#include "runtime/view/BitmapFont.h"

#include <doctest/doctest.h>
#include <set>
#include <string>
#include <vector>

using namespace moire::view;

namespace {

std::string bitsOf(char c) {
    std::string s;
    for (int y = 0; y < font::kGlyphHeight; ++y)
        for (int x = 0; x < font::kGlyphWidth; ++x) s += font::ink(c, x, y) ? '#' : '.';
    return s;
}

int inkCount(const std::vector<uint8_t>& rgba) {
    int n = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) n += rgba[i] == 255;
    return n;
}

} // namespace

TEST_CASE("font: every printable ASCII glyph is distinct, and only the space is blank") {
    std::set<std::string> seen;
    for (int c = 32; c <= 126; ++c) {
        CAPTURE(static_cast<char>(c));
        std::string bits = bitsOf(static_cast<char>(c));
        CHECK(seen.insert(bits).second);
        CHECK((bits.find('#') == std::string::npos) == (c == ' '));
    }
    CHECK(seen.size() == 95);
    // Outside the printable range: a question mark, never garbage.
    CHECK(bitsOf('\t') == bitsOf('?'));
    CHECK(bitsOf(static_cast<char>(0xC3)) == bitsOf('?'));
    CHECK_FALSE(font::ink('A', 5, 0));
    CHECK_FALSE(font::ink('A', 0, 7));
}

TEST_CASE("font: text width") {
    CHECK(font::textWidth("") == 0);
    CHECK(font::textWidth("A") == 5);
    CHECK(font::textWidth("AB") == 11);
    CHECK(font::textWidth("12.5 ms", 2) == 2 * (7 * 6 - 1));
    // Drawing advances by exactly that (plus the space after the last glyph).
    std::vector<uint8_t> rgba(64 * 16 * 4, 0);
    Canvas canvas{rgba.data(), 64, 16};
    CHECK(font::drawText(canvas, 3, 2, "abc", 1, {255, 255, 255, 255}) ==
          3 + font::textWidth("abc") + 1);
}

TEST_CASE("font: drawing is the glyph, scaled, and clipped to the canvas") {
    std::vector<uint8_t> rgba(40 * 20 * 4, 0);
    Canvas canvas{rgba.data(), 40, 20};
    font::drawText(canvas, 1, 1, "H", 2, {255, 0, 0, 255});
    int expect = 0;
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 5; ++x) expect += font::ink('H', x, y) ? 4 : 0;
    CHECK(inkCount(rgba) == expect);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 5; ++x)
            CHECK((rgba[((1 + 2 * y) * 40 + 1 + 2 * x) * 4] == 255) == font::ink('H', x, y));
    // Off every edge: nothing is written out of bounds (the sanitizer build watches), and
    // what lands inside is drawn.
    std::vector<uint8_t> small(8 * 8 * 4, 0);
    Canvas tiny{small.data(), 8, 8};
    font::drawText(tiny, -3, -4, "WWWW", 3, {255, 255, 255, 255});
    font::drawText(tiny, 6, 6, "M", 1, {255, 255, 255, 255});
    CHECK(inkCount(small) > 0);
    fillRect(tiny, -10, -10, 100, 100, {0, 0, 0, 255});
    CHECK(inkCount(small) == 0);
    // Half-transparent fills blend.
    fillRect(tiny, 0, 0, 1, 1, {255, 255, 255, 128});
    CHECK(small[0] == 128);
}
