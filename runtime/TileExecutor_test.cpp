// The tile executor: every pixel once, whatever the tiling and thread count; and a frame
// abandoned part way when asked. runKernelInBands: every band once with every pixel of it; a
// failure in the sink stops the frame; a cancelled frame says so.
#include "runtime/TileExecutor.h"

#include <atomic>
#include <chrono>
#include <doctest/doctest.h>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

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

TEST_CASE("runKernelInBands hands every band over once, its rows in order, every pixel in it") {
    const int w = 131, h = 77;
    for (bool whole : {false, true}) // a GPU kernel's bands come from the calling thread
        for (int bandRows : {1, 16, 64, 100})
            for (int threads : {1, 2, 5})
                for (auto [tile, step] : {std::pair{8, 0}, {64, 0}, {8, 3}, {64, 8}}) {
                    CAPTURE(whole);
                    CAPTURE(step);
                    CAPTURE(bandRows);
                    CAPTURE(threads);
                    CAPTURE(tile);
                    CoordinateKernel k(whole);
                    ExecOptions o;
                    o.threads = threads;
                    o.tileSize = tile;
                    std::vector<int> seen((h + bandRows - 1) / bandRows, 0);
                    std::mutex m;
                    int wrong = 0;
                    BandTimes times;
                    CHECK(runKernelInBands(
                        k, KernelFrame{nullptr, w, h}, o, bandRows,
                        [&](int band, int first, int count, const float* rows, size_t stride) {
                            CHECK(stride == size_t{w} * 2);
                            int bad = 0;
                            const int y0 = band * bandRows + first;
                            for (int y = y0; y < y0 + count; ++y)
                                for (int x = 0; x < w; ++x) {
                                    const float* p = rows + (y - y0) * stride + x * 2;
                                    bad += p[0] != x || p[1] != y;
                                }
                            std::lock_guard<std::mutex> lock(m);
                            // Each band's steps in order, the last ending at the band's end.
                            int& next = seen.at(static_cast<size_t>(band));
                            bad += first != next;
                            next = first + count;
                            wrong += bad;
                        },
                        &times, step));
                    CHECK(wrong == 0);
                    for (size_t b = 0; b < seen.size(); ++b)
                        CHECK(seen[b] == std::min(bandRows, h - static_cast<int>(b) * bandRows));
                    CHECK(times.kernel >= 0.0);
                    CHECK(times.sink >= 0.0);
                }
}

TEST_CASE("runKernelInBands: no worker runs more than `threads` bands past a slow band") {
    // Band 0 is slow in the sink; until it is handed over whole, bands past `threads` must
    // not start, so that a sink keeping bands until those above them come holds a few.
    for (int threads : {2, 3}) {
        CAPTURE(threads);
        CoordinateKernel k(false);
        ExecOptions o;
        o.threads = threads;
        std::atomic<bool> firstDone{false};
        std::atomic<int> furthest{0}, bands{0};
        CHECK(runKernelInBands(
            k, KernelFrame{nullptr, 32, 400}, o, 4,
            [&](int band, int first, int count, const float*, size_t) {
                if (band == 0) {
                    std::this_thread::sleep_for(std::chrono::milliseconds(30));
                    if (first + count == 4) firstDone.store(true);
                } else if (!firstDone.load()) {
                    int f = furthest.load();
                    while (band > f && !furthest.compare_exchange_weak(f, band)) {
                    }
                }
                if (first + count == 4) ++bands;
            },
            nullptr, 1));
        CHECK(bands.load() == 100);
        CHECK(furthest.load() <= threads);
    }
}

TEST_CASE("runKernelInBands stops on the sink's failure and rethrows it") {
    CoordinateKernel k(false);
    ExecOptions o;
    o.threads = 1;
    std::atomic<int> calls{0};
    CHECK_THROWS_AS(runKernelInBands(k, KernelFrame{nullptr, 64, 640}, o, 8,
                                     [&](int band, int, int, const float*, size_t) {
                                         ++calls;
                                         if (band == 2) throw std::runtime_error("disk full");
                                     }),
                    std::runtime_error);
    CHECK(calls.load() == 3);
}

TEST_CASE("runKernelInBands: a cancelled frame hands over no band after the cancel") {
    CoordinateKernel k(false);
    ExecOptions o;
    o.threads = 2;
    std::atomic<int> bands{0};
    std::atomic<bool> stop{false};
    o.cancelled = [&] { return stop.load(); };
    CHECK_FALSE(runKernelInBands(k, KernelFrame{nullptr, 64, 6400}, o, 8,
                                 [&](int, int, int, const float*, size_t) {
                                     if (++bands == 3) stop.store(true);
                                 }));
    // The two workers may each have been in a band when the third arrived.
    CHECK(bands.load() <= 4);
}

} // namespace moire
