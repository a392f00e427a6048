// PNG pixel data encoded in horizontal bands that are independent of each other, so that
// every core can filter and compress a band of its own (and, later, a band can be encoded as
// soon as the renderer has finished it). OpenImageIO's PNG writer runs zlib on one thread:
// at 7200x4800 that alone took 2.4 s against 0.5 s for the kernel on two cores.
//
// How the bands stay independent and the file stays one ordinary PNG:
//   - each band's rows are filtered on their own: a band's first row uses only filters that
//     do not look at the row above (None, Sub), the others choose among None, Sub, Up and
//     Paeth by the smallest sum of absolute differences (the PNG specification's suggested
//     heuristic);
//   - each band is a raw deflate stream of its own, ended with a sync flush (byte-aligned,
//     not final) except the last, which ends the stream; one after another they form one
//     deflate stream, since no band refers back into another;
//   - the zlib header goes before the first band and the Adler-32 of all the filtered bytes,
//     combined from the bands' own, after the last.
// The pixel values are those OpenImageIO's writer stored (quantizeRow rounds as its float
// conversion does; PngBands_test holds the two together); only the compressed bytes differ,
// as any two PNG encoders' do.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace moire {

class PngBands {
  public:
    // An RGBA image of width x height at `bits` (8 or 16) per channel, compressed at zlib
    // `level` (0-9), in bands of `bandRows` rows.
    PngBands(int width, int height, int bits, int level, int bandRows = 64);

    int bands() const { return static_cast<int>(bands_.size()); }
    int bandRows() const { return bandRows_; }
    // The band that holds the rows from y0 (a multiple of bandRows()).
    int firstRow(int band) const { return band * bandRows_; }
    int rowsIn(int band) const;

    // Encodes band `band` from its rows of straight RGBA in [0, 1] (`stride` floats from one
    // row to the next, `channels` floats a pixel, RGBA first). Bands may be encoded in any
    // order, from any threads, each once.
    void encode(int band, const float* rows, size_t stride, int channels);
    // The same a few rows at a time: `count` rows from the band's row `first`. A band's rows
    // come in order, all on one thread, which encodes no other band meanwhile; the call with
    // its last rows compresses it. Returns whether the band is done.
    bool encodeRows(int band, int first, int count, const float* rows, size_t stride, int channels);

    // The whole file: the signature, IHDR, `chunks` (whole chunks, as they go between IHDR and
    // the pixel data: colour space, text, resolution), the bands' pixel data, IEND. Every band
    // must have been encoded.
    std::vector<unsigned char> file(const std::vector<unsigned char>& chunks) const;

    // The same file in pieces, to be written as the bands come (BandedPng): head() is every
    // byte before the first band's data; bandData(band) that band's data as IDAT chunks (the
    // band encoded); tail() the Adler-32 of all the data and IEND (every band encoded).
    // release(band) frees a band's compressed bytes once they are written.
    std::vector<unsigned char> head(const std::vector<unsigned char>& chunks) const;
    std::vector<unsigned char> bandData(int band) const;
    std::vector<unsigned char> tail() const;
    void release(int band);

  private:
    struct Band {
        std::vector<unsigned char> deflated;
        uint32_t adler = 1;
        bool done = false;
    };
    int width_, height_, bits_, level_, bandRows_;
    std::vector<Band> bands_;
};

// A row of `width` pixels (`channels` floats each, RGBA first) as PNG samples at `bits` (8 or
// 16) per channel, RGBA: clamped to [0, 1] (NaN to 0), scaled by 255 or 65535 in float and
// rounded to nearest, ties away from zero, as OpenImageIO 2.4 converts float to uint8 and
// uint16 (see toByte in ImageIO.h); 16-bit samples big-endian. `out` holds width * 4 * bits / 8
// bytes.
void quantizeRow(const float* src, int width, int channels, int bits, unsigned char* out);

// Where a PNG sits in a larger frame (render --region): its top-left pixel in the frame, and
// the frame's size; fullWidth 0: the image is the whole frame.
struct PngPlacement {
    int x = 0, y = 0;
    int fullWidth = 0, fullHeight = 0;
};
// The text key that holds a placed PNG's full frame size, "WIDTHxHEIGHT" (PNG has no chunk
// for it; OpenImageIO reads it as an attribute of that name).
inline constexpr const char* kPngFullSizeKey = "moire:FullSize";

// Pixels per metre as a PNG's pHYs holds `dpi`: truncated, as OpenImageIO converts.
inline uint32_t pngPixelsPerMetre(double dpi) {
    return static_cast<uint32_t>(static_cast<float>(dpi) * (100.0 / 2.54));
}
// A resolution in dots per inch that pngPixelsPerMetre turns into `perMetre` again, so that
// a PNG read and written again keeps its pHYs (300 dpi is 11811 per metre, which reads back
// as 299.9994 dpi, which would be written as 11810): the shortest of a whole number, tenths
// and hundredths of a dot per inch that does, else the middle of the values that do.
inline double pngDpiOf(uint32_t perMetre) {
    const double exact = perMetre * 0.0254;
    for (double scale : {1.0, 10.0, 100.0}) {
        const double rounded = std::round(exact * scale) / scale;
        if (rounded > 0 && pngPixelsPerMetre(rounded) == perMetre) return rounded;
    }
    return (perMetre + 0.5) * 0.0254;
}

// The chunks moire writes between a PNG's IHDR and its pixel data: the sRGB colour space
// (sRGB, with gAMA and cHRM for readers that ignore it), the offset (oFFs, in pixels: the
// placement's corner, 0,0 for a whole frame), the resolution when `dpi` > 0, and text naming
// the colour space and the software (and a placed image's full size), the very chunks and
// bytes OpenImageIO 2.4's writer gives the same image (PngBands_test holds the two together),
// so that a file reads back with the same attributes; written here, so that writing a PNG
// does not load OpenImageIO.
std::vector<unsigned char> pngColourChunks(double dpi, const std::string& software,
                                           const PngPlacement& placement = {});

// The chunks between IHDR and the first IDAT of a PNG file (whole chunks: length, type, data,
// CRC); empty when there are none. Throws std::runtime_error on a file that is not a PNG.
std::vector<unsigned char> pngChunksBeforeData(const std::vector<unsigned char>& png);

} // namespace moire
