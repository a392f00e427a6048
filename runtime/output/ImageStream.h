// An image written to its file band by band as the renderer finishes the rows, so that the
// memory a render holds is bounded by a few bands, not by the image: a 65536 x 65536 poster
// is 64 GiB of float pixels, but its bands are a few megabytes each. Every format moire
// writes goes through it (PNG by PngBands, TIFF, EXR and JPEG by OpenImageIO's scanline or
// tile writes in the codec module, OiioCodec.h), under OutputFile.h's rules: the bytes go to
// a temporary beside the target and are renamed into place by finish(), so a reader never
// sees half an image and a render stopped part way leaves any earlier file as it was.
#pragma once

#include "runtime/output/ImageIO.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace moire {

class ImageStream {
  public:
    // Dropped without finish() (an error, Ctrl-C): the temporary is removed, nothing written.
    virtual ~ImageStream() = default;

    int width() const { return width_; }
    int height() const { return height_; }
    // The rows best handed over together (the PNG encoder's band; a band of the other
    // writers): runKernelInBands' bandRows.
    virtual int bandRows() const = 0;

    // Rows [y, y + count) of the image (0: its top row): `channels` floats a pixel, straight
    // sRGB-encoded RGBA first, `stride` floats from one row to the next. Safe from any thread;
    // rows may come in any order, each once. Rows in hand are converted to the file's sample
    // type at once (PNG: encoded, when the rows above them in their band have come) and kept
    // only until the rows above them are written; the call never waits for other rows, so
    // what bounds the memory held is how far ahead of the first unfinished row the caller
    // runs (runKernelInBands: a few bands), and no caller can deadlock in here.
    virtual void addRows(int y, int count, const float* rows, size_t stride, int channels) = 0;

    // Every row added: writes what ends the file and moves it into place. Throws IoError.
    virtual void finish() = 0;

  protected:
    ImageStream(int width, int height) : width_(width), height_(height) {}

  private:
    int width_, height_;
};

// Opens `path` (standard output for kStdoutPath, as a PNG) to receive a width x height image
// in `format` (imageFormatOf's name) at options' depth, resolution and placement. Creates a
// missing directory and clears dead temporaries there, as every writer does. Throws IoError.
std::unique_ptr<ImageStream> openImageStream(const std::string& path, const std::string& format,
                                             int width, int height, const WriteOptions& options);

// The most memory an open stream of this shape holds at its peak (its buffers and the
// encoder's) when fed by runKernelInBands on options.threads workers, for MemoryBudget's
// estimate.
uint64_t imageStreamBytes(const std::string& format, int width, const WriteOptions& options);

} // namespace moire
