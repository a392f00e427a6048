#include "runtime/output/ImageIO.h"

#include "runtime/output/OutputFile.h"
#include "runtime/output/Parallel.h"
#include "runtime/output/PngBands.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
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

IoError encodeFailure(const std::string& path, std::string why) {
    if (why.empty()) why = "the image writer failed";
    return IoError(fmt::format("cannot write '{}': {}", path, why));
}

// PNG, EXR and JPEG: OpenImageIO's writer encodes into a vector through an IOProxy, so no
// library ever writes to the disk itself (libjpeg's stdio writer would exit(1) on a full
// disk) and the bytes reach it through writeFileAtomically alone.
std::vector<unsigned char> encodeInMemory(const std::string& path, const std::string& format,
                                          const OIIO::ImageSpec& spec, const float* pixels) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create(format);
    if (!out) throw encodeFailure(path, OIIO::geterror());
    if (!out->supports("ioproxy") || !out->set_ioproxy(&proxy))
        throw encodeFailure(path, fmt::format("the {} writer cannot write to memory", format));
    if (!(out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels) && out->close()))
        throw encodeFailure(path, out->geterror());
    return bytes;
}

// TIFF: OpenImageIO 2.4's TIFF writer loses the image's directory when it writes through an
// IOProxy and there is Exif data to add (the sRGB colour space is), because it reads the
// directory back with a read callback that reads nothing. It writes correctly to a file
// by name, so it is given a memory file (memfd) by name: the bytes still never touch the
// disk until writeFileAtomically, and the result is read back to be sure it is whole.
std::vector<unsigned char> encodeTiff(const std::string& path, const OIIO::ImageSpec& spec,
                                      const float* pixels) {
    int fd = ::memfd_create("moire-tiff", MFD_CLOEXEC);
    if (fd < 0) throw encodeFailure(path, std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    const std::string name = fmt::format("/proc/self/fd/{}", fd);
    auto out = OIIO::ImageOutput::create("tiff");
    if (!out) throw encodeFailure(path, OIIO::geterror());
    const bool ok =
        out->open(name, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels) && out->close();
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw encodeFailure(path, std::strerror(errno));
    // A file size limit applies to the memory file too: when it was reached, that is the
    // reason, whatever libtiff made of it.
    auto failed = [&](std::string why) {
        struct rlimit limit {};
        if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
            static_cast<rlim_t>(st.st_size) >= limit.rlim_cur)
            why = std::strerror(EFBIG);
        return encodeFailure(path, why);
    };
    if (!ok) throw failed(out->geterror());
    std::vector<unsigned char> bytes(static_cast<size_t>(st.st_size));
    size_t got = 0;
    while (got < bytes.size()) {
        ssize_t n = ::pread(fd, bytes.data() + got, bytes.size() - got, static_cast<off_t>(got));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw encodeFailure(path, n < 0 ? std::strerror(errno) : "short read");
        got += static_cast<size_t>(n);
    }
    // libtiff writes the image's directory at TIFFClose, which reports no failure: read the
    // directory back.
    OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
    auto in = OIIO::ImageInput::open("memory.tif", nullptr, &reader);
    if (!in || in->spec().width != spec.width || in->spec().height != spec.height ||
        in->spec().nchannels != spec.nchannels)
        throw failed("the TIFF writer left the file incomplete");
    return bytes;
}

std::vector<unsigned char> encode(const std::string& path, const std::string& format,
                                  const OIIO::ImageSpec& spec, const float* pixels) {
    return format == "tiff" ? encodeTiff(path, spec, pixels)
                            : encodeInMemory(path, format, spec, pixels);
}

} // namespace

std::string depthProblem(const std::string& format, PixelDepth depth) {
    if (format == "png" && depth != PixelDepth::Default && depth != PixelDepth::U8 &&
        depth != PixelDepth::U16)
        return "PNG holds 8 or 16 bits per channel; use .exr for float";
    if (format == "exr" && (depth == PixelDepth::U8 || depth == PixelDepth::U16))
        return "EXR holds half or float channels; use .png or .tif for 8 and 16 bits";
    if (format == "jpeg" && depth != PixelDepth::Default && depth != PixelDepth::U8)
        return "JPEG holds 8 bits per channel";
    return "";
}

