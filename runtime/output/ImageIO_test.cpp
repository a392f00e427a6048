#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

// A deterministic RGBA ramp covering the whole range, with partial alpha.
Image ramp(int w, int h) {
    Image img(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.row(y) + x * 4;
            p[0] = static_cast<float>(x) / (w - 1);
            p[1] = static_cast<float>(y) / (h - 1);
            p[2] = static_cast<float>((x * 7 + y * 13) % 101) / 100.0f;
            p[3] = 0.25f + 0.75f * static_cast<float>(x + y) / (w + h - 2);
        }
    return img;
}

// Worst per-channel difference between `got` and `expect(v)` applied to the source.
template <class F>
double worst(const Image& src, const Image& got, int channels, F expect) {
    double w = 0.0;
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            for (int c = 0; c < channels; ++c)
                w = std::max(w, std::fabs(static_cast<double>(got.at(x, y, c)) -
                                          expect(src.at(x, y, c), c)));
    return w;
}

} // namespace

TEST_CASE("sRGB transfer functions invert each other and match their definition") {
    for (float v = 0.0f; v <= 1.0f; v += 0.01f) {
        CHECK(linearToSrgb(srgbToLinear(v)) == doctest::Approx(v).epsilon(1e-5));
    }
    CHECK(srgbToLinear(0.5f) ==
          doctest::Approx(std::pow((0.5 + 0.055) / 1.055, 2.4)).epsilon(1e-6));
    CHECK(srgbToLinear(0.02f) == doctest::Approx(0.02 / 12.92).epsilon(1e-6));
}

TEST_CASE("PNG, TIFF, EXR and JPEG round-trip at their depths") {
    test::TempDir dir("imageio");
    Image src = ramp(37, 23);
    auto same = [](float v, int) { return static_cast<double>(v); };
    // An integer format keeps every value to within half a step of its depth.
    const double step8 = 1.0 / 255, step16 = 1.0 / 65535;

    writeImage(dir.file("a.png"), src);
    CHECK(worst(src, readImage(dir.file("a.png")), 4, same) <= 0.5 * step8 + 1e-6);

    WriteOptions deep;
    deep.depth = PixelDepth::U16;
    writeImage(dir.file("b.png"), src, deep);
    CHECK(worst(src, readImage(dir.file("b.png")), 4, same) <= 0.5 * step16 + 1e-6);

    writeImage(dir.file("c.tif"), src); // TIFF defaults to 16 bits
    CHECK(worst(src, readImage(dir.file("c.tif")), 4, same) <= 0.5 * step16 + 1e-6);

    // EXR holds linear light: colour through the sRGB decoding, alpha as is.
    writeImage(dir.file("d.exr"), src);
    Image exr = readImage(dir.file("d.exr"));
    CHECK(worst(src, exr, 4, [](float v, int c) {
              return c < 3 ? (v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4)) : v;
          }) < 1e-6);

    WriteOptions half;
    half.depth = PixelDepth::Half;
    writeImage(dir.file("e.exr"), src, half);
    Image exrHalf = readImage(dir.file("e.exr"));
    CHECK(worst(exr, exrHalf, 4, [](float v, int) { return v; }) < 1e-3);

    // JPEG is lossy and has no alpha: on a smooth image the colour comes back close.
    Image smooth = ramp(37, 23);
    for (int y = 0; y < smooth.height; ++y)
        for (int x = 0; x < smooth.width; ++x) smooth.row(y)[x * 4 + 2] = 0.5f;
    writeImage(dir.file("f.jpg"), smooth);
    Image jpg = readImage(dir.file("f.jpg"));
    CHECK(jpg.width == src.width);
    CHECK(worst(smooth, jpg, 3, same) < 0.05);

    CHECK(dir.names().size() == 6); // no temporaries left behind
}

TEST_CASE(
    "depths a format cannot hold and unknown formats are refused before anything is written") {
    test::TempDir dir("imageio");
    Image src = ramp(4, 4);
    WriteOptions f;
    f.depth = PixelDepth::Float;
    CHECK_THROWS_AS(writeImage(dir.file("x.png"), src, f), IoError);
    WriteOptions u8;
    u8.depth = PixelDepth::U8;
    CHECK_THROWS_AS(writeImage(dir.file("x.exr"), src, u8), IoError);
    CHECK_THROWS_AS(writeImage(dir.file("x.bmpx"), src), IoError);
    CHECK(dir.names().empty());
}

TEST_CASE("a failed write leaves the existing target and no temporary file") {
    test::TempDir dir("imageio");
    Image src = ramp(8, 8);
    // The target is a directory: the image is written to a temporary, and the final rename
    // fails. The directory must survive and the temporary must be gone.
    fs::create_directories(dir.file("taken.png"));
    fs::path marker = dir.file("taken.png/keep");
    { std::ofstream(marker.string()) << "x"; }
    CHECK_THROWS_AS(writeImage(dir.file("taken.png"), src), IoError);
    CHECK(fs::exists(marker));
    CHECK(dir.names("taken.png").empty());

    // A directory that does not exist: a clear error, nothing created.
    CHECK_THROWS_AS(writeImage(dir.file("missing/sub/out.png"), src), IoError);
    CHECK_FALSE(fs::exists(dir.file("missing")));
}

TEST_CASE("an existing image is replaced whole") {
    test::TempDir dir("imageio");
    writeImage(dir.file("out.png"), ramp(5, 3));
    Image bigger = ramp(50, 30);
    writeImage(dir.file("out.png"), bigger);
    Image back = readImage(dir.file("out.png"));
    CHECK(back.width == 50);
    CHECK(back.height == 30);
    CHECK(dir.names("out.png").empty());
}
