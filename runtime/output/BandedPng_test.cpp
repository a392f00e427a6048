// A PNG streamed to its file as the bands come (BandedPng with an AtomicFile) is, byte for
// byte, the PNG made in memory (itself held to OpenImageIO's pixels in PngBands_test),
// whatever order the bands are added in and from however many threads; and a stream
// dropped before its end leaves no file.
#include "runtime/output/ImageIO.h"
#include "runtime/output/OutputFile.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <random>
#include <thread>

using namespace moire;

namespace {

Image noisy(int w, int h, unsigned seed) {
    Image img(w, h, 4);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f); // clamped on the way out
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w * 4; ++x) img.row(y)[x] = (x % 4 == 3 && y % 5 == 0) ? 1.0f : u(rng);
    return img;
}

void addBands(BandedPng& png, const Image& img, std::vector<int> order, int threads) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (size_t i = static_cast<size_t>(t); i < order.size(); i += threads)
                png.add(order[i], img.row(order[i] * png.bandRows()),
                        static_cast<size_t>(img.width) * 4, 4);
        });
    for (std::thread& t : pool) t.join();
}

} // namespace

TEST_CASE("a PNG streamed band by band is the PNG made in memory, in any order of bands") {
    test::TempDir dir("bandedpng");
    for (auto [w, h, bits] : {std::tuple{97, 300, 8}, {64, 64, 16}, {5, 1, 8}, {300, 129, 8}}) {
        const Image img = noisy(w, h, static_cast<unsigned>(w * h));
        WriteOptions wo;
        wo.depth = bits == 16 ? PixelDepth::U16 : PixelDepth::U8;
        wo.dpi = 300;
        BandedPng memory("m.png", w, h, wo);
        std::vector<int> order(static_cast<size_t>(memory.bands()));
        for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
        addBands(memory, img, order, 1);
        const std::vector<unsigned char> want = memory.file();

        std::mt19937 rng(7);
        for (int threads : {1, 3}) {
            std::shuffle(order.begin(), order.end(), rng);
            const std::string path = dir.file("s.png");
            AtomicFile file(path);
            BandedPng streamed(path, w, h, wo, &file);
            addBands(streamed, img, order, threads);
            streamed.finish();
            CAPTURE(w);
            CAPTURE(threads);
            const std::string got = test::readFile(path);
            CHECK(got == std::string(want.begin(), want.end()));
            CHECK(dir.names() == std::vector<std::string>{"s.png"});
        }
    }
}

TEST_CASE("a streamed PNG dropped before its end leaves no file and no temporary") {
    test::TempDir dir("bandedpng");
    const Image img = noisy(40, 200, 3);
    {
        AtomicFile file(dir.file("cut.png"));
        BandedPng png(dir.file("cut.png"), 40, 200, WriteOptions{}, &file);
        png.add(0, img.row(0), 40 * 4, 4); // one band of four, then abandoned
        CHECK(!dir.names().empty());       // the temporary exists meanwhile
    }
    CHECK(dir.names().empty());
    AtomicFile file(dir.file("early.png"));
    BandedPng png(dir.file("early.png"), 40, 200, WriteOptions{}, &file);
    CHECK_THROWS_AS(png.finish(), IoError); // bands missing
}

TEST_CASE("a PNG whose bands come a few rows at a time is the PNG of whole bands") {
    for (auto [w, h, bits] : {std::tuple{97, 300, 8}, {64, 70, 16}}) {
        const Image img = noisy(w, h, 11);
        WriteOptions wo;
        wo.depth = bits == 16 ? PixelDepth::U16 : PixelDepth::U8;
        BandedPng whole("w.png", w, h, wo), steps("s.png", w, h, wo);
        for (int band = 0; band < whole.bands(); ++band) {
            const float* top = img.row(band * whole.bandRows());
            const size_t stride = static_cast<size_t>(w) * 4;
            whole.add(band, top, stride, 4);
            const int rows = std::min(whole.bandRows(), h - band * whole.bandRows());
            for (int first = 0; first < rows; first += 5)
                steps.addRows(band, first, std::min(5, rows - first), top + first * stride, stride,
                              4);
        }
        CAPTURE(w);
        CHECK(steps.file() == whole.file());
    }
}
