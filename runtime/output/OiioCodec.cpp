// OpenImageIO's side of image input and output (OiioCodec.h), built as the module
// libmoire_oiio.so that moire loads the first time a file needs it.
#include "runtime/output/OiioCodec.h"

#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

namespace moire {

namespace {

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

// The file's spec as OpenImageIO's writer for `format` takes it: type, alpha, colour space,
// resolution, compression (the caller has checked the format can hold the depth).
OIIO::ImageSpec specFor(const std::string& format, int width, int height,
                        const WriteOptions& options) {
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

std::vector<unsigned char> encodeFile(const std::string& path, const std::string& format, int width,
                                      int height, const float* pixels,
                                      const WriteOptions& options) {
    return encode(path, format, specFor(format, width, height, options), pixels);
}

Image readFile(const std::string& path) {
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

} // namespace

} // namespace moire

extern "C" const moire::OiioCodec* moire_oiio_codec() {
    static const moire::OiioCodec codec{&moire::encodeFile, &moire::readFile};
    return &codec;
}
