// toByte against the writer it stands in for: floats on every rounding tie of the 8-bit
// scale (and just either side of one) written as a PNG by writeImage, read back as bytes by
// OpenImageIO, and compared with toByte of the same floats and with the viewer's bytes.
#include "runtime/output/ImageIO.h"
#include "runtime/view/FrameRenderer.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <OpenImageIO/imageio.h>
#include <vector>

using namespace moire;

namespace {

// The float nearest (k + 0.5) / 255 whose product with 255, in float, is exactly k + 0.5:
// the value on which round-half-up, half-away and half-to-even part ways.
float tie(int k) {
    const float target = static_cast<float>(k) + 0.5f;
    float v = static_cast<float>((k + 0.5) / 255.0);
    for (int step = 0; step < 8 && v * 255.0f != target; ++step)
        v = std::nextafter(v, v * 255.0f < target ? 2.0f : 0.0f);
    return v;
}

// The 8-bit values OpenImageIO reads from a PNG, RGBA.
std::vector<uint8_t> readBytes(const std::string& path, int count) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    REQUIRE(in);
    std::vector<uint8_t> bytes(static_cast<size_t>(count));
    REQUIRE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, bytes.data()));
    return bytes;
}

} // namespace

TEST_CASE("toByte rounds as the 8-bit PNG writer does, ties included") {
    std::vector<float> values;
    for (int k = 0; k < 255; ++k) {
        const float t = tie(k);
        REQUIRE(t * 255.0f == static_cast<float>(k) + 0.5f);
        values.push_back(t);
        values.push_back(std::nextafter(t, 0.0f));
        values.push_back(std::nextafter(t, 1.0f));
    }
    for (int i = 0; i <= 1000; ++i) values.push_back(static_cast<float>(i) / 1000.0f);
    for (float v : {-1.0f, -0.0f, 1.0f, 1.5f, INFINITY, -INFINITY, NAN}) values.push_back(v);
    while (values.size() % 4 != 0) values.push_back(0.5f);

    // One channel a value, four values a pixel, in one row.
    const int width = static_cast<int>(values.size() / 4);
    Image img(width, 1, 4);
    std::copy(values.begin(), values.end(), img.pixels.begin());
    test::TempDir dir("rounding");
    const std::string path = dir.file("ties.png");
    writeImage(path, img);
    const std::vector<uint8_t> written = readBytes(path, static_cast<int>(values.size()));

    int ties = 0, tiesUp = 0;
    for (size_t i = 0; i < values.size(); ++i) {
        CAPTURE(i);
        CAPTURE(values[i]);
        CHECK(toByte(values[i]) == written[i]);
        const float scaled = values[i] * 255.0f;
        if (i < 3 * 255 && i % 3 == 0) {
            ++ties;
            tiesUp += written[i] == static_cast<int>(scaled) + 1;
        }
    }
    // The viewer's window shows the same bytes.
    std::vector<uint8_t> shown(values.size());
    view::toRgba8(img.pixels.data(), 4, static_cast<size_t>(width), shown.data());
    CHECK(shown == written);
    // Every tie goes up, even k + 0.5 with k even: not to even.
    CHECK(ties == 255);
    CHECK(tiesUp == 255);
}
