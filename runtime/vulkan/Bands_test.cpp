// The chunk planner against the limits it must respect, with made-up device limits: no
// device needed.
#include "runtime/vulkan/Bands.h"

#include <doctest/doctest.h>
#include <vector>

using namespace moire;
using moire::vk::ChunkLimits;
using moire::vk::planChunks;

namespace {

// Every pixel of `rect` in exactly one chunk, and every chunk within the limits.
void checkPlan(TileRect rect, int n, const ChunkLimits& limits) {
    std::vector<TileRect> chunks = planChunks(rect, n, limits);
    const int w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
    std::vector<unsigned char> hits(static_cast<size_t>(w) * h, 0);
    for (const TileRect& c : chunks) {
        CAPTURE(c.x0);
        CAPTURE(c.y0);
        REQUIRE(c.x0 < c.x1);
        REQUIRE(c.y0 < c.y1);
        REQUIRE(c.x0 >= rect.x0);
        REQUIRE(c.y0 >= rect.y0);
        REQUIRE(c.x1 <= rect.x1);
        REQUIRE(c.y1 <= rect.y1);
        const uint64_t bytes = uint64_t(c.x1 - c.x0) * (c.y1 - c.y0) * n * sizeof(float);
        CHECK(bytes <= limits.maxBytes);
        CHECK((c.x1 - c.x0 + limits.localX - 1) / limits.localX <= limits.maxGroupsX);
        CHECK((c.y1 - c.y0 + limits.localY - 1) / limits.localY <= limits.maxGroupsY);
        for (int y = c.y0; y < c.y1; ++y)
            for (int x = c.x0; x < c.x1; ++x)
                ++hits[static_cast<size_t>(y - rect.y0) * w + (x - rect.x0)];
    }
    size_t wrong = 0;
    for (unsigned char v : hits) wrong += v != 1;
    CHECK(wrong == 0);
    // Row-major: each chunk starts at or after the previous one's rows.
    for (size_t i = 1; i < chunks.size(); ++i) CHECK(chunks[i].y0 >= chunks[i - 1].y0);
}

} // namespace

TEST_CASE("vulkan chunks: a print-size frame fits lavapipe's and a desktop GPU's limits") {
    // 7200 x 4800 RGBA is 553 MB of output; lavapipe binds at most 128 MiB, and the executor's
    // own budget is 64 MiB.
    const TileRect frame{0, 0, 7200, 4800};
    ChunkLimits lavapipe{64ull << 20, 65535, 65535};
    checkPlan(frame, 4, lavapipe);
    std::vector<TileRect> chunks = planChunks(frame, 4, lavapipe);
    CHECK(chunks.size() == 9); // 582 rows of 7200 pixels a chunk, whole rows
    CHECK(chunks[0].x1 - chunks[0].x0 == 7200);
    // With every layer's fields (4 + 4 per layer, say 12 outputs) the chunks get shorter.
    checkPlan(frame, 12, lavapipe);
    // The largest side moire accepts, on a device with the minimum workgroup count.
    checkPlan(TileRect{0, 0, 32768, 3}, 4, ChunkLimits{64ull << 20, 65535, 65535});
    checkPlan(TileRect{0, 0, 1000, 1000}, 4, ChunkLimits{64ull << 20, 16, 16}); // 128 px
}

TEST_CASE("vulkan chunks: small budgets split rows, and windows keep their offsets") {
    checkPlan(TileRect{0, 0, 150, 94}, 4, ChunkLimits{37 * 16, 65535, 65535});
    checkPlan(TileRect{41, 17, 94, 46}, 5, ChunkLimits{1000, 65535, 65535});
    checkPlan(TileRect{3, 5, 4, 6}, 4, ChunkLimits{16, 1, 1}); // one pixel, one chunk
    std::vector<TileRect> one = planChunks(TileRect{3, 5, 4, 6}, 4, ChunkLimits{16, 1, 1});
    REQUIRE(one.size() == 1);
    CHECK((one[0].x0 == 3 && one[0].y0 == 5 && one[0].x1 == 4 && one[0].y1 == 6));
}

TEST_CASE("vulkan chunks: nothing to do, or nothing that fits") {
    CHECK(planChunks(TileRect{5, 5, 5, 9}, 4, ChunkLimits{1 << 20, 65535, 65535}).empty());
    CHECK_THROWS_AS(planChunks(TileRect{0, 0, 8, 8}, 4, ChunkLimits{15, 65535, 65535}),
                    BackendError);
    CHECK_THROWS_AS(planChunks(TileRect{0, 0, 8, 8}, 4, ChunkLimits{1 << 20, 0, 0}), BackendError);
}
