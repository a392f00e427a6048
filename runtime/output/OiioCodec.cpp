// OpenImageIO's side of image input and output (OiioCodec.h), built as the module
// libmoire_oiio.so that moire loads the first time a file needs it.
#include "runtime/output/OiioCodec.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
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
        // OpenImageIO's JPEG writer knows the unit only as "in" (anything else leaves JFIF's
        // density unit 0, a bare aspect ratio that print software reads as 72 dpi); the
        // other writers take "inch".
        spec.attribute("ResolutionUnit", format == "jpeg" ? "in" : "inch");
    }
    // zip for TIFF and EXR: moire_poster_bench's 16-bit posters come out 20% smaller than
    // with lzw for 1.2-1.4x its write time, and 10-20x smaller than uncompressed ones, whose
    // gigabytes the disk cannot take as fast as the encoder makes them (docs/cli.md).
    const std::string codec = options.codec.empty() ? "zip" : options.codec;
    if (format == "tiff") {
        spec.attribute("compression", codec);
        // Classic TIFF's offsets are 32 bits: a file that may pass 4 GB must be BigTIFF,
        // which fewer readers take, so only then. zip stores incompressible strips nearly as
        // they are, so the samples' own size (with an eighth to spare) decides.
        const uint64_t samples = static_cast<uint64_t>(width) * static_cast<uint64_t>(height) *
                                 static_cast<uint64_t>(outChannels) * type.size();
        if (samples + samples / 8 >= (uint64_t{1} << 32)) spec.attribute("tiff:bigtiff", 1);
    }
    if (format == "exr") spec.attribute("compression", codec);
    // A region of a larger frame (WriteOptions): the data window inside the display window.
    if (options.fullWidth > 0 && options.fullHeight > 0 && format != "jpeg") {
        spec.x = options.originX;
        spec.y = options.originY;
        spec.full_x = spec.full_y = 0;
        spec.full_width = options.fullWidth;
        spec.full_height = options.fullHeight;
    }
    return spec;
}

// An IOProxy that hands every byte to a ByteWriter, for a writer that only appends (JPEG).
// A failure is kept, not thrown through the codec's C code, and reported after.
class ByteProxy : public OIIO::Filesystem::IOProxy {
  public:
    explicit ByteProxy(const ByteWriter& bytes) : IOProxy("", Write), bytes_(bytes) {}
    const char* proxytype() const override { return "moire"; }
    size_t write(const void* buf, size_t size) override {
        if (failure_) return 0;
        try {
            bytes_(buf, size);
        } catch (...) {
            failure_ = std::current_exception();
            return 0;
        }
        m_pos += static_cast<int64_t>(size);
        return size;
    }
    size_t pwrite(const void* buf, size_t size, int64_t offset) override {
        return offset == m_pos ? write(buf, size) : 0;
    }
    bool seek(int64_t offset) override { return offset == m_pos; }
    size_t size() const override { return static_cast<size_t>(m_pos); }
    void rethrow() const {
        if (failure_) std::rethrow_exception(failure_);
    }

  private:
    const ByteWriter& bytes_;
    std::exception_ptr failure_;
};

// An IOProxy over a seekable descriptor, for the writers that seek back (TIFF's directory,
// EXR's offset table): reads and writes at offsets, the first failure's errno kept, since
// libtiff and OpenEXR report a failed write at close poorly or not at all.
class FdProxy : public OIIO::Filesystem::IOProxy {
  public:
    FdProxy(int fd, Mode mode) : IOProxy("", mode), fd_(fd) {}
    const char* proxytype() const override { return "fd"; }
    bool seek(int64_t offset) override {
        m_pos = offset;
        return offset >= 0;
    }
    size_t read(void* buf, size_t size) override {
        const size_t n = pread(buf, size, m_pos);
        m_pos += static_cast<int64_t>(n);
        return n;
    }
    size_t write(const void* buf, size_t size) override {
        const size_t n = pwrite(buf, size, m_pos);
        m_pos += static_cast<int64_t>(n);
        return n;
    }
    size_t pread(void* buf, size_t size, int64_t offset) override {
        size_t got = 0;
        while (got < size) {
            const ssize_t n = ::pread(fd_, static_cast<char*>(buf) + got, size - got,
                                      static_cast<off_t>(offset + static_cast<int64_t>(got)));
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) keep(errno);
            if (n <= 0) break;
            got += static_cast<size_t>(n);
        }
        return got;
    }
    size_t pwrite(const void* buf, size_t size, int64_t offset) override {
        size_t put = 0;
        while (put < size) {
            // A file size limit (RLIMIT_FSIZE) is EFBIG here (main() ignores SIGXFSZ); a full
            // disk ENOSPC.
            const ssize_t n = ::pwrite(fd_, static_cast<const char*>(buf) + put, size - put,
                                       static_cast<off_t>(offset + static_cast<int64_t>(put)));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                keep(n < 0 ? errno : EIO);
                break;
            }
            put += static_cast<size_t>(n);
        }
        return put;
    }
    size_t size() const override {
        struct stat st {};
        return ::fstat(fd_, &st) == 0 ? static_cast<size_t>(st.st_size) : 0;
    }
    int error() const { return error_; }

  private:
    void keep(int error) {
        if (!error_) error_ = error;
    }
    int fd_;
    int error_ = 0;
};

