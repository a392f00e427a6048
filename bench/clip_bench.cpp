// Clip throughput: frames a second for a clip of the default scene on the JIT, and how the
// time splits between rendering and writing, for PNG frames at several compression levels
// and for a video piped to ffmpeg, side by side.
//
//   build/bin/moire_clip_bench [--size WxH] [--frames N] [--fps F]
//
// Every row renders the same frames (t = n / fps, as `moire clip` does). The first table
// renders each frame once and times every way of writing it alone, one after the other; the
// second runs the frames through ClipOutput as `moire clip` does, writing in the background
// (PNGs on several threads, video through ffmpeg in its own process) while the next frame
// renders, so writing costs only what the wall time exceeds rendering by.
#include "bench/OiioPng.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "compiler/lower/ClipClock.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/VideoWriter.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <thread>
#include <unistd.h>

using namespace moire;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

double seconds(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Row {
    std::string name;
    double render = 0, write = 0, wall = 0; // seconds over all frames; wall 0: sequential
    uintmax_t bytes = 0;
};

} // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, frames = 12;
    double fps = 24;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size")) std::sscanf(argv[i + 1], "%dx%d", &width, &height);
        if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
        if (!std::strcmp(argv[i], "--fps")) fps = std::atof(argv[i + 1]);
    }
    EmbeddedScene scene = defaultScene();
    CompileResult compiled = compileScene(scene.path, scene.text);
    if (!compiled.program) {
        fmt::print(stderr, "{}", compiled.diagnostics);
        return 1;
    }
    const SceneProgram& program = *compiled.program;
    LlvmJitBackend jit;
    auto kernel = jit.compile(program.kernel);

    FrameValues first;
    std::string diags;
    evaluateFrame(program, FrameRequest{0.0, width, height}, first, diags);
    fmt::print("clip bench: default scene ({} timing{}), {}x{}, jit, {} threads, {} frames at "
               "{:g} fps\n\n",
               first.timings.size(), first.timings.size() == 1 ? "" : "s", width, height,
               std::thread::hardware_concurrency(), frames, fps);

    fs::path dir = fs::temp_directory_path() / fmt::format("moire-clip-bench-{}", getpid());
    fs::create_directories(dir);

    // Renders frame n; adds the time to `*spent`.
    auto render = [&](int n, double* spent) {
        auto t0 = Clock::now();
        FrameValues fv;
        evaluateFrame(program, FrameRequest{clip::frameTime(0.0, n, fps), width, height}, fv,
                      diags);
        Image img = runKernel(*kernel, KernelFrame{fv.uniforms.data(), fv.width, fv.height});
        *spent += seconds(t0);
        return img;
    };

    // One after the other, as a clip without background writing would: each frame rendered
    // once, then written by writeImage and by OpenImageIO at each zlib level, every write
    // timed alone.
    const std::vector<int> levels = {1, 3, 6, 9};
    const WriteOptions clipWrite; // as `moire clip` writes its numbered frames
    double renderOnly = 0;
    std::vector<Row> sequential(1 + levels.size());
    sequential[0].name = fmt::format("png, writeImage (level {})", kPrintCompression);
    for (size_t i = 0; i < levels.size(); ++i)
        sequential[i + 1].name = fmt::format("png, OpenImageIO level {}", levels[i]);
    for (int n = 0; n < frames; ++n) {
        Image img = render(n, &renderOnly);
        for (size_t i = 0; i < sequential.size(); ++i) {
            std::string path = (dir / fmt::format("s{}_{:04}.png", i, n)).string();
            auto w0 = Clock::now();
            if (i == 0)
                writeImage(path, img, clipWrite);
            else {
                const std::vector<unsigned char> png = bench::oiioPng(img, levels[i - 1]);
                writeFileAtomically(path, png.data(), png.size());
            }
            sequential[i].write += seconds(w0);
            sequential[i].bytes += fs::file_size(path);
        }
    }
    for (Row& r : sequential) r.render = renderOnly;

    // As `moire clip` runs: frames handed to a ClipOutput, written in the background.
    std::vector<Row> piped;
    std::string ffmpeg = findOnPath("ffmpeg");
    for (int kind = 0; kind < 3; ++kind) {
        std::optional<VideoFormat> format;
        if (kind > 0) format = kind == 1 ? VideoFormat::Mp4 : VideoFormat::WebM;
        if (format && ffmpeg.empty()) continue;
        auto pattern = [&](int64_t n) { return (dir / fmt::format("p_{:04}.png", n)).string(); };
        Row row;
        std::string video =
            format ? (dir / fmt::format("clip{}", extensionOf(*format))).string() : std::string();
        row.name =
            format ? fmt::format("moire clip -> {}", extensionOf(*format))
                   : fmt::format("moire clip -> png ({} writing)", ClipOutput::defaultInFlight());
        auto t0 = Clock::now();
        {
            ClipOutput out = format ? ClipOutput(std::make_unique<VideoWriter>(
                                          ffmpeg, video, *format, width, height, fps, frames))
                                    : ClipOutput(pattern, clipWrite, ClipOutput::defaultInFlight());
            for (int n = 0; n < frames; ++n) out.add(n, render(n, &row.render));
            out.finish();
        }
        row.wall = seconds(t0);
        if (format)
            row.bytes = fs::file_size(video);
        else
            for (int n = 0; n < frames; ++n) row.bytes += fs::file_size(pattern(n));
        piped.push_back(row);
    }
    if (ffmpeg.empty()) fmt::print("(no ffmpeg on PATH: the video rows are left out)\n");

    fmt::print("rendering alone: {:.1f} ms a frame, {:.2f} frames/s\n\n",
               1000 * renderOnly / frames, frames / renderOnly);
    fmt::print("{:<32}{:>11}{:>11}{:>10}{:>10}{:>9}\n", "one after the other", "render ms",
               "write ms", "fps", "render %", "MB/fr");
    for (const Row& r : sequential)
        fmt::print("{:<32}{:>11.1f}{:>11.1f}{:>10.2f}{:>9.0f}%{:>9.2f}\n", r.name,
                   1000 * r.render / frames, 1000 * r.write / frames, frames / (r.render + r.write),
                   100 * r.render / (r.render + r.write),
                   static_cast<double>(r.bytes) / frames / 1e6);
    // Writing in the background costs what the wall time exceeds rendering by.
    fmt::print("\n{:<32}{:>11}{:>11}{:>10}{:>10}{:>9}\n", "writing in the background", "render ms",
               "extra ms", "fps", "render %", "MB/fr");
    for (const Row& r : piped)
        fmt::print("{:<32}{:>11.1f}{:>11.1f}{:>10.2f}{:>9.0f}%{:>9.2f}\n", r.name,
                   1000 * r.render / frames, 1000 * (r.wall - r.render) / frames, frames / r.wall,
                   100 * r.render / r.wall, static_cast<double>(r.bytes) / frames / 1e6);
    std::error_code ec;
    fs::remove_all(dir, ec);
    return 0;
}
