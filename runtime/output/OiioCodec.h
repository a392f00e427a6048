// The part of image input and output that needs OpenImageIO (TIFF, EXR and JPEG files, and
// reading any image), in a module of its own, libmoire_oiio.so beside the moire binary,
// loaded the first time a file needs it. Debian's OpenImageIO brings some 260 shared
// libraries (openvdb, gdal, poppler, dcmtk, ...); loading them and binding their symbols took
// 150-200 ms of every moire command's start, `moire --version` included. PNG, the default
// format, is written without it (PngBands.h).
#pragma once

#include "runtime/Image.h"
#include "runtime/output/ImageIO.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace moire {

// A file OpenImageIO writes row by row, top to bottom (ImageStream.cpp puts the rows in
// order): the rows in the file's sample type, made by convert().
class OiioRowWriter {
  public:
    virtual ~OiioRowWriter() = default;
    // Bytes of one channel value in the file.
    virtual size_t sampleBytes() const = 0;
    // `count` floats (clamped to [0, 1], linear for EXR) to the file's sample type, exactly as
    // the whole-image encoder converts them. Safe from any thread.
    virtual void convert(const float* floats, size_t count, void* samples) const = 0;
    // Rows [y, y + count) of the image, the file's channels a pixel, packed. Throws IoError.
    virtual void writeRows(int y, int count, const void* samples) = 0;
    // Writes what ends the file and checks it is whole. Throws IoError.
    virtual void close() = 0;
};

// Where a sequential writer (JPEG) sends its bytes; throws IoError.
using ByteWriter = std::function<void(const void* data, size_t size)>;

struct OiioCodec {
    // `format`'s file of width x height pixels of `channels` floats (3 for JPEG, 4 otherwise),
    // already clamped to [0, 1] (and linear for EXR), at options' depth and resolution; the
    // bytes in memory. `path` names the image in errors. Throws IoError.
    std::vector<unsigned char> (*encode)(const std::string& path, const std::string& format,
                                         int width, int height, const float* pixels,
                                         const WriteOptions& options);
    // readImage (ImageIO.h). Throws IoError.
    Image (*read)(const std::string& path);
    // A writer of `format`'s file as encode() would make it, written by rows: TIFF and EXR
    // into the seekable descriptor `fd` (an AtomicFile's temporary, or a memory file; they seek
    // back to write their directories), JPEG through `bytes` (fd -1: it only appends). Every
    // failed read or write is reported with the system's words. Throws IoError naming `path`.
    std::unique_ptr<OiioRowWriter> (*openWriter)(const std::string& path, const std::string& format,
                                                 int width, int height, const WriteOptions& options,
                                                 int fd, const ByteWriter& bytes);
};

// "cannot write 'path': why", for the writers on both sides.
inline IoError encodeFailure(const std::string& path, std::string why) {
    if (why.empty()) why = "the image writer failed";
    return IoError("cannot write '" + path + "': " + why);
}

// The module's codec, loaded on first use (from any thread); throws IoError when the module
// cannot be loaded.
const OiioCodec& oiioCodec();

} // namespace moire

// The module's one entry point.
extern "C" const moire::OiioCodec* moire_oiio_codec();
