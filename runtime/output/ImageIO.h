// Writing images through OpenImageIO, the format chosen by the file extension:
//   .png  8-bit (default) or 16-bit sRGB
//   .tif  16-bit (default) or 8-bit sRGB
//   .exr  32-bit float (default) or half, linear colour
//   .jpg  8-bit sRGB, no alpha
// PNG is encoded in bands on several threads (PngBands.h); the other formats by OpenImageIO.
// The image is encoded in memory and written by writeFileAtomically (runtime/output/OutputFile.h):
// through a temporary beside the target, every write checked, renamed into place, so a
// reader never sees half an image and a failed write leaves any existing file untouched.
#pragma once

#include "runtime/Image.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace moire {

class PngBands;

enum class PixelDepth { Default, U8, U16, Half, Float };

// zlib levels for PNG (moire_encode_bench --levels measures them): a file to keep (render's
// default: level 4 made files within 1% of level 6's on the examples, in 0.55-0.8x the time)
// (and clip's frames) and an image soon replaced (watch: level 1, in 0.6-0.75x level 4's time
// for files 5-9% larger).
constexpr int kPrintCompression = 4;
// Rows a CPU render hands the PNG encoder at a time (runKernelInBands' step): a worker's
// floats stay in the cache between the kernel and the encoder.
constexpr int kPngStepRows = 8;
constexpr int kPreviewCompression = 1;

struct WriteOptions {
    PixelDepth depth = PixelDepth::Default;
    double dpi = 0.0;     // resolution metadata for print; 0 leaves it unset
    int compression = -1; // PNG's zlib level, 0 (none) to 9; -1: kPrintCompression
    int threads = 0;      // threads that encode; 0: one per hardware thread
    // Where the image sits in a larger frame (render --region): its top-left pixel in the
    // frame, and the frame's size (0: the image is the whole frame). Recorded in the file
    // (TIFF's XPosition/YPosition and page size, EXR's data and display windows, PNG's oFFs)
    // so that `moire assemble` can put a tile back in its place.
    int originX = 0, originY = 0;
    int fullWidth = 0, fullHeight = 0;
    // TIFF's and EXR's compression as OpenImageIO names it ("zip", "lzw", "none"); empty:
    // zip (moire_poster_bench compares them).
    std::string codec;
};

class IoError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// `image` holds straight sRGB-encoded RGBA (channels >= 4); throws IoError.
void writeImage(const std::string& path, const Image& image, const WriteOptions& options = {});

// The file's bytes in memory, as writeImage would write them (render -o -): `format` is
// imageFormatOf's name; `path` names the image in errors. Throws IoError.
std::vector<unsigned char> encodeImage(const std::string& path, const std::string& format,
                                       const Image& image, const WriteOptions& options = {});

class AtomicFile;

// A PNG made from its bands as they come (render's pipeline, runKernelInBands): the pixel
// data of each band of bandRows() rows encoded on the thread that hands it over, in any order
// (PngBands.h). Then either the whole file's bytes, as encodeImage would make them (file()),
// or, with `stream`, the file written as the bands come: each band's data goes to `stream`
// (from the thread that finished it) as soon as every band above it has gone, and is freed;
// finish() writes the end and commits the file. Throws IoError naming `path`.
class BandedPng {
  public:
    BandedPng(const std::string& path, int width, int height, const WriteOptions& options,
              AtomicFile* stream = nullptr);
    ~BandedPng();
    int bands() const;
    int bandRows() const;
    // Band `band`'s rows: `channels` floats a pixel (RGBA first), `stride` floats a row.
    void add(int band, const float* rows, size_t stride, int channels);
    // The same a few rows at a time, in order, on one thread (PngBands::encodeRows).
    void addRows(int band, int first, int count, const float* rows, size_t stride, int channels);
    std::vector<unsigned char> file() const; // every band added; not when streamed
    void finish();                           // every band added; streamed only

  private:
    std::string path_;
    std::vector<unsigned char> chunks_;
    std::unique_ptr<PngBands> png_;
    AtomicFile* stream_;
    std::mutex streamMutex_;
    std::vector<char> added_; // with a stream: which bands are encoded
    int written_ = 0;         // with a stream: the bands written, from the top
};

// Why `format` (imageFormatOf's name) cannot hold `depth`, or "" when it can.
std::string depthProblem(const std::string& format, PixelDepth depth);

// The largest side each format takes (kMaxImageSide, FrameEval.h, bounds them all): JPEG's
// markers hold 16 bits and libjpeg refuses more than 65500; PNG's header would take 2^31 - 1,
// but libpng, which most programs read PNGs with, refuses more than 1,000,000 unless the
// program raises its limit, so a larger PNG would be a file few can open.
constexpr int kMaxJpegSide = 65500;
constexpr int kMaxPngSide = 1000000;

// Why `format` cannot hold a width x height image ("JPEG holds at most 65500 pixels a side;
// use .tif or .exr for larger images"), or "" when it can.
std::string sizeProblem(const std::string& format, int width, int height);

// Reads any image OpenImageIO understands into float RGBA (values as stored; sRGB files stay
// sRGB-encoded, EXR stays linear). Throws IoError.
Image readImage(const std::string& path);

// A channel value as the 8-bit PNG writer stores it, for everything else that makes 8-bit
// pixels from the same floats (the viewer's window, a video's frames): clamped to [0, 1],
// scaled by 255 in float and rounded to nearest, ties away from zero. That is OpenImageIO
// 2.4's float to uint8 conversion as built for x86-64 without SSE4.1 (simd::round is roundf
// there; with SSE4.1 it would round ties to even); ByteRounding_test holds this to what
// writeImage actually writes. NaN gives 0, as OpenImageIO's clamp does.
inline uint8_t toByte(float v) {
    if (!(v > 0.0f)) return 0; // and NaN
    if (v >= 1.0f) return 255;
    return static_cast<uint8_t>(std::round(v * 255.0f));
}

// The sRGB transfer function and its inverse.
float srgbToLinear(float v);
float linearToSrgb(float v);

// "png", "exr", ... for the formats writeImage accepts; "" otherwise.
std::string imageFormatOf(const std::string& path);

} // namespace moire
