// The banded PNG encoder against OpenImageIO, its independent oracle: the same floats written
// by OpenImageIO's own PNG writer and by PngBands must read back (through OpenImageIO's
// reader, libpng and zlib checking every CRC and the Adler-32) as the same samples and the
// same attributes; and quantizeRow must round as OpenImageIO's float conversion does.
#include "runtime/output/ImageIO.h"
#include "runtime/output/PngBands.h"

#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <limits>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <random>
#include <vector>
#include <zlib.h>

using namespace moire;

namespace {

OIIO::ImageSpec specFor(int w, int h, int bits) {
    OIIO::ImageSpec spec(w, h, 4, bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
    spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("Software", "moire test");
    spec.attribute("XResolution", 300.0f);
    spec.attribute("YResolution", 300.0f);
    spec.attribute("ResolutionUnit", "inch");
    return spec;
}

// What OpenImageIO's PNG writer makes of `rgba` (floats already in [0, 1]).
std::vector<unsigned char> oiioPng(const OIIO::ImageSpec& spec, const float* rgba) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    REQUIRE(out);
    REQUIRE(out->set_ioproxy(&proxy));
    REQUIRE(out->open("oracle.png", spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, rgba));
    REQUIRE(out->close());
    return bytes;
}

struct Decoded {
    OIIO::ImageSpec spec;
    std::vector<uint16_t> samples; // as stored, 8- or 16-bit
};

Decoded decode(std::vector<unsigned char>& png) {
    // OpenImageIO 2.4 drops the proxy given to ImageInput::open beside a config, so the
    // proxy goes in the config.
    OIIO::Filesystem::IOMemReader reader(png.data(), png.size());
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    void* proxy = &reader;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    auto in = OIIO::ImageInput::create("png");
    REQUIRE(in);
    OIIO::ImageSpec opened;
    REQUIRE_MESSAGE(in->open("memory.png", opened, config), in->geterror());
    Decoded d;
    d.spec = in->spec();
    d.samples.resize(static_cast<size_t>(d.spec.width) * d.spec.height * d.spec.nchannels);
    REQUIRE_MESSAGE(
        in->read_image(0, 0, 0, d.spec.nchannels, OIIO::TypeDesc::UINT16, d.samples.data()),
        in->geterror());
    CHECK(!in->has_error());
    return d;
}

// The zlib stream of a PNG's IDAT chunks, inflated: zlib checks the Adler-32.
std::vector<unsigned char> inflatePixels(const std::vector<unsigned char>& png, size_t expected) {
    std::vector<unsigned char> z;
    for (size_t at = 8; at + 12 <= png.size();) {
        const uint32_t n = uint32_t{png[at]} << 24 | uint32_t{png[at + 1]} << 16 |
                           uint32_t{png[at + 2]} << 8 | png[at + 3];
        if (std::memcmp(&png[at + 4], "IDAT", 4) == 0)
            z.insert(z.end(), png.begin() + at + 8, png.begin() + at + 8 + n);
        at += 12 + n;
    }
    std::vector<unsigned char> out(expected + 16);
    uLongf size = out.size();
    REQUIRE(uncompress(out.data(), &size, z.data(), z.size()) == Z_OK);
    out.resize(size);
    return out;
}

} // namespace

