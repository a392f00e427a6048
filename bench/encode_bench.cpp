// Encoding and the whole `moire render` command, side by side in one run.
//
//   build/bin/moire_encode_bench [--repeat N] [--big WxH] [--levels] [scene.moire]
//
// 1. One 1920x1080 frame of the scene (examples/two_rings.moire unless one is given) written
//    to PNG in memory by OpenImageIO's writer (what `moire render` used before) and by
//    writeImage's banded encoder at several zlib levels on one thread and on every thread:
//    milliseconds, size, and the speed-up over OpenImageIO at level 6.
// 2. The whole command, `moire render` run as a process (the binary beside this one), at
//    1920x1080 and at 7200x4800 (--big), on one thread and on two: wall time, CPU time, and
//    the parts its summary line reports.
// 3. The targets: at 1920x1080 the whole command within 1.5x of the kernel plus a parallel
//    encode (both measured here in this process), and on the big frame two threads at least
//    1.7x faster than one.
// --levels: part 1 alone, at every zlib level (to choose the defaults in ImageIO.h).
// Every figure is the fastest of --repeat runs (other work can only add time), with the
// median beside it; the runs being compared are interleaved.
#include "bench/BenchScenes.h"
#include "bench/OiioPng.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <functional>
#include <regex>
#include <sys/resource.h>
#include <thread>
#include <unistd.h>

using namespace moire;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

double millisSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Times {
    std::vector<double> ms;
    double best() const { return *std::min_element(ms.begin(), ms.end()); }
    double median() const {
        std::vector<double> s = ms;
        std::sort(s.begin(), s.end());
        return s[s.size() / 2];
    }
};

std::string moireBinary() {
    return (fs::read_symlink("/proc/self/exe").parent_path() / "moire").string();
}

// The CPU time, in ms, of the children waited for so far.
double childCpuMs() {
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
           (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e3;
}

// One `moire render` as a process: its wall time in ms, its CPU time (user and system) in
// `cpu`, and its summary line.
double runCommand(const std::string& scene, int w, int h, int threads, const std::string& out,
                  std::string& summary, double& cpu) {
    const double cpu0 = childCpuMs();
    const std::string command =
        fmt::format("'{}' render '{}' --size {}x{} --threads {} -o '{}' 2>&1", moireBinary(), scene,
                    w, h, threads, out);
    auto t0 = Clock::now();
    FILE* p = popen(command.c_str(), "r");
    if (!p) std::exit(1);
    summary.clear();
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) summary += buf;
    const int status = pclose(p);
    const double ms = millisSince(t0);
    cpu = childCpuMs() - cpu0;
    if (status != 0) {
        fmt::print(stderr, "{} failed:\n{}", command, summary);
        std::exit(1);
    }
    while (!summary.empty() && summary.back() == '\n') summary.pop_back();
    return ms;
}

// "render R, encode and write E" from the summary line.
std::pair<double, double> parts(const std::string& summary) {
    std::smatch m;
    static const std::regex re(R"(render (\d+), encode and write (\d+))");
    if (!std::regex_search(summary, m, re)) return {0, 0};
    return {std::stod(m[1]), std::stod(m[2])};
}

} // namespace

