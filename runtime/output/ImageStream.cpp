#include "runtime/output/ImageStream.h"

#include "runtime/output/OiioCodec.h"
#include "runtime/output/OutputFile.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <mutex>
#include <optional>
#include <sys/mman.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace moire {

namespace fs = std::filesystem;

namespace {

// The rows OpenImageIO's writers are handed at a time: a band of render's pipeline.
constexpr int kOiioBandRows = 64;

// The band a thread is part way through encoding: PngBands keeps a band's filtered rows so
// far in the thread's own scratch, so a thread finishes one band before it starts another,
// and only it can go on with the band. Streams are told apart by a number never reused (a
// thread whose band's stream has gone may start another).
struct OpenBand {
    uint64_t stream = 0;
    int band = -1;
};
thread_local OpenBand openBand;
std::atomic<uint64_t> streamNumbers{0};

// A PNG through BandedPng: a band's rows are encoded on the thread that started it, in order,
// as they come (runKernelInBands hands a band to one worker, eight rows at a time, so the
// rows are encoded while still in the cache). Rows that cannot be encoded yet (they come
// before those above them in the band, from another thread, or from a thread part way
// through another band) wait as floats until their band's thread, or a thread with no band
// open, comes back to it. Written to a file as the bands come, or, to standard output, kept
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
        if (y < 0 || count < 0 || y + count > height())
            throw IoError(
                fmt::format("internal: rows {} to {} of '{}' out of range", y, y + count, path_));
        const int r = png_->bandRows();
        for (int top = y; top < y + count;) {
            const int band = top / r;
            const int n = std::min(y + count, (band + 1) * r) - top;
            addToBand(band, top - band * r, n, rows + static_cast<size_t>(top - y) * stride, stride,
                      channels);
            top += n;
        }
    }

    void finish() override {
        // Bands whose rows all wait, with no thread part way through them, are encoded here.
        for (size_t band = 0; band < bands_.size(); ++band) {
            Band& b = bands_[band];
            std::lock_guard<std::mutex> lock(b.mutex);
            if (b.next < rowsIn(static_cast<int>(band)) && b.owner == std::thread::id() &&
                openBand.stream != number_)
                drain(static_cast<int>(band), b);
        }
        if (file_) {
            png_->finish(); // the bands are in the file already
            return;
        }
        const std::vector<unsigned char> bytes = png_->file();
        writeStandardOutput(bytes.data(), bytes.size());
    }

  private:
    struct Early {
        int count, channels;
        std::vector<float> rows; // packed
    };
    struct Band {
        std::mutex mutex;
        int next = 0;               // the first row not yet encoded
        std::thread::id owner;      // the thread part way through it
        std::map<int, Early> early; // rows waiting, by their first row in the band
    };

    int rowsIn(int band) const {
        return std::min(png_->bandRows(), height() - band * png_->bandRows());
    }

    // Encodes rows [first, first + count) of `band` on this thread (b.next == first).
    void encode(int band, Band& b, int first, int count, const float* rows, size_t stride,
                int channels) {
        openBand = {number_, band};
        b.owner = std::this_thread::get_id();
        png_->addRows(band, first, count, rows, stride, channels);
        b.next += count;
        if (b.next == rowsIn(band)) {
            openBand = {};
            b.owner = std::thread::id();
        }
    }

    // The waiting rows that continue the band, on this thread.
    void drain(int band, Band& b) {
        for (auto it = b.early.find(b.next); it != b.early.end(); it = b.early.find(b.next)) {
            Early e = std::move(it->second);
            b.early.erase(it);
            encode(band, b, b.next, e.count, e.rows.data(),
                   static_cast<size_t>(width()) * e.channels, e.channels);
        }
    }

    void addToBand(int band, int first, int count, const float* rows, size_t stride, int channels) {
        Band& b = bands_[static_cast<size_t>(band)];
        std::lock_guard<std::mutex> lock(b.mutex);
        const bool mine = b.owner == std::this_thread::get_id();
        const bool free = b.owner == std::thread::id() && openBand.stream != number_;
        if (first == b.next && (mine || free)) {
            encode(band, b, first, count, rows, stride, channels);
            drain(band, b);
            return;
        }
        const size_t row = static_cast<size_t>(width()) * channels;
        Early e{count, channels, std::vector<float>(row * count)};
        for (int i = 0; i < count; ++i)
            std::copy_n(rows + i * stride, row, e.rows.data() + i * row);
        b.early.emplace(first, std::move(e));
        if (mine || free) drain(band, b);
    }

    const uint64_t number_ = ++streamNumbers;
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
        // Through the checked writer's temporary (OutputFile.h): JPEG only appends, so its
        // bytes go to it as they come; TIFF and EXR seek back to write their directories,
        // so they write at offsets into its descriptor, or, when the destination cannot seek
        // (a FIFO, a device), into a memory file copied to it at the end.
        file_.emplace(path);
        int fd = -1;
        if (format != "jpeg") {
            if (file_->writtenInPlace()) {
                memory_ = ::memfd_create("moire-image", MFD_CLOEXEC);
                if (memory_ < 0) throw encodeFailure(path, std::strerror(errno));
                fd = memory_;
            } else {
                fd = file_->descriptor();
            }
        }
        writer_ =
            codec.openWriter(path, format, width, height, options, fd,
                             [this](const void* data, size_t size) { file_->write(data, size); });
    }

    ~OiioStream() override {
        writer_.reset();
        if (memory_ >= 0) ::close(memory_);
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
            // The run of rows from the top that is here, written once it is a band long (or
            // ends the image), in one call: the codec gets whole strips and blocks to compress
            // (OpenImageIO compresses a TIFF's strips in parallel when handed several).
            int run = 0;
            for (auto it = waiting_.begin(); it != waiting_.end() && it->first == next_ + run; ++it)
                run += it->second.count;
            if (run == 0 || (run < kOiioBandRows && next_ + run < height())) break;
            const int top = next_;
            Rows rows;
            if (waiting_.begin()->second.count == run) {
                rows = std::move(waiting_.begin()->second);
                waiting_.erase(waiting_.begin());
            } else {
                rows.count = run;
                rows.samples.reserve(static_cast<size_t>(run) * width() * channels_ *
                                     writer_->sampleBytes());
                while (!waiting_.empty() && waiting_.begin()->first < top + run) {
                    const std::vector<unsigned char>& s = waiting_.begin()->second.samples;
                    rows.samples.insert(rows.samples.end(), s.begin(), s.end());
                    waiting_.erase(waiting_.begin());
                }
            }
            next_ += run;
            lock.unlock();
            try {
                writer_->writeRows(top, rows.count, rows.samples.data());
            } catch (const IoError& e) {
                lock.lock();
                failed_ = true;
                failure_ = e.what();
                writing_ = false;
                waiting_.clear();
                throw;
            }
            rows = Rows(); // freed before the lock is taken again
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
        if (memory_ >= 0) copyMemoryFile();
        file_->commit();
    }

  private:
    struct Rows {
        int count = 0;
        std::vector<unsigned char> samples;
    };

    // The memory file, to a destination that cannot seek, a megabyte at a time.
    void copyMemoryFile() {
        std::vector<char> buf(1 << 20);
        for (off_t at = 0;;) {
            const ssize_t n = ::pread(memory_, buf.data(), buf.size(), at);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) throw encodeFailure(path_, std::strerror(errno));
            if (n == 0) return;
            file_->write(buf.data(), static_cast<size_t>(n));
            at += n;
        }
    }

    std::string path_;
    int memory_ = -1; // the memory file, when the destination cannot seek
    int channels_;
    bool linear_;
    std::optional<AtomicFile> file_;
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
