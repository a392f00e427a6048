#include "runtime/output/MemoryBudget.h"

#include "runtime/output/ImageStream.h"

#include <algorithm>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <sys/resource.h>
#include <thread>
#include <vector>

namespace moire {

namespace {

// The process before any frame: code, the JIT's LLVM, OpenImageIO (loaded only for a file
// that needs it: not for PNG, OiioCodec.h) and the compiled scene, with room for the
// allocator's slack. Measured at 204 MB peak resident for a one-layer scene rendered at 16x16
// on the JIT to TIFF, and 65-80 MB to PNG (getrusage of the child, 2 cores).
constexpr uint64_t kProcessBytes = 256ull << 20;
constexpr uint64_t kProcessBytesWithoutOiio = 96ull << 20;
// OpenImageIO writes a scanline file in chunks of about 64 MB of the caller's pixels, each
// converted to the file's type in a buffer of its own; the codecs keep a few rows besides.
constexpr uint64_t kWriterChunkBytes = 64ull << 20;
// The Vulkan executor's two slots, each a device buffer and a host readback buffer of at most
// 64 MiB (VulkanContext's budget); on a CPU device both live in host memory.
constexpr uint64_t kVulkanStagingBytes = 4 * (64ull << 20);
// The rows of a band of render's pipeline (ImageStream::bandRows).
constexpr uint64_t kBandRows = 64;

uint64_t pixelsOf(const FrameFootprint& f) {
    return static_cast<uint64_t>(std::max(f.width, 0)) *
           static_cast<uint64_t>(std::max(f.height, 0));
}

// What writeImage holds beside the frame: the clamped float copy in the file's channels
// (RGB for JPEG), OpenImageIO's chunk and its conversion, and the encoded file, which is
// built in memory before it is written (at most the pixels at 4 bytes a channel, before
// compression).
uint64_t imageWriterBytes(const FrameFootprint& f) {
    const uint64_t channels = f.format == "jpeg" ? 3 : 4;
    const uint64_t copy = pixelsOf(f) * channels * sizeof(float);
    const uint64_t encoded = copy;
    return copy + encoded + 2 * std::min(copy, kWriterChunkBytes);
}

uint64_t sinkBytes(const FrameFootprint& f) {
    const uint64_t px = pixelsOf(f);
    switch (f.sink) {
    case FrameSink::ImageFile:
        return imageWriterBytes(f);
    case FrameSink::Video:
        return px * 4; // the 8-bit RGBA frame written to ffmpeg's pipe
    case FrameSink::Streamed: {
        // The stream's own (ImageStream.h), and each worker's step of the kernel's floats.
        WriteOptions options;
        options.depth = f.depth;
        options.threads = f.threads;
        const uint64_t threads = static_cast<uint64_t>(
            f.threads > 0 ? f.threads : std::max(1u, std::thread::hardware_concurrency()));
        const uint64_t rowFloats = static_cast<uint64_t>(std::max(f.width, 0)) *
                                   static_cast<uint64_t>(std::max(f.channels, 1));
        uint64_t bytes = imageStreamBytes(f.format, f.width, options) +
                         threads * kPngStepRows * rowFloats * sizeof(float);
        // A GPU kernel's bands come a device call at a time (TileExecutor: a buffer of about
        // 4 Mpx, or one band), handed over a band at a time: a band's floats in the file's
        // channels beside them.
        if (f.gpu) {
            const uint64_t width = static_cast<uint64_t>(std::max(f.width, 0));
            bytes += std::max<uint64_t>(kBandRows * width, 1ull << 22) *
                         static_cast<uint64_t>(std::max(f.channels, 1)) * sizeof(float) +
                     kBandRows * width * 4 * sizeof(float);
        }
        // To standard output, the compressed file and its copy in the writer (at most the
        // samples' size, as zlib stores incompressible data).
        if (!f.streamed) {
            const uint64_t sampleBytes = f.depth == PixelDepth::U16 ? 2 : 1;
            const uint64_t file =
                pixelsOf(f) * 4 * sampleBytes + pixelsOf(f) * 4 * sampleBytes / 500 + (1ull << 16);
            bytes += 2 * file;
        }
        return bytes;
    }
    case FrameSink::Window:
        // The frame in 8 bits as rendered, as shown and as kept for reuse, the window's
        // canvas, the texture, and the GL drawable's front and back buffers (host memory on
        // a software GL, and mapped into the process by the driver on most others).
        return px * 4 * 7;
    }
    return 0;
}

uint64_t frameBytes(const FrameFootprint& f) {
    if (f.sink == FrameSink::Streamed) return 0; // never made whole
    return pixelsOf(f) * static_cast<uint64_t>(std::max(f.channels, 1)) * sizeof(float);
}

std::optional<uint64_t> readNumber(const std::string& path) {
    std::ifstream in(path);
    unsigned long long v = 0;
    if (!(in >> v)) return std::nullopt; // missing, or "max"
    return v;
}

// A field of /proc/meminfo or /proc/self/status ("MemAvailable:  1234 kB"), in bytes.
std::optional<uint64_t> procField(const char* file, const std::string& key) {
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        if (line.compare(0, key.size(), key) != 0 || line.size() <= key.size() ||
            line[key.size()] != ':')
            continue;
        std::istringstream fields(line.substr(key.size() + 1));
        unsigned long long kb = 0;
        if (fields >> kb) return static_cast<uint64_t>(kb) * 1024;
    }
    return std::nullopt;
}

void lower(std::optional<MemoryAvailable>& best, uint64_t bytes, const std::string& limit) {
    if (!best || bytes < best->bytes) best = MemoryAvailable{bytes, limit};
}

// The headroom of a cgroup directory and every one above it up to `root`: the tightest of
// limit - usage among those with a limit.
void cgroupHeadroom(std::optional<MemoryAvailable>& best, const std::string& root, std::string path,
                    const char* maxFile, const char* currentFile, const std::string& name) {
    for (;;) {
        const std::string dir = root + path;
        std::optional<uint64_t> max = readNumber(dir + "/" + maxFile);
        std::optional<uint64_t> current = readNumber(dir + "/" + currentFile);
        // cgroup v1 says "no limit" with a number near 2^63.
        if (max && current && *max < (1ull << 60))
            lower(best, *max > *current ? *max - *current : 0, name);
        if (path.empty() || path == "/") break;
        const size_t slash = path.rfind('/');
        path = slash == std::string::npos ? std::string() : path.substr(0, slash);
    }
}

void cgroupLimits(std::optional<MemoryAvailable>& best) {
    std::ifstream in("/proc/self/cgroup");
    for (std::string line; std::getline(in, line);) {
        // "0::/path" (v2) or "4:memory:/path" (v1). Inside a container the mount's root is
        // the process's own group, so the path may not exist below it: the walk up reaches
        // the mount's root, which then is the group.
        const size_t a = line.find(':'), b = line.find(':', a + 1);
        if (a == std::string::npos || b == std::string::npos) continue;
        const std::string controllers = line.substr(a + 1, b - a - 1);
        const std::string path = line.substr(b + 1);
        if (line.compare(0, a, "0") == 0 && controllers.empty())
            cgroupHeadroom(best, "/sys/fs/cgroup", path, "memory.max", "memory.current",
                           "the cgroup's memory.max");
        std::istringstream list(controllers);
        for (std::string c; std::getline(list, c, ',');)
            if (c == "memory")
                cgroupHeadroom(best, "/sys/fs/cgroup/memory", path, "memory.limit_in_bytes",
                               "memory.usage_in_bytes", "the cgroup's memory limit");
    }
}

void rlimitHeadroom(std::optional<MemoryAvailable>& best, int resource, const char* statusKey,
                    const std::string& name) {
    rlimit rl{};
    if (::getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return;
    const uint64_t used = procField("/proc/self/status", statusKey).value_or(0);
    const uint64_t limit = rl.rlim_cur;
    lower(best, limit > used ? limit - used : 0, name);
}

} // namespace

uint64_t estimateFrameBytes(const FrameFootprint& f) {
    const bool oiio = f.sink != FrameSink::Streamed || f.format != "png";
    uint64_t bytes =
        (oiio ? kProcessBytes : kProcessBytesWithoutOiio) + frameBytes(f) + sinkBytes(f);
    // A queued frame is a whole picture waiting for (or in) its writer.
    bytes += static_cast<uint64_t>(std::max(f.queued, 0)) * (frameBytes(f) + sinkBytes(f));
    if (f.gpu) bytes += kVulkanStagingBytes;
    return bytes;
}

std::optional<MemoryAvailable> availableMemory() {
    std::optional<MemoryAvailable> best;
    if (std::optional<uint64_t> avail = procField("/proc/meminfo", "MemAvailable"))
        lower(best, *avail, "");
    rlimitHeadroom(best, RLIMIT_AS, "VmSize", "the address space limit (ulimit -v)");
    rlimitHeadroom(best, RLIMIT_DATA, "VmData", "the data size limit (ulimit -d)");
    cgroupLimits(best);
    return best;
}

std::string formatBytes(uint64_t bytes) {
    const double b = static_cast<double>(bytes);
    if (b >= 1e9) return fmt::format("{:.1f} GB", b / 1e9);
    if (b >= 1e6) return fmt::format("{:.0f} MB", b / 1e6);
    return fmt::format("{:.0f} kB", b / 1e3);
}

std::string memoryProblem(const FrameFootprint& frame) {
    const uint64_t need = estimateFrameBytes(frame);
    std::optional<MemoryAvailable> have = availableMemory();
    if (!have || need <= have->bytes) return {};
    return fmt::format("a {}x{} {} needs about {} of memory; {} {} available{}", frame.width,
                       frame.height, frame.sink == FrameSink::Window ? "window" : "image",
                       formatBytes(need), have->limit.empty() ? "this machine has" : "there is",
                       formatBytes(have->bytes),
                       have->limit.empty() ? "" : " under " + have->limit);
}

} // namespace moire