int main(int argc, char** argv) {
    int repeat = 5, bigW = 7200, bigH = 4800;
    bool levelsOnly = false;
    std::string scenePath = MOIRE_SOURCE_DIR "/examples/two_rings.moire";
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--levels")
            levelsOnly = true;
        else if (a == "--big" && i + 1 < argc)
            std::sscanf(argv[++i], "%dx%d", &bigW, &bigH);
        else
            scenePath = a;
    }
    const bench::Scene scene = bench::sceneFile(scenePath);
    const int hw = std::max(1u, std::thread::hardware_concurrency());
    fmt::print("moire encode benchmark: {}, best (median) of {}, {} hardware threads\n\n",
               scene.name, repeat, hw);

    CompileResult r = compileScene(scene.path, scene.text);
    if (!r.program) {
        fmt::print(stderr, "{}", r.diagnostics);
        return 1;
    }
    LlvmJitBackend jit;
    auto kernel = jit.compile(r.program->kernel);
    FrameValues fv;
    std::string diags;
    if (!evaluateFrame(*r.program, FrameRequest{0.0, 1920, 1080}, fv, diags)) {
        fmt::print(stderr, "{}", diags);
        return 1;
    }
    const KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    Times kernelTimes;
    Image img;
    for (int i = 0; i < repeat; ++i) {
        auto t0 = Clock::now();
        img = runKernel(*kernel, frame);
        kernelTimes.ms.push_back(millisSince(t0));
    }

    // 1. The encoders on one frame.
    struct Row {
        std::string name;
        std::function<size_t()> encode;
        int level = -1, threads = 1; // bands only
        Times t = {};
        size_t bytes = 0;
    };
    std::vector<Row> rows;
    rows.push_back(
        {"OpenImageIO, level 6 (before)", [&] { return bench::oiioPng(img, 6).size(); }});
    rows.push_back({"OpenImageIO, level 1", [&] { return bench::oiioPng(img, 1).size(); }});
    const std::vector<int> levels = levelsOnly ? std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 9}
                                               : std::vector<int>{1, kPrintCompression, 6};
    for (int level : levels)
        for (int threads : {1, hw}) {
            if (levelsOnly && threads > 1) continue;
            WriteOptions wo;
            wo.compression = level;
            wo.threads = threads;
            rows.push_back({fmt::format("bands, level {}, {} thread{}", level, threads,
                                        threads == 1 ? "" : "s"),
                            [&img, wo] { return encodeImage("bench.png", "png", img, wo).size(); },
                            level, threads});
        }
    for (int i = 0; i < repeat; ++i)
        for (Row& row : rows) {
            auto t0 = Clock::now();
            row.bytes = row.encode();
            row.t.ms.push_back(millisSince(t0));
        }
    fmt::print("PNG of one 1920x1080 frame, in memory\n");
    fmt::print("{:<34}{:>10}{:>10}{:>9}{:>14}\n", "writer", "best ms", "median", "MB",
               "vs OIIO lvl 6");
    for (const Row& row : rows)
        fmt::print("{:<34}{:>10.1f}{:>10.1f}{:>9.2f}{:>13.2f}x\n", row.name, row.t.best(),
                   row.t.median(), row.bytes / 1e6, rows[0].t.best() / row.t.best());

    if (levelsOnly) return 0;

    // 2. The whole command.
    const fs::path dir = fs::temp_directory_path() / fmt::format("moire-encode-bench-{}", getpid());
    fs::create_directories(dir);
    struct Run {
        int w, h, threads;
        Times wall = {}, cpu = {}, render = {}, write = {};
        std::string last = {};
    };
    std::vector<Run> runs = {{1920, 1080, 1}, {1920, 1080, hw}, {bigW, bigH, 1}, {bigW, bigH, 2}};
    for (int i = 0; i < repeat; ++i)
        for (Run& run : runs) {
            std::string summary;
            double cpu = 0;
            run.wall.ms.push_back(runCommand(scene.path, run.w, run.h, run.threads,
                                             (dir / "out.png").string(), summary, cpu));
            run.cpu.ms.push_back(cpu);
            auto [render, write] = parts(summary);
            run.render.ms.push_back(render);
            run.write.ms.push_back(write);
            run.last = summary;
        }
    fmt::print("\nmoire render, whole command (a process each run)\n");
    fmt::print("{:<24}{:>10}{:>10}{:>10}{:>12}{:>12}\n", "size, threads", "wall ms", "median",
               "cpu ms", "render ms", "encode ms");
    for (const Run& run : runs)
        fmt::print("{:<24}{:>10.0f}{:>10.0f}{:>10.0f}{:>12.0f}{:>12.0f}\n",
                   fmt::format("{}x{}, {}", run.w, run.h, run.threads), run.wall.best(),
                   run.wall.median(), run.cpu.best(), run.render.best(), run.write.best());
    fmt::print("(cpu: user and system time of the process; a one-thread run whose wall time is\n"
               "well above its cpu time waited for a core: the machine was busy)\n");
    fmt::print("last summary: {}\n", runs.back().last);

    // 3. The targets.
    // The default level on every thread: what `moire render` does.
    const Row& parallel = *std::find_if(rows.begin(), rows.end(), [&](const Row& row) {
        return row.level == kPrintCompression && row.threads == hw;
    });
    const double budget = kernelTimes.best() + parallel.t.best();
    const double whole = runs[1].wall.best();
    fmt::print("\ntargets\n");
    fmt::print("1920x1080: whole command {:.0f} ms / (kernel {:.1f} ms + parallel encode {:.1f} "
               "ms = {:.1f} ms) = {:.2f}x (target <= 1.5x)\n",
               whole, kernelTimes.best(), parallel.t.best(), budget, whole / budget);
    fmt::print("{}x{}: 1 thread {:.0f} ms / 2 threads {:.0f} ms = {:.2f}x (target >= 1.7x)\n", bigW,
               bigH, runs[2].wall.best(), runs[3].wall.best(),
               runs[2].wall.best() / runs[3].wall.best());
    std::error_code ec;
    fs::remove_all(dir, ec);
    return 0;
}