class RowWriter : public OiioRowWriter {
  public:
    RowWriter(const std::string& path, const std::string& format, const OIIO::ImageSpec& spec,
              int fd, const ByteWriter& bytes)
        : path_(path), format_(format), spec_(spec), fd_(fd), bytes_(bytes) {
        out_ = OIIO::ImageOutput::create(format);
        if (!out_) throw encodeFailure(path, OIIO::geterror());
        if (format == "tiff") {
            // OpenImageIO 2.4's TIFF writer loses its directory through an IOProxy (encodeTiff);
            // by name it writes correctly: the descriptor's name, the same file.
            if (!out_->open(fmt::format("/proc/self/fd/{}", fd), spec_)) fail(out_->geterror());
            return;
        }
        if (fd >= 0)
            fdProxy_ = std::make_unique<FdProxy>(fd, OIIO::Filesystem::IOProxy::Write);
        else
            byteProxy_ = std::make_unique<ByteProxy>(bytes_);
        OIIO::Filesystem::IOProxy* proxy =
            fdProxy_ ? static_cast<OIIO::Filesystem::IOProxy*>(fdProxy_.get()) : byteProxy_.get();
        if (!out_->supports("ioproxy") || !out_->set_ioproxy(proxy))
            throw encodeFailure(path,
                                fmt::format("the {} writer cannot write to a stream", format));
        if (!out_->open(path, spec_)) fail(out_->geterror());
    }
    ~RowWriter() override {
        // Dropped before close(): the codec lets go; the caller removes what was written.
        if (out_ && !closed_) out_->close();
    }
    size_t sampleBytes() const override { return spec_.format.size(); }
    void convert(const float* floats, size_t count, void* samples) const override {
        OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, floats, spec_.format, samples,
                                   static_cast<int>(count));
    }
    void writeRows(int y, int count, const void* samples) override {
        if (!out_->write_scanlines(spec_.y + y, spec_.y + y + count, 0, spec_.format, samples))
            fail(out_->geterror());
        check();
    }
    void close() override {
        closed_ = true;
        if (!out_->close()) fail(out_->geterror());
        check();
        if (format_ != "tiff") return;
        // libtiff writes the image's directory at TIFFClose, which reports no failure: read
        // the directory back.
        auto in = OIIO::ImageInput::open(fmt::format("/proc/self/fd/{}", fd_));
        if (!in || in->spec().width != spec_.width || in->spec().height != spec_.height ||
            in->spec().nchannels != spec_.nchannels)
            fail("the TIFF writer left the file incomplete");
    }

  private:
    // A failed read or write of the file, in the system's words, whatever the codec made of it.
    void check() {
        if (byteProxy_) byteProxy_->rethrow();
        if (fdProxy_ && fdProxy_->error())
            throw encodeFailure(path_, std::strerror(fdProxy_->error()));
        // TIFF, written by name: a file size limit reached is the reason.
        struct stat st {};
        struct rlimit limit {};
        if (format_ == "tiff" && ::fstat(fd_, &st) == 0 && ::getrlimit(RLIMIT_FSIZE, &limit) == 0 &&
            limit.rlim_cur != RLIM_INFINITY && static_cast<rlim_t>(st.st_size) >= limit.rlim_cur)
            throw encodeFailure(path_, std::strerror(EFBIG));
    }
    [[noreturn]] void fail(const std::string& why) {
        check();
        throw encodeFailure(path_, why);
    }

    std::string path_, format_;
    OIIO::ImageSpec spec_;
    int fd_;
    ByteWriter bytes_;
    std::unique_ptr<ByteProxy> byteProxy_;
    std::unique_ptr<FdProxy> fdProxy_;
    std::unique_ptr<OIIO::ImageOutput> out_; // after the proxies: dropped first
    bool closed_ = false;
};

std::unique_ptr<OiioRowWriter> openWriter(const std::string& path, const std::string& format,
                                          int width, int height, const WriteOptions& options,
                                          int fd, const ByteWriter& bytes) {
    return std::make_unique<RowWriter>(path, format, specFor(format, width, height, options), fd,
                                       bytes);
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
    static const moire::OiioCodec codec{&moire::encodeFile, &moire::readFile, &moire::openWriter};
    return &codec;
}
