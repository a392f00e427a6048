// A PNG made by OpenImageIO's own writer, on one thread, as writeImage made one before it
// encoded PNG in bands (straight RGBA, sRGB): the benchmarks' point of comparison.
#pragma once

#include "runtime/Image.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <vector>

namespace moire::bench {

// The file's bytes, 8-bit at zlib `level`.
inline std::vector<unsigned char> oiioPng(const Image& img, int level) {
    OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("png:compressionLevel", level);
    std::vector<float> data(static_cast<size_t>(img.width) * img.height * 4);
    for (size_t p = 0; p < data.size() / 4; ++p)
        for (int c = 0; c < 4; ++c)
            data[p * 4 + c] = std::clamp(img.pixels[p * img.channels + c], 0.0f, 1.0f);
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    if (!out || !out->set_ioproxy(&proxy) || !out->open("bench.png", spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, data.data()) || !out->close()) {
        std::fprintf(stderr, "OpenImageIO could not write a PNG\n");
        std::exit(1);
    }
    return bytes;
}

} // namespace moire::bench
