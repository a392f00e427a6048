#include "runtime/output/ImageIO.h"

#include "runtime/output/OiioCodec.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/Parallel.h"
#include "runtime/output/PngBands.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <dlfcn.h>
#include <filesystem>
#include <fmt/format.h>
#include <mutex>

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

std::string sizeProblem(const std::string& format, int width, int height) {
    const int side = std::max(width, height);
    if (format == "jpeg" && side > kMaxJpegSide)
        return fmt::format("JPEG holds at most {} pixels a side, not {}x{}; use .tif or .exr "
                           "for larger images",
                           kMaxJpegSide, width, height);
    if (format == "png" && side > kMaxPngSide)
        return fmt::format("a PNG over {} pixels a side is refused by libpng's readers, not "
                           "{}x{}; use .tif or .exr for larger images",
                           kMaxPngSide, width, height);
    return "";
}

BandedPng::BandedPng(const std::string& path, int width, int height, const WriteOptions& options,
                     AtomicFile* stream)
    : path_(path), stream_(stream) {
    if (std::string problem = depthProblem("png", options.depth); !problem.empty())
        throw IoError(problem);
    chunks_ = pngColourChunks(options.dpi, "moire " MOIRE_VERSION);
    try {
        png_ = std::make_unique<PngBands>(width, height, options.depth == PixelDepth::U16 ? 16 : 8,
                                          options.compression >= 0 ? options.compression
                                                                   : kPrintCompression);
    } catch (const std::exception& e) {
        throw encodeFailure(path, e.what());
    }
    if (stream_) {
        added_.assign(static_cast<size_t>(png_->bands()), 0);
        const std::vector<unsigned char> head = png_->head(chunks_);
        stream_->write(head.data(), head.size());
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
    addRows(band, 0, png_->rowsIn(band), rows, stride, channels);
}

void BandedPng::addRows(int band, int first, int count, const float* rows, size_t stride,
                        int channels) {
    bool done = false;
    try {
        done = png_->encodeRows(band, first, count, rows, stride, channels);
    } catch (const std::exception& e) {
        throw encodeFailure(path_, e.what());
    }
    if (!done || !stream_) return;
    // Whoever completes the run of encoded bands from the top writes it, in order; the others
    // only mark theirs. A write that fails throws IoError from here.
    std::lock_guard<std::mutex> lock(streamMutex_);
    added_[static_cast<size_t>(band)] = 1;
    while (written_ < png_->bands() && added_[static_cast<size_t>(written_)]) {
        const std::vector<unsigned char> data = png_->bandData(written_);
        stream_->write(data.data(), data.size());
        png_->release(written_++);
    }
}

std::vector<unsigned char> BandedPng::file() const {
    if (stream_) throw IoError("internal: BandedPng::file of a streamed PNG");
    try {
        return png_->file(chunks_);
    } catch (const std::exception& e) {
        throw encodeFailure(path_, e.what());
    }
}

void BandedPng::finish() {
    if (!stream_ || written_ != png_->bands())
        throw IoError(fmt::format("internal: '{}' finished before every band was written", path_));
    std::vector<unsigned char> end;
    try {
        end = png_->tail();
    } catch (const std::exception& e) {
        throw encodeFailure(path_, e.what());
    }
    stream_->write(end.data(), end.size());
    stream_->commit();
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
    if (std::string problem = depthProblem(format, options.depth); !problem.empty())
        throw IoError(problem);
    const int outChannels = format == "jpeg" ? 3 : 4;
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
    return oiioCodec().encode(path, format, image.width, image.height, data.data(), options);
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
    return oiioCodec().read(path);
}

const OiioCodec& oiioCodec() {
    // Loaded once, by the first caller; a failure is reported to every caller.
    static const OiioCodec* codec = nullptr;
    static std::string failure;
    static std::once_flag once;
    std::call_once(once, [] {
        std::error_code ec;
        const fs::path self = fs::read_symlink("/proc/self/exe", ec);
        const std::string module = (self.parent_path() / "libmoire_oiio.so").string();
        void* handle = ::dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            failure = ::dlerror();
            return;
        }
        using Entry = const OiioCodec* (*)();
        auto entry = reinterpret_cast<Entry>(::dlsym(handle, "moire_oiio_codec"));
        if (!entry) {
            failure = ::dlerror();
            return;
        }
        codec = entry();
    });
    if (!codec)
        throw IoError(fmt::format("cannot load moire's image library (for TIFF, EXR, JPEG and "
                                  "reading images): {}",
                                  failure));
    return *codec;
}

} // namespace moire
