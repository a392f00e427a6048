// Posters: the default scene rendered as a large still and streamed to its file as
// `moire render` does (runKernelInBands into an ImageStream), at several sizes, formats and
// compressions, side by side in one run.
//
//   build/bin/moire_poster_bench [--sizes 8192,16384,32768] [--threads N] [--dir DIR]
//                                [--png 0,1,4,6] [--tiff none,lzw,zip]
//
// Each render runs in a child process (fork), so that its peak resident memory is its own
// (wait4's ru_maxrss), and prints: Mpx/s over the whole render and write, the peak RSS, the
// render's and the write's wall time (the kernel and the encoder run interleaved on the same
// threads: their wall time is split in proportion to the thread time each took, as render's
// summary does, and the end of the file, its fsync and rename, is the write's), the file's
// size, and a "kernel only" row (the bands thrown away) for the render's floor. The file is
// written into DIR (default: the system's temporary directory) and removed.
//
// The defaults chosen from it (ImageIO.h's kPrintCompression for PNG, OiioCodec.cpp's zip for
// TIFF) are discussed in docs/cli.md ("Large images").
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageStream.h"
#include "runtime/output/Render.h"
#include "runtime/TileExecutor.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace moire;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct Config {
    std::string format; // "png", "tiff", or "" (kernel only)
    int level = -1;     // PNG's zlib level
    std::string codec;  // TIFF's compression
    std::string label() const {
        if (format.empty()) return "kernel only";
        if (format == "png") return fmt::format("png level {}", level);
        return fmt::format("tiff {}", codec);
    }
};

struct Result {
    double wall = 0, render = 0, write = 0;
    uint64_t bytes = 0, maxRss = 0;
    bool ok = false;
};

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// In the child: compile, render and write; the figures on `fd`.
int renderChild(int size, const Config& c, int threads, const std::string& path, int fd) {
    const EmbeddedScene scene = defaultScene();
    CompileResult r = compileScene(scene.path, scene.text);
    if (!r.program) return 1;
    FrameRequest req;
    req.width = req.height = size;
    FrameValues frame;
    std::string diags;
    if (!evaluateFrame(*r.program, req, frame, diags)) return 1;
    auto backend = makeBackend("jit");
    auto kernel = backend->compile(r.program->kernel);
    const KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
    ExecOptions exec;
    exec.threads = threads;
    WriteOptions wo;
    wo.threads = threads;
    wo.compression = c.level;
    wo.codec = c.codec;
    BandTimes times;
    const int channels = kernel->numOutputs();
    const auto t0 = Clock::now();
    double pipeline = 0, finish = 0;
    try {
        std::unique_ptr<ImageStream> stream;
        if (!c.format.empty()) stream = openImageStream(path, c.format, size, size, wo);
        const int bandRows = stream ? stream->bandRows() : 64;
        runKernelInBands(
            *kernel, kf, exec, bandRows,
            [&](int band, int first, int count, const float* rows, size_t stride) {
                if (stream) stream->addRows(band * bandRows + first, count, rows, stride, channels);
            },
            &times, kPngStepRows);
        pipeline = secondsSince(t0);
        const auto t1 = Clock::now();
        if (stream) stream->finish();
        finish = secondsSince(t1);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    const double share =
        times.kernel + times.sink > 0 ? times.sink / (times.kernel + times.sink) : 0;
    const std::string line = fmt::format("{} {} {}\n", pipeline + finish, pipeline * (1 - share),
                                         pipeline * share + finish);
    return ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size()) ? 0 : 1;
}

Result measure(int size, const Config& c, int threads, const std::string& dir) {
    const std::string path = (fs::path(dir) / fmt::format("moire-poster-bench-{}.{}", ::getpid(),
                                                          c.format == "tiff" ? "tif" : "png"))
                                 .string();
    int fds[2];
    if (::pipe(fds) != 0) return {};
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(fds[0]);
        ::_exit(renderChild(size, c, threads, path, fds[1]));
    }
    ::close(fds[1]);
    std::string text;
    char buf[256];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
        text.append(buf, static_cast<size_t>(n));
    ::close(fds[0]);
    int status = 0;
    rusage usage{};
    Result res;
    if (::wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return res;
    res.maxRss = static_cast<uint64_t>(usage.ru_maxrss) * 1024;
    if (std::sscanf(text.c_str(), "%lf %lf %lf", &res.wall, &res.render, &res.write) != 3)
        return res;
    std::error_code ec;
    res.bytes = c.format.empty() ? 0 : fs::file_size(path, ec);
    fs::remove(path, ec);
    res.ok = true;
    return res;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    for (size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
        out.push_back(s.substr(start, comma - start));
    if (start < s.size()) out.push_back(s.substr(start));
    return out;
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string> sizes = {"8192", "16384"}, png = {"1", "4", "6"},
                             tiff = {"none", "lzw", "zip"};
    std::string dir = fs::temp_directory_path().string();
    int threads = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--sizes")
            sizes = split(v);
        else if (a == "--png")
            png = split(v);
        else if (a == "--tiff")
            tiff = split(v);
        else if (a == "--dir")
            dir = v;
        else if (a == "--threads")
            threads = std::atoi(v.c_str());
        else {
            std::fprintf(stderr,
                         "usage: %s [--sizes A,B] [--png L,..] [--tiff C,..] [--threads N] "
                         "[--dir DIR]\n",
                         argv[0]);
            return 2;
        }
    }
    std::vector<Config> configs = {Config{}};
    for (const std::string& l : png) configs.push_back(Config{"png", std::atoi(l.c_str()), ""});
    for (const std::string& c : tiff) configs.push_back(Config{"tiff", -1, c});
    fmt::print("default scene, jit, {} threads; 16-bit TIFF, 8-bit PNG; into {}\n",
               threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency()), dir);
    fmt::print("{:>6} {:<14} {:>8} {:>9} {:>8} {:>8} {:>7} {:>10} {:>6}\n", "size", "output",
               "Mpx/s", "peak RSS", "render s", "write s", "write%", "file MB", "vs kern");
    for (const std::string& s : sizes) {
        const int size = std::atoi(s.c_str());
        double kernelWall = 0;
        for (const Config& c : configs) {
            const Result r = measure(size, c, threads, dir);
            if (!r.ok) {
                fmt::print("{:>6} {:<14} failed\n", size, c.label());
                continue;
            }
            if (c.format.empty()) kernelWall = r.wall;
            const double mpx = static_cast<double>(size) * size / 1e6;
            fmt::print("{:>6} {:<14} {:>8.1f} {:>6.0f} MB {:>8.2f} {:>8.2f} {:>6.0f}% {:>10.0f} "
                       "{:>5.2f}x\n",
                       size, c.label(), mpx / r.wall, r.maxRss / 1e6, r.render, r.write,
                       100 * r.write / r.wall, r.bytes / 1e6,
                       kernelWall > 0 ? r.wall / kernelWall : 0);
            std::fflush(stdout);
        }
    }
    return 0;
}
