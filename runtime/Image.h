// An image in memory: interleaved float channels, rows top to bottom. The renderer's RGBA
// output is sRGB-encoded straight colour with alpha, as composited.
#pragma once

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace moire {

// std::allocator, except that an element made without a value is left uninitialised (a
// vector resized to n floats holds whatever memory held), where std::vector would write
// zeros first.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = UninitialisedAllocator<U>;
    };
    UninitialisedAllocator() = default;
    template <class U>
    UninitialisedAllocator(const UninitialisedAllocator<U>&) {}
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0)
            ::new (static_cast<void*>(p)) U;
        else
            ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

struct Image {
    using Pixels = std::vector<float, UninitialisedAllocator<float>>;
    int width = 0, height = 0, channels = 4;
    Pixels pixels;

    Image() = default;
    // Every channel of every pixel 0.
    Image(int w, int h, int c)
        : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c, 0.0f) {}
    // Pixels left as memory held them, for a producer that writes every one (a kernel's
    // frame): filling a 1080p frame with zeros first cost more than a fast kernel drawing it.
    static Image forOverwrite(int w, int h, int c) {
        Image img;
        img.width = w, img.height = h, img.channels = c;
        img.pixels.resize(static_cast<size_t>(w) * h * c);
        return img;
    }
    float* row(int y) { return pixels.data() + static_cast<size_t>(y) * width * channels; }
    const float* row(int y) const {
        return pixels.data() + static_cast<size_t>(y) * width * channels;
    }
    float at(int x, int y, int c) const { return row(y)[x * channels + c]; }
};

} // namespace moire