namespace {

// The file's spec as OpenImageIO's writer for `format` takes it: type, alpha, colour space,
// resolution, compression. Throws IoError when the format cannot hold the depth.
OIIO::ImageSpec specFor(const std::string& format, int width, int height,
                        const WriteOptions& options) {
    if (std::string problem = depthProblem(format, options.depth); !problem.empty())
        throw IoError(problem);
    OIIO::TypeDesc type;
    PixelDepth depth = options.depth;
    if (depth == PixelDepth::Default)
        depth = format == "tiff"  ? PixelDepth::U16
                : format == "exr" ? PixelDepth::Float
                                  : PixelDepth::U8;
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
    OIIO::ImageSpec spec(width, height, outChannels, type);
    if (outChannels == 4) {
        spec.alpha_channel = 3;
        // Our colour is straight (unassociated); without this OpenImageIO would treat it as
        // premultiplied and divide it by alpha on the way into PNG and TIFF.
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    spec.attribute("oiio:ColorSpace", format == "exr" ? "Linear" : "sRGB");
    spec.attribute("Software", "moire " MOIRE_VERSION);
    if (options.dpi > 0) {
        spec.attribute("XResolution", static_cast<float>(options.dpi));
        spec.attribute("YResolution", static_cast<float>(options.dpi));
        spec.attribute("ResolutionUnit", "inch");
    }
    if (format == "tiff") spec.attribute("compression", "zip");
    if (format == "exr") spec.attribute("compression", "zip");
    return spec;
}

} // namespace

BandedPng::BandedPng(const std::string& path, int width, int height, const WriteOptions& options)
    : path_(path) {
    const OIIO::ImageSpec spec = specFor("png", width, height, options);
    // The chunks between the header and the pixels (colour space, text, resolution) are
    // OpenImageIO's own, taken from the same spec written at one pixel, so that a file reads
    // back with the attributes OpenImageIO's writer gives it.
    OIIO::ImageSpec one = spec;
    one.width = one.height = one.full_width = one.full_height = 1;
    const float pixel[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    try {
        chunks_ = pngChunksBeforeData(encodeInMemory(path, "png", one, pixel));
        png_ = std::make_unique<PngBands>(
            width, height, spec.format == OIIO::TypeDesc::UINT16 ? 16 : 8,
            options.compression >= 0 ? options.compression : kPrintCompression);
    } catch (const IoError&) {
        throw;
    } catch (const std::exception& e) {
        throw encodeFailure(path, e.what());
    }
}

BandedPng::~BandedPng() = default;

int BandedPng::bands() const {
    return png_->bands();
}
int BandedPng::bandRows() const {
    return png_->bandRows();
}

void BandedPng::add(int band, const float* rows, size_t stride, int channels) {
    try {
        png_->encode(band, rows, stride, channels);
    } catch (const std::exception& e) {
        throw encodeFailure(path_, e.what());
    }
}

std::vector<unsigned char> BandedPng::file() const {
    try {
        return png_->file(chunks_);
    } catch (const std::exception& e) {
        throw encodeFailure(path_, e.what());
    }
}

std::vector<unsigned char> encodeImage(const std::string& path, const std::string& format,
                                       const Image& image, const WriteOptions& options) {
    if (image.channels < 4) throw IoError("internal: writeImage needs RGBA");
    if (format == "png") {
        // The bands on `options.threads` threads, straight from the frame.
        BandedPng png(path, image.width, image.height, options);
        forEachInParallel(png.bands(), options.threads, [&](int band) {
            png.add(band, image.row(band * png.bandRows()),
                    static_cast<size_t>(image.width) * image.channels, image.channels);
        });
        return png.file();
    }
    const OIIO::ImageSpec spec = specFor(format, image.width, image.height, options);
    const int outChannels = spec.nchannels;
    const bool linear = format == "exr";

    // The other writers take the whole image as floats in the file's channels, clamped (and
    // linear for EXR), made in bands on every thread.
    std::vector<float> data(static_cast<size_t>(image.width) * image.height * outChannels);
    constexpr int kRows = 64;
    forEachInParallel((image.height + kRows - 1) / kRows, options.threads, [&](int band) {
        for (int y = band * kRows; y < std::min(image.height, (band + 1) * kRows); ++y) {
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
    });
    return encode(path, format, spec, data.data());
}

void writeImage(const std::string& path, const Image& image, const WriteOptions& options) {
    const std::string format = imageFormatOf(path);
    if (format.empty())
        throw IoError(fmt::format(
            "cannot write '{}': unknown image format '{}'; use .png, .tif, .exr or .jpg", path,
            fs::path(path).extension().string()));
    const std::vector<unsigned char> bytes = encodeImage(path, format, image, options);
    writeFileAtomically(path, bytes.data(), bytes.size());
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
