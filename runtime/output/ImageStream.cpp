#include "runtime/output/ImageStream.h"

#include "runtime/output/OiioCodec.h"
#include "runtime/output/OutputFile.h"

#include <algorithm>
#include <condition_variable>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace moire {

namespace fs = std::filesystem;

namespace {

// The rows OpenImageIO's writers are handed at a time: a band of render's pipeline.
constexpr int kOiioBandRows = 64;

// A PNG through BandedPng: each band's rows are encoded on the thread that hands them over,
// in order within the band (zlib's stream); rows that come before those above them in their
// band wait as floats. Written to a file as the bands come, or, to standard output, kept
// compressed and written whole at the end.
class PngStream final : public ImageStream {
  public:
    PngStream(const std::string& path, int width, int height, const WriteOptions& options,
              bool toStdout)
        : ImageStream(width, height), path_(toStdout ? "standard output" : path) {
        if (!toStdout) file_.emplace(path);
        png_.emplace(path_, width, height, options, file_ ? &*file_ : nullptr);
        bands_ = std::vector<Band>(static_cast<size_t>(png_->bands()));
    }

    int bandRows() const override { return png_->bandRows(); }

    void addRows(int y, int count, const float* rows, size_t stride, int channels) override {
        const int r = png_->bandRows();
        for (int top = y; top < y + count;) {
            const int band = top / r;
            const int first = top - band * r;
            const int n = std::min(y + count, (band + 1) * r) - top;
            addToBand(band, first, n, rows + static_cast<size_t>(top - y) * stride, stride,
                      channels);
            top += n;
        }
    }

    void finish() override {
        if (file_) {
            png_->finish(); // the bands are in the file already
            return;
        }
        const std::vector<unsigned char> bytes = png_->file();
        writeStandardOutput(bytes.data(), bytes.size());
    }

  private:
    struct Band {
        std::mutex mutex;
        int next = 0;                                 // the first row not yet encoded
        std::map<int, std::vector<float>> early;      // rows come before their turn, packed
        std::map<int, std::pair<int, int>> earlyRows; // their count and channels
    };

    void addToBand(int band, int first, int count, const float* rows, size_t stride, int channels) {
        Band& b = bands_[static_cast<size_t>(band)];
        std::lock_guard<std::mutex> lock(b.mutex);
        if (first != b.next) {
            const size_t row = static_cast<size_t>(width()) * channels;
            std::vector<float> copy(row * count);
            for (int i = 0; i < count; ++i)
                std::copy_n(rows + i * stride, row, copy.data() + i * row);
            b.early.emplace(first, std::move(copy));
            b.earlyRows.emplace(first, std::make_pair(count, channels));
            return;
        }
        png_->addRows(band, first, count, rows, stride, channels);
        b.next += count;
        for (auto it = b.early.find(b.next); it != b.early.end(); it = b.early.find(b.next)) {
            const auto [n, c] = b.earlyRows.at(b.next);
            png_->addRows(band, b.next, n, it->second.data(), static_cast<size_t>(width()) * c, c);
            b.early.erase(it);
            b.earlyRows.erase(b.next);
            b.next += n;
        }
    }

    std::string path_;
    std::optional<AtomicFile> file_;
    std::optional<BandedPng> png_; // after file_: dropped first
    std::vector<Band> bands_;
};

// TIFF, EXR and JPEG through the codec module's row writer. Rows are converted to the file's
// sample type as they come, on the caller's thread, and kept only until every row above them
// has been written; whoever completes the run of rows from the top writes it, in order, while
// the others go on rendering.
class OiioStream final : public ImageStream {
  public:
    OiioStream(const std::string& path, const std::string& format, int width, int height,
               const WriteOptions& options)
        : ImageStream(width, height), path_(path), channels_(format == "jpeg" ? 3 : 4),
          linear_(format == "exr") {
        const OiioCodec& codec = oiioCodec();
        if (format == "jpeg") {
            // JPEG only appends: its bytes go through the checked writer as they come.
            file_.emplace(path);
            writer_ = codec.openWriter(
                path, "", format, width, height, options,
                [this](const void* data, size_t size) { file_->write(data, size); });
        } else {
            // TIFF and EXR seek back to write their directories: the codec writes them by
            // name into a temporary beside the target, committed by finish().
            temp_ = temporaryBeside(path);
            try {
                writer_ = codec.openWriter(path, temp_, format, width, height, options, {});
            } catch (...) {
                removeTemporary();
                throw;
            }
        }
    }

    ~OiioStream() override {
        writer_.reset();
        removeTemporary();
    }

    int bandRows() const override { return kOiioBandRows; }

