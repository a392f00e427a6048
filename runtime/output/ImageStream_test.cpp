// An image streamed row by row (ImageStream) is the file writeImage makes of the whole
// image: for every format and depth, with the rows handed over out of order from several
// threads, byte for byte but the time it was written (so the pixels, the resolution, the
// colour space and the software tag agree); a stream dropped before finish() leaves nothing behind.
#include "runtime/output/ImageStream.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <doctest/doctest.h>
#include <filesystem>
#include <OpenImageIO/imageio.h>
#include <random>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace moire;

namespace {

// Straight sRGB RGBA with values past both ends (the writers clamp them), a smooth ramp and
// noise, so that every sample value class is met.
Image pattern(int w, int h) {
    Image img(w, h, 4);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> noise(-0.2f, 1.2f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.row(y) + static_cast<size_t>(x) * 4;
            p[0] = static_cast<float>(x) / w;
            p[1] = noise(rng);
            p[2] = static_cast<float>(y) / h * 1.3f - 0.1f;
            p[3] = (x + y) % 5 == 0 ? noise(rng) : 1.0f;
        }
    return img;
}

// Hands `img` to `stream` as runKernelInBands might and then some: the bands (bandRows()
// rows) in a shuffled order on three threads, each band's rows by one thread in runs of 1 to
// 37 rows, themselves shuffled (so rows come before those above them), with a stride wider
// than the row (a kernel's extra outputs). `anyThread`: the runs of all bands shuffled
// together, so that a band's rows come from several threads (which TIFF, EXR and JPEG take;
// a PNG band is encoded on one thread, PngStream).
void feed(ImageStream& stream, const Image& img, bool anyThread = false) {
    const int extra = 2, channels = img.channels + extra;
    std::vector<float> wide(static_cast<size_t>(img.width) * img.height * channels, 0.5f);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            std::memcpy(&wide[(static_cast<size_t>(y) * img.width + x) * channels],
                        img.row(y) + static_cast<size_t>(x) * img.channels,
                        sizeof(float) * img.channels);
    std::mt19937 rng(11);
    std::vector<std::vector<std::pair<int, int>>> bands;
    for (int top = 0; top < img.height; top += stream.bandRows()) {
        const int bottom = std::min(img.height, top + stream.bandRows());
        std::vector<std::pair<int, int>> runs;
        for (int y = top; y < bottom;) {
            const int n = std::min(bottom - y, 1 + static_cast<int>(rng() % 37));
            runs.emplace_back(y, n);
            y += n;
        }
        std::shuffle(runs.begin(), runs.end(), rng);
        bands.push_back(runs);
    }
    std::shuffle(bands.begin(), bands.end(), rng);
    if (anyThread) {
        std::vector<std::vector<std::pair<int, int>>> runs;
        for (const auto& band : bands)
            for (const auto& run : band) runs.push_back({run});
        std::shuffle(runs.begin(), runs.end(), rng);
        bands = runs;
    }
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i; (i = next.fetch_add(1)) < bands.size();)
            for (const auto& [y, n] : bands[i])
                stream.addRows(y, n, &wide[static_cast<size_t>(y) * img.width * channels],
                               static_cast<size_t>(img.width) * channels, channels);
    };
    std::thread a(worker), b(worker);
    worker();
    a.join();
    b.join();
}

} // namespace

TEST_CASE("an image streamed out of order is the file writeImage makes, every format and depth") {
    test::TempDir dir("stream");
    const Image img = pattern(203, 157);
    struct Case {
        const char* ext;
        PixelDepth depth;
    };
    for (const Case c :
         {Case{"png", PixelDepth::U8}, Case{"png", PixelDepth::U16}, Case{"tif", PixelDepth::U8},
          Case{"tif", PixelDepth::U16}, Case{"exr", PixelDepth::Half},
          Case{"exr", PixelDepth::Float}, Case{"jpg", PixelDepth::Default}}) {
        for (const double dpi : {0.0, 300.0}) {
            CAPTURE(c.ext);
            CAPTURE(static_cast<int>(c.depth));
            CAPTURE(dpi);
            WriteOptions wo;
            wo.depth = c.depth;
            wo.dpi = dpi;
            const std::string whole = dir.file(std::string("whole.") + c.ext);
            const std::string streamed = dir.file(std::string("stream.") + c.ext);
            writeImage(whole, img, wo);
            auto stream =
                openImageStream(streamed, imageFormatOf(streamed), img.width, img.height, wo);
            feed(*stream, img, std::string(c.ext) != "png" && dpi > 0);
            stream->finish();
            CHECK(test::imageBytesWithoutTime(streamed) == test::imageBytesWithoutTime(whole));
            const Image a = readImage(whole), b = readImage(streamed);
            REQUIRE(a.width == b.width);
            CHECK(a.pixels == b.pixels);
            CHECK(dir.names() == std::vector<std::string>{std::string("stream.") + c.ext,
                                                          std::string("whole.") + c.ext});
            fs::remove(whole);
            fs::remove(streamed);
        }
    }
}

