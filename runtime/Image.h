// An image in memory: interleaved float channels, rows top to bottom. The renderer's RGBA
// output is sRGB-encoded straight colour with alpha, as composited.
#pragma once

#include <cstddef>
#include <vector>

namespace moire {

struct Image {
    int width = 0, height = 0, channels = 4;
    std::vector<float> pixels;

    Image() = default;
    Image(int w, int h, int c)
        : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c, 0.0f) {}
    float* row(int y) { return pixels.data() + static_cast<size_t>(y) * width * channels; }
    const float* row(int y) const {
        return pixels.data() + static_cast<size_t>(y) * width * channels;
    }
    float at(int x, int y, int c) const { return row(y)[x * channels + c]; }
};

} // namespace moire
