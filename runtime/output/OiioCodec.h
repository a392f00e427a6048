// The part of image input and output that needs OpenImageIO (TIFF, EXR and JPEG files, and
// reading any image), in a module of its own, libmoire_oiio.so beside the moire binary,
// loaded the first time a file needs it. Debian's OpenImageIO brings some 260 shared
// libraries (openvdb, gdal, poppler, dcmtk, ...); loading them and binding their symbols took
// 150-200 ms of every moire command's start, `moire --version` included. PNG, the default
// format, is written without it (PngBands.h).
#pragma once

#include "runtime/Image.h"
#include "runtime/output/ImageIO.h"

#include <string>
#include <vector>

namespace moire {

struct OiioCodec {
    // `format`'s file of width x height pixels of `channels` floats (3 for JPEG, 4 otherwise),
    // already clamped to [0, 1] (and linear for EXR), at options' depth and resolution; the
    // bytes in memory. `path` names the image in errors. Throws IoError.
    std::vector<unsigned char> (*encode)(const std::string& path, const std::string& format,
                                         int width, int height, const float* pixels,
                                         const WriteOptions& options);
    // readImage (ImageIO.h). Throws IoError.
    Image (*read)(const std::string& path);
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