TEST_CASE("a stream dropped before finish() leaves no file and no temporary") {
    test::TempDir dir("dropped");
    const Image img = pattern(64, 150);
    for (const char* ext : {"png", "tif", "exr", "jpg"}) {
        CAPTURE(ext);
        const std::string path = dir.file(std::string("out.") + ext);
        {
            auto stream = openImageStream(path, imageFormatOf(path), img.width, img.height, {});
            stream->addRows(0, 100, img.row(0), static_cast<size_t>(img.width) * 4, 4);
            // An earlier file under the same name stays as it was.
        }
        CHECK(dir.names().empty());
        dir.write(std::string("out.") + ext, "earlier");
        {
            auto stream = openImageStream(path, imageFormatOf(path), img.width, img.height, {});
            stream->addRows(64, 86, img.row(64), static_cast<size_t>(img.width) * 4, 4);
            CHECK_THROWS_AS(stream->finish(), IoError); // rows 0 to 63 never came
        }
        CHECK(test::readFile(path) == "earlier");
        CHECK(dir.names() == std::vector<std::string>{std::string("out.") + ext});
        fs::remove(path);
    }
}

TEST_CASE("a stream refuses a size its format cannot hold, naming the format") {
    test::TempDir dir("limits");
    auto refused = [&](const std::string& name, int w, int h) {
        try {
            openImageStream(dir.file(name), imageFormatOf(name), w, h, {});
        } catch (const IoError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(refused("a.jpg", 65501, 10).find("JPEG holds at most 65500 pixels a side") !=
          std::string::npos);
    CHECK(refused("a.jpg", 10, 65501).find("use .tif or .exr") != std::string::npos);
    CHECK(refused("a.png", 1000001, 1).find("over 1000000 pixels a side") != std::string::npos);
    CHECK(dir.names().empty());
}

TEST_CASE("a streamed EXR records its place in a larger frame: the data window in the display "
          "window") {
    // OpenEXR's header holds dataWindow and displayWindow as box2i: xMin, yMin, xMax, yMax.
    test::TempDir dir("placed");
    const Image img = pattern(40, 30);
    WriteOptions wo;
    wo.originX = 100;
    wo.originY = 60;
    wo.fullWidth = 400;
    wo.fullHeight = 300;
    const std::string path = dir.file("tile.exr");
    auto stream = openImageStream(path, "exr", img.width, img.height, wo);
    feed(*stream, img);
    stream->finish();
    const std::string bytes = test::readFile(path);
    auto box = [&](const std::string& name) {
        const std::string key = name + std::string("\0box2i\0", 7);
        const size_t at = bytes.find(key);
        REQUIRE(at != std::string::npos);
        std::array<int32_t, 4> v{};
        std::memcpy(v.data(), bytes.data() + at + key.size() + 4, sizeof v);
        return v;
    };
    CHECK(box("dataWindow") == std::array<int32_t, 4>{100, 60, 139, 89});
    CHECK(box("displayWindow") == std::array<int32_t, 4>{0, 0, 399, 299});
    const Image back = readImage(path);
    CHECK(back.width == 40);
    CHECK(back.height == 30);
}

TEST_CASE("a JPEG keeps --dpi: JFIF's density in dots per inch, as OpenImageIO reads it back") {
    // JFIF's APP0 segment: FF D8, FF E0, length (2), "JFIF\0", version (2), units (1: dots
    // per inch; 0 would leave only an aspect ratio, which print software reads as 72 dpi),
    // then the X and Y density, big-endian.
    test::TempDir dir("dpi");
    const Image img = pattern(30, 20);
    WriteOptions wo;
    wo.dpi = 300;
    const std::string whole = dir.file("whole.jpg"), streamed = dir.file("stream.jpg");
    writeImage(whole, img, wo);
    auto stream = openImageStream(streamed, "jpeg", img.width, img.height, wo);
    feed(*stream, img);
    stream->finish();
    for (const std::string& path : {whole, streamed}) {
        CAPTURE(path);
        const std::string b = test::readFile(path);
        REQUIRE(b.size() > 20);
        CHECK(b.compare(6, 5, std::string("JFIF\0", 5)) == 0);
        CHECK(static_cast<unsigned char>(b[13]) == 1);
        CHECK((static_cast<unsigned char>(b[14]) << 8 | static_cast<unsigned char>(b[15])) == 300);
        CHECK((static_cast<unsigned char>(b[16]) << 8 | static_cast<unsigned char>(b[17])) == 300);
        auto in = OIIO::ImageInput::open(path);
        REQUIRE(in);
        CHECK(in->spec().get_float_attribute("XResolution") == 300.0f);
        CHECK(in->spec().get_float_attribute("YResolution") == 300.0f);
        CHECK(in->spec().get_string_attribute("ResolutionUnit") == "in");
    }
}