TEST_CASE("quantizeRow rounds as OpenImageIO converts float to 8 and 16 bits") {
    std::vector<float> values = {0.0f,
                                 1.0f,
                                 -0.0f,
                                 -1.0f,
                                 2.0f,
                                 1e-30f,
                                 0.99999994f,
                                 std::numeric_limits<float>::infinity(),
                                 -std::numeric_limits<float>::infinity(),
                                 std::numeric_limits<float>::quiet_NaN()};
    // Every rounding tie of both scales, and a few floats either side of each.
    for (double scale : {255.0, 65535.0})
        for (int k = 0; k < static_cast<int>(scale); ++k) {
            float v = static_cast<float>((k + 0.5) / scale);
            for (int i = 0; i < 3; ++i) v = std::nextafter(v, 0.0f);
            for (int i = 0; i < 7; ++i, v = std::nextafter(v, 2.0f)) values.push_back(v);
        }
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> any(-0.1f, 1.1f);
    for (int i = 0; i < 100000; ++i) values.push_back(any(rng));
    while (values.size() % 4) values.push_back(0.5f);
    const int width = static_cast<int>(values.size() / 4);

    // writeImage clamped to [0, 1] with std::clamp before OpenImageIO converted.
    std::vector<float> clamped(values.size());
    for (size_t i = 0; i < values.size(); ++i) clamped[i] = std::clamp(values[i], 0.0f, 1.0f);
    for (int bits : {8, 16}) {
        CAPTURE(bits);
        std::vector<unsigned char> ours(values.size() * bits / 8);
        quantizeRow(values.data(), width, 4, bits, ours.data());
        std::vector<uint16_t> oracle(values.size());
        if (bits == 8) {
            std::vector<uint8_t> b(values.size());
            REQUIRE(OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, clamped.data(),
                                               OIIO::TypeDesc::UINT8, b.data(),
                                               static_cast<int>(values.size())));
            std::copy(b.begin(), b.end(), oracle.begin());
        } else {
            REQUIRE(OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, clamped.data(),
                                               OIIO::TypeDesc::UINT16, oracle.data(),
                                               static_cast<int>(values.size())));
        }
        int wrong = 0;
        for (size_t i = 0; i < values.size(); ++i) {
            const unsigned got =
                bits == 8 ? ours[i] : (unsigned{ours[2 * i]} << 8 | ours[2 * i + 1]);
            if (got != oracle[i] && ++wrong <= 5)
                FAIL_CHECK("value " << values[i] << ": " << got << ", OpenImageIO " << oracle[i]);
        }
        CHECK(wrong == 0);
    }
}

TEST_CASE("a PNG encoded in bands reads back as OpenImageIO's writer wrote it") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    struct Shape {
        int w, h, bandRows;
    };
    for (Shape s : {Shape{1, 1, 64}, Shape{7, 1, 64}, Shape{1, 9, 4}, Shape{37, 23, 4},
                    Shape{130, 70, 64}, Shape{64, 128, 64}})
        for (int bits : {8, 16})
            for (int level : {0, 1, 6}) {
                CAPTURE(s.w);
                CAPTURE(s.h);
                CAPTURE(bits);
                CAPTURE(level);
                // Five channels a pixel, as a kernel with an extra output gives: only RGBA
                // is written. Smooth gradients with noise, so every filter gets chosen.
                const int channels = 5;
                std::vector<float> frame(static_cast<size_t>(s.w) * s.h * channels);
                std::vector<float> rgba(static_cast<size_t>(s.w) * s.h * 4);
                for (int y = 0; y < s.h; ++y)
                    for (int x = 0; x < s.w; ++x)
                        for (int c = 0; c < channels; ++c) {
                            const float smooth = (x + 2.0f * y + c) / (s.w + 2.0f * s.h + 4);
                            const float v = (x * 3 + y) % 5 == 0 ? unit(rng) : smooth;
                            frame[(static_cast<size_t>(y) * s.w + x) * channels + c] = v;
                            if (c < 4) rgba[(static_cast<size_t>(y) * s.w + x) * 4 + c] = v;
                        }
                const OIIO::ImageSpec spec = specFor(s.w, s.h, bits);
                std::vector<unsigned char> oracle = oiioPng(spec, rgba.data());

                PngBands png(s.w, s.h, bits, level, s.bandRows);
                CHECK(png.bands() == (s.h + s.bandRows - 1) / s.bandRows);
                for (int b = png.bands() - 1; b >= 0; --b) // any order
                    png.encode(b,
                               frame.data() + static_cast<size_t>(png.firstRow(b)) * s.w * channels,
                               static_cast<size_t>(s.w) * channels, channels);
                std::vector<unsigned char> ours = png.file(pngChunksBeforeData(oracle));

                const Decoded want = decode(oracle), got = decode(ours);
                CHECK(got.spec.width == s.w);
                CHECK(got.spec.height == s.h);
                CHECK(got.spec.format == want.spec.format);
                CHECK(got.spec.nchannels == 4);
                CHECK(got.samples == want.samples);
                CHECK(got.spec.extra_attribs.size() == want.spec.extra_attribs.size());
                for (const OIIO::ParamValue& p : want.spec.extra_attribs) {
                    CAPTURE(p.name());
                    CHECK(got.spec.get_string_attribute(p.name()) ==
                          want.spec.get_string_attribute(p.name()));
                }

                // The filter of every row is a PNG filter, and the first row of each band
                // does not look at the row above, which another thread may not have made.
                const size_t rowBytes = 1 + static_cast<size_t>(s.w) * 4 * bits / 8;
                const std::vector<unsigned char> raw = inflatePixels(ours, rowBytes * s.h);
                REQUIRE(raw.size() == rowBytes * s.h);
                for (int y = 0; y < s.h; ++y) {
                    CAPTURE(y);
                    CHECK(raw[y * rowBytes] <= 4);
                    if (y % s.bandRows == 0) CHECK(raw[y * rowBytes] <= 1);
                }
            }
}

