#include "runtime/view/WindowCanvas.h"

#include <algorithm>
#include <cstring>

namespace moire::view {

void blitFrame(const RenderedFrame& f, int w, int h, std::vector<uint8_t>& canvas) {
    canvas.assign(static_cast<size_t>(w) * h * 4, 0);
    const bool preview = f.divisor > 1 && f.fullWidth == w && f.fullHeight == h;
    const int d = f.divisor;
    for (int y = 0; y < h; ++y) {
        const int sy = preview ? y / d : static_cast<int>(static_cast<int64_t>(y) * f.height / h);
        const uint8_t* src =
            f.rgba.data() + static_cast<size_t>(std::min(sy, f.height - 1)) * f.width * 4;
        uint8_t* dst = canvas.data() + static_cast<size_t>(y) * w * 4;
        if (!preview && f.width == w) {
            std::memcpy(dst, src, static_cast<size_t>(w) * 4);
            continue;
        }
        for (int x = 0; x < w; ++x) {
            const int sx =
                preview ? x / d : static_cast<int>(static_cast<int64_t>(x) * f.width / w);
            std::memcpy(dst + x * 4, src + std::min(sx, f.width - 1) * 4, 4);
        }
    }
    for (size_t i = 3; i < canvas.size(); i += 4) canvas[i] = 255;
}

void composeWindow(const RenderedFrame* shown, int w, int h, const OverlayText& text, int scale,
                   std::vector<uint8_t>& canvas) {
    if (shown) {
        blitFrame(*shown, w, h, canvas);
    } else {
        canvas.assign(static_cast<size_t>(w) * h * 4, 0);
        for (size_t i = 0; i < canvas.size(); i += 4)
            canvas[i] = 48, canvas[i + 1] = 48, canvas[i + 2] = 52, canvas[i + 3] = 255;
    }
    Canvas c{canvas.data(), w, h};
    drawOverlay(c, text, scale);
}

} // namespace moire::view
