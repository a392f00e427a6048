#include "runtime/vulkan/Bands.h"

#include <algorithm>
#include <fmt/format.h>

namespace moire::vk {

std::vector<TileRect> planChunks(TileRect rect, int numOutputs, const ChunkLimits& limits) {
    std::vector<TileRect> out;
    const int64_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
    if (w <= 0 || h <= 0) return out;
    const uint64_t pixelBytes = static_cast<uint64_t>(std::max(numOutputs, 1)) * sizeof(float);
    // The shader indexes its output with a 32-bit int: (gy * w + gx) * n must stay below 2^31.
    const uint64_t maxBytes = std::min<uint64_t>(limits.maxBytes, uint64_t{1} << 31);
    const int64_t maxPixels = static_cast<int64_t>(maxBytes / pixelBytes);
    if (maxPixels < 1)
        throw BackendError(
            fmt::format("a pixel's {} outputs do not fit the device's {}-byte storage buffer limit",
                        numOutputs, limits.maxBytes));
    const int64_t maxW = static_cast<int64_t>(limits.maxGroupsX) * limits.localX;
    const int64_t maxH = static_cast<int64_t>(limits.maxGroupsY) * limits.localY;
    if (maxW < 1 || maxH < 1) throw BackendError("the device reports no compute workgroups");
    const int64_t cw = std::min({w, maxW, maxPixels});
    const int64_t ch = std::min({h, maxH, std::max<int64_t>(1, maxPixels / cw)});
    for (int64_t y = rect.y0; y < rect.y1; y += ch)
        for (int64_t x = rect.x0; x < rect.x1; x += cw)
            out.push_back(TileRect{static_cast<int>(x), static_cast<int>(y),
                                   static_cast<int>(std::min<int64_t>(x + cw, rect.x1)),
                                   static_cast<int>(std::min<int64_t>(y + ch, rect.y1))});
    return out;
}

} // namespace moire::vk
