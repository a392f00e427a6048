#include "runtime/ImageIO.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

namespace moire {

namespace fs = std::filesystem;

float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float v) {
    return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

std::string imageFormatOf(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png") return "png";
    if (ext == ".exr") return "exr";
    if (ext == ".tif" || ext == ".tiff") return "tiff";
    if (ext == ".jpg" || ext == ".jpeg") return "jpeg";
    return "";
}

namespace {

// A temporary name beside the target, keeping its extension so the writer picks the format.
fs::path temporaryBeside(const fs::path& target) {
    static std::atomic<int> counter{0};
    fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::string name = fmt::format(".{}.{}-{}.tmp{}", target.stem().string(), getpid(), counter++,
                                   target.extension().string());
    return dir / name;
}

} // namespace

void writeImage(const std::string& path, const Image& image, const WriteOptions& options) {
    const std::string format = imageFormatOf(path);
    if (format.empty())
        throw IoError(fmt::format(
            "cannot write '{}': unknown image format '{}'; use .png, .tif, .exr or .jpg", path,
            fs::path(path).extension().string()));
    if (image.channels < 4) throw IoError("internal: writeImage needs RGBA");

    OIIO::TypeDesc type;
    PixelDepth depth = options.depth;
    if (format == "png") {
        if (depth == PixelDepth::Default) depth = PixelDepth::U8;
        if (depth != PixelDepth::U8 && depth != PixelDepth::U16)
            throw IoError("PNG holds 8 or 16 bits per channel; use .exr for float");
    } else if (format == "tiff") {
        if (depth == PixelDepth::Default) depth = PixelDepth::U16;
    } else if (format == "exr") {
        if (depth == PixelDepth::Default) depth = PixelDepth::Float;
        if (depth != PixelDepth::Half && depth != PixelDepth::Float)
            throw IoError("EXR holds half or float channels; use .png or .tif for 8 and 16 bits");
    } else if (format == "jpeg") {
        if (depth == PixelDepth::Default) depth = PixelDepth::U8;
        if (depth != PixelDepth::U8) throw IoError("JPEG holds 8 bits per channel");
    }
    switch (depth) {
    case PixelDepth::U8:
        type = OIIO::TypeDesc::UINT8;
        break;
    case PixelDepth::U16:
        type = OIIO::TypeDesc::UINT16;
        break;
    case PixelDepth::Half:
        type = OIIO::TypeDesc::HALF;
        break;
    default:
        type = OIIO::TypeDesc::FLOAT;
        break;
    }

    const int outChannels = format == "jpeg" ? 3 : 4;
    const bool linear = format == "exr";
    std::vector<float> data(static_cast<size_t>(image.width) * image.height * outChannels);
    for (int y = 0; y < image.height; ++y) {
        const float* src = image.row(y);
        float* dst = data.data() + static_cast<size_t>(y) * image.width * outChannels;
        for (int x = 0; x < image.width; ++x) {
            for (int c = 0; c < outChannels; ++c) {
                float v = src[x * image.channels + c];
                if (c < 3 && linear) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
                dst[x * outChannels + c] = std::clamp(v, 0.0f, 1.0f);
            }
        }
    }

    OIIO::ImageSpec spec(image.width, image.height, outChannels, type);
    if (outChannels == 4) {
        spec.alpha_channel = 3;
        // Our colour is straight (unassociated); without this OpenImageIO would treat it as
        // premultiplied and divide it by alpha on the way into PNG and TIFF.
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    spec.attribute("oiio:ColorSpace", linear ? "Linear" : "sRGB");
    spec.attribute("Software", "moire " MOIRE_VERSION);
    if (options.dpi > 0) {
        spec.attribute("XResolution", static_cast<float>(options.dpi));
        spec.attribute("YResolution", static_cast<float>(options.dpi));
        spec.attribute("ResolutionUnit", "inch");
    }
    if (format == "png") spec.attribute("png:compressionLevel", 6);
    if (format == "tiff") spec.attribute("compression", "zip");
    if (format == "exr") spec.attribute("compression", "zip");

    fs::path target(path);
    fs::path temp = temporaryBeside(target);
    auto out = OIIO::ImageOutput::create(format);
    if (!out) throw IoError(fmt::format("cannot write '{}': {}", path, OIIO::geterror()));
    bool ok = out->open(temp.string(), spec) &&
              out->write_image(OIIO::TypeDesc::FLOAT, data.data()) && out->close();
    if (!ok) {
        std::string why = out->geterror();
        std::error_code ec;
        fs::remove(temp, ec);
        if (why.empty()) why = "the image writer failed";
        throw IoError(fmt::format("cannot write '{}': {}", path, why));
    }
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) {
        fs::remove(temp, ec);
        throw IoError(fmt::format("cannot write '{}': {}", path, ec.message()));
    }
}

Image readImage(const std::string& path) {
    // Keep straight alpha as stored rather than premultiplying on read.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) throw IoError(fmt::format("cannot read '{}': {}", path, OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> raw(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, raw.data()))
        throw IoError(fmt::format("cannot read '{}': {}", path, in->geterror()));
    Image img(spec.width, spec.height, 4);
    for (size_t i = 0; i < static_cast<size_t>(spec.width) * spec.height; ++i) {
        for (int c = 0; c < 4; ++c) {
            float v = c < spec.nchannels ? raw[i * spec.nchannels + c]
                                         : (c == 3 ? 1.0f : raw[i * spec.nchannels]);
            if (spec.nchannels < 3 && c < 3) v = raw[i * spec.nchannels];
            img.pixels[i * 4 + c] = v;
        }
    }
    return img;
}

} // namespace moire
