// The tile executor: every pixel once, whatever the tiling and thread count; and a frame
// abandoned part way when asked.
#include "runtime/TileExecutor.h"

#include <atomic>
#include <doctest/doctest.h>

namespace moire {
namespace {

// Writes each pixel's own coordinates, and counts the tiles it was given.
class CoordinateKernel : public CompiledKernel {
  public:
    explicit CoordinateKernel(bool whole) : whole_(whole) {}
    void runTile(const KernelFrame&, TileRect t, float* out, size_t rowStride) const override {
        ++calls;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float* p = out + (y - t.y0) * rowStride + (x - t.x0) * 2;
                p[0] = static_cast<float>(x);
                p[1] = static_cast<float>(y);
            }
    }
    int numOutputs() const override { return 2; }
    bool wholeFrame() const override { return whole_; }
    mutable std::atomic<int> calls{0};

  private:
    bool whole_;
};

} // namespace

TEST_CASE("tile executor: every pixel once, on any tiling and thread count") {
    for (bool whole : {false, true})
        for (int threads : {1, 2, 5})
            for (int tile : {8, 64}) {
                CAPTURE(whole);
                CAPTURE(threads);
                CAPTURE(tile);
                CoordinateKernel k(whole);
                KernelFrame f{nullptr, 131, 77};
                ExecOptions o;
                o.threads = threads;
                o.tileSize = tile;
                Image img = runKernel(k, f, o);
                REQUIRE(img.width == 131);
                int wrong = 0;
                for (int y = 0; y < 77; ++y)
                    for (int x = 0; x < 131; ++x)
                        wrong += img.at(x, y, 0) != x || img.at(x, y, 1) != y;
                CHECK(wrong == 0);
            }
}

TEST_CASE("tile executor: a cancelled frame stops between tiles and comes back empty") {
    for (bool whole : {false, true}) {
        CAPTURE(whole);
        CoordinateKernel k(whole);
        KernelFrame f{nullptr, 640, 480};
        ExecOptions o;
        o.threads = 2;
        o.tileSize = 16; // 1200 tiles (16 bands for a whole-frame kernel)
        std::atomic<int> asked{0};
        o.cancelled = [&] { return ++asked > 3; };
        Image img = runKernel(k, f, o);
        CHECK(img.width == 0);
        CHECK(img.pixels.empty());
        CHECK(k.calls.load() <= 3 + o.threads); // each worker may finish the tile in hand
        CHECK(k.calls.load() < (whole ? 16 : 1200));
        // Not cancelled: the whole frame.
        o.cancelled = [] { return false; };
        CHECK(runKernel(k, f, o).width == 640);
    }
}

} // namespace moire