TEST_CASE("writeImage's PNG keeps the depth, the resolution and the colour space") {
    Image img(19, 11, 4);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = static_cast<float>(i % 257) / 256; // products exact in float
    for (PixelDepth depth : {PixelDepth::U8, PixelDepth::U16})
        for (int threads : {1, 3}) {
            WriteOptions wo;
            wo.depth = depth;
            wo.dpi = 600;
            wo.threads = threads;
            std::vector<unsigned char> bytes = encodeImage("x.png", "png", img, wo);
            const Decoded d = decode(bytes);
            CHECK(d.spec.format ==
                  (depth == PixelDepth::U8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16));
            CHECK(d.spec.get_float_attribute("XResolution") == doctest::Approx(600));
            CHECK(d.spec.get_string_attribute("ResolutionUnit") == "inch");
            CHECK(d.spec.get_string_attribute("oiio:ColorSpace") == "sRGB");
            const double scale = depth == PixelDepth::U8 ? 255.0 : 65535.0;
            // decode reads every file at 16 bits: an 8-bit sample comes back times 257.
            const long widen = depth == PixelDepth::U8 ? 257 : 1;
            for (size_t i = 0; i < img.pixels.size(); ++i)
                CHECK(d.samples[i] == std::lround(img.pixels[i] * scale) * widen);
        }
}

TEST_CASE("pngChunksBeforeData refuses what is not a PNG") {
    CHECK_THROWS(pngChunksBeforeData({1, 2, 3}));
    CHECK_THROWS(PngBands(0, 4, 8, 6));
    CHECK_THROWS(PngBands(4, 4, 12, 6));
}

// The chunks moire writes itself (so that a PNG never loads OpenImageIO) are byte for byte
// those OpenImageIO's writer gives the same spec, at every resolution and bit depth.
TEST_CASE("pngColourChunks are OpenImageIO's chunks for the same spec") {
    const float pixel[4] = {0.25f, 0.5f, 0.75f, 1.0f};
    for (int bits : {8, 16})
        for (double dpi : {0.0, 72.0, 96.0, 150.0, 299.7, 300.0, 600.0, 2400.0, 1.0}) {
            CAPTURE(bits);
            CAPTURE(dpi);
            OIIO::ImageSpec spec(1, 1, 4,
                                 bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
            spec.alpha_channel = 3;
            spec.attribute("oiio:UnassociatedAlpha", 1);
            spec.attribute("oiio:ColorSpace", "sRGB");
            spec.attribute("Software", "moire 9.8.7");
            if (dpi > 0) {
                spec.attribute("XResolution", static_cast<float>(dpi));
                spec.attribute("YResolution", static_cast<float>(dpi));
                spec.attribute("ResolutionUnit", "inch");
            }
            CHECK(pngColourChunks(dpi, "moire 9.8.7") == pngChunksBeforeData(oiioPng(spec, pixel)));
            // A region of a larger frame: its corner as OpenImageIO's origin, its frame's size
            // as a text attribute.
            spec.x = 1200;
            spec.y = 77;
            spec.attribute(kPngFullSizeKey, "4000x3000");
            CHECK(pngColourChunks(dpi, "moire 9.8.7", PngPlacement{1200, 77, 4000, 3000}) ==
                  pngChunksBeforeData(oiioPng(spec, pixel)));
        }
}

// A PNG's resolution read back (pixels per metre) and written again keeps its pHYs: every
// value up to 400,000 per metre (over 10,000 dpi), and the whole dpi values come back whole.
TEST_CASE("pngDpiOf gives back a resolution that pHYs holds as the same pixels per metre") {
    int wrong = 0;
    for (uint32_t perMetre = 1; perMetre <= 400000; ++perMetre)
        wrong += pngPixelsPerMetre(pngDpiOf(perMetre)) != perMetre;
    CHECK(wrong == 0);
    for (double dpi : {1.0, 72.0, 96.0, 150.0, 300.0, 600.0, 1200.0, 2400.0})
        CHECK(pngDpiOf(pngPixelsPerMetre(dpi)) == dpi);
    CHECK(pngPixelsPerMetre(300.0) == 11811);
}
