// The window's pixels: a frame of the window's size shown as it is, a preview's pixels each a
// block of the frame it stands for, a frame of another size stretched while a resize waits,
// always opaque; before any frame a plain dark grey.
#include "runtime/view/WindowCanvas.h"

#include <doctest/doctest.h>

using namespace moire::view;

namespace {

// A frame whose pixel (x, y) is (x, y, x + y, 7): every pixel tells where it came from.
RenderedFrame numbered(int w, int h) {
    RenderedFrame f;
    f.width = f.fullWidth = w;
    f.height = f.fullHeight = h;
    f.rgba.resize(static_cast<size_t>(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &f.rgba[(static_cast<size_t>(y) * w + x) * 4];
            p[0] = uint8_t(x), p[1] = uint8_t(y), p[2] = uint8_t(x + y), p[3] = 7;
        }
    return f;
}

const uint8_t* pixel(const std::vector<uint8_t>& c, int w, int x, int y) {
    return &c[(static_cast<size_t>(y) * w + x) * 4];
}

} // namespace

TEST_CASE("window canvas: full frames, previews and stretched frames") {
    std::vector<uint8_t> canvas;
    // The window's size: byte for byte, opaque.
    blitFrame(numbered(30, 20), 30, 20, canvas);
    REQUIRE(canvas.size() == 30u * 20 * 4);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 30; ++x) {
            const uint8_t* p = pixel(canvas, 30, x, y);
            CHECK((p[0] == x && p[1] == y && p[2] == x + y && p[3] == 255));
        }

    // A 1/4 preview of a 30x20 frame (8x5 pixels, the last column hanging over the edge):
    // window pixel (x, y) is preview pixel (x / 4, y / 4).
    RenderedFrame preview = numbered(8, 5);
    preview.fullWidth = 30, preview.fullHeight = 20, preview.divisor = 4;
    blitFrame(preview, 30, 20, canvas);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 30; ++x) {
            const uint8_t* p = pixel(canvas, 30, x, y);
            CHECK((p[0] == x / 4 && p[1] == y / 4 && p[3] == 255));
        }

    // A 10x10 frame in a 40x20 window: each of its pixels 4 wide and 2 high.
    blitFrame(numbered(10, 10), 40, 20, canvas);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 40; ++x) {
            const uint8_t* p = pixel(canvas, 40, x, y);
            CHECK((p[0] == x / 4 && p[1] == y / 2));
        }
}

TEST_CASE("window canvas: the backdrop before a frame, and the overlay over it") {
    std::vector<uint8_t> canvas;
    composeWindow(nullptr, 50, 40, {}, 1, canvas);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 50; ++x) {
            const uint8_t* p = pixel(canvas, 50, x, y);
            CHECK((p[0] == 48 && p[1] == 48 && p[2] == 52 && p[3] == 255));
        }
    RenderedFrame f = numbered(50, 40);
    OverlayText text;
    text.status = "t=0.000";
    composeWindow(&f, 50, 40, text, 1, canvas);
    // Above the status line, the frame untouched; along the bottom, something drawn over it.
    const int top = 40 - statusHeight(1);
    int changed = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 50; ++x) {
            const uint8_t* p = pixel(canvas, 50, x, y);
            const bool same = p[0] == x && p[1] == y && p[2] == x + y;
            if (y < top)
                CHECK(same);
            else
                changed += !same;
        }
    CHECK(changed > 50);
}