    void addRows(int y, int count, const float* rows, size_t stride, int channels) override {
        if (y < 0 || count < 0 || y + count > height())
            throw IoError(
                fmt::format("internal: rows {} to {} of '{}' out of range", y, y + count, path_));
        // The file's channels, clamped (and linear for EXR), as encodeImage makes them, then
        // the file's samples.
        const size_t values = static_cast<size_t>(width()) * channels_ * count;
        thread_local std::vector<float> floats;
        floats.resize(values);
        for (int r = 0; r < count; ++r) {
            const float* src = rows + r * stride;
            float* dst = floats.data() + static_cast<size_t>(r) * width() * channels_;
            for (int x = 0; x < width(); ++x) {
                for (int c = 0; c < channels_; ++c) {
                    float v = src[static_cast<size_t>(x) * channels + c];
                    if (c < 3 && linear_) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
                    dst[static_cast<size_t>(x) * channels_ + c] = std::clamp(v, 0.0f, 1.0f);
                }
            }
        }
        std::vector<unsigned char> samples(values * writer_->sampleBytes());
        writer_->convert(floats.data(), values, samples.data());

        std::unique_lock<std::mutex> lock(mutex_);
        if (failed_) throw IoError(failure_);
        waiting_.emplace(y, Rows{count, std::move(samples)});
        if (writing_) return; // the writer will find them
        writing_ = true;
        for (;;) {
            std::vector<std::pair<int, Rows>> ready;
            for (auto it = waiting_.begin(); it != waiting_.end() && it->first == next_;
                 it = waiting_.erase(it)) {
                next_ += it->second.count;
                ready.emplace_back(it->first, std::move(it->second));
            }
            if (ready.empty()) break;
            lock.unlock();
            try {
                for (const auto& [top, r] : ready)
                    writer_->writeRows(top, r.count, r.samples.data());
            } catch (const IoError& e) {
                lock.lock();
                failed_ = true;
                failure_ = e.what();
                writing_ = false;
                waiting_.clear();
                throw;
            }
            ready.clear(); // freed before the lock is taken again
            lock.lock();
        }
        writing_ = false;
    }

    void finish() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (failed_) throw IoError(failure_);
            if (next_ != height() || writing_)
                throw IoError(
                    fmt::format("internal: '{}' finished before every row was written", path_));
        }
        writer_->close();
        if (file_) {
            file_->commit();
        } else {
            commitTemporary(temp_, path_);
            temp_.clear();
        }
    }

  private:
    struct Rows {
        int count = 0;
        std::vector<unsigned char> samples;
    };

    void removeTemporary() {
        if (temp_.empty()) return;
        std::error_code ec;
        fs::remove(temp_, ec);
        temp_.clear();
    }

    std::string path_, temp_;
    int channels_;
    bool linear_;
    std::optional<AtomicFile> file_;        // JPEG's bytes
    std::unique_ptr<OiioRowWriter> writer_; // after file_: dropped first
    std::mutex mutex_;
    std::map<int, Rows> waiting_; // by their first row
    int next_ = 0;                // the rows above are written
    bool writing_ = false;
    bool failed_ = false;
    std::string failure_;
};

} // namespace

std::unique_ptr<ImageStream> openImageStream(const std::string& path, const std::string& format,
                                             int width, int height, const WriteOptions& options) {
    const bool toStdout = path == "-";
    if (toStdout && format != "png")
        throw IoError("internal: only a PNG is written to standard output");
    const std::string name = toStdout ? "standard output" : path;
    if (std::string problem = depthProblem(format, options.depth); !problem.empty())
        throw IoError(fmt::format("cannot write '{}': {}", name, problem));
    if (std::string problem = sizeProblem(format, width, height); !problem.empty())
        throw IoError(fmt::format("cannot write '{}': {}", name, problem));
    if (!toStdout) {
        // A missing directory is created, as clip creates one; temporaries that renders
        // killed there earlier left behind go.
        prepareOutputDirectory(path);
        removeStaleTemporaries(path);
    }
    if (format == "png") return std::make_unique<PngStream>(path, width, height, options, toStdout);
    if (format == "tiff" || format == "exr" || format == "jpeg")
        return std::make_unique<OiioStream>(path, format, width, height, options);
    throw IoError(fmt::format("cannot write '{}': unknown image format '{}'", name, format));
}

uint64_t imageStreamBytes(const std::string& format, int width, const WriteOptions& options) {
    const uint64_t threads = static_cast<uint64_t>(
        options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency()));
    const uint64_t w = static_cast<uint64_t>(std::max(width, 0));
    const uint64_t channels = format == "jpeg" ? 3 : 4;
    uint64_t sampleBytes = 1;
    switch (options.depth) {
    case PixelDepth::U16:
    case PixelDepth::Half:
        sampleBytes = 2;
        break;
    case PixelDepth::Float:
        sampleBytes = 4;
        break;
    default:
        sampleBytes = format == "tiff" ? 2 : format == "exr" ? 4 : 1;
        break;
    }
    const uint64_t rowSamples = w * channels * sampleBytes + 1; // PNG's filter byte
    const uint64_t bandRows = format == "png" ? 64 : kOiioBandRows;
    // runKernelInBands lets workers run at most `threads` bands ahead of the first unfinished
    // one: the bands waiting for those above them, converted (PNG: compressed, at most the
    // samples' size), are at most 2 x threads.
    const uint64_t waiting = 2 * threads * bandRows * rowSamples;
    // A thread's own: its floats in the file's channels (OiioStream) and, for PNG, the band
    // it encodes filtered and compressed, and zlib's state.
    const uint64_t perThread =
        format == "png" ? 2 * bandRows * rowSamples + (1ull << 20)
                        : static_cast<uint64_t>(kPngStepRows) * w * channels * sizeof(float);
    // The codec's own: libtiff's strip, OpenEXR's line buffers, libjpeg's rows: a band.
    const uint64_t codec = format == "png" ? 0 : bandRows * rowSamples + (4ull << 20);
    return waiting + threads * perThread + codec;
}

} // namespace moire
