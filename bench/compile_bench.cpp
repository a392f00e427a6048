// How compile time grows with the number of layers, measured side by side in one run.
//
//   build/bin/moire_compile_bench [--layers 10,100,1000] [--no-jit] [--no-spirv] [--no-classic]
//
// For each count N: a scene of N identical circle layers at distinct origins, compiled from
// source to the kernel (each stage of compileScene timed), then to callable JIT code and to
// SPIR-V. Each figure is also given per layer, and relative to the per-layer figure of the
// smallest scene: near-linear compilation keeps that ratio near 1 as N grows tenfold.
//
// Then the JIT's trade, side by side: for each N, the time to callable code (wall and CPU
// seconds: the machine may be shared) and the render speed at 600x400 (fastest of 3), with
// chunked kernels compiled as now (whole strips, chunks on parallel threads) and as before
// (LlvmJitBackend::Options::classicChunks), and as now without the vector-width hint on the
// chunks' pixel loops (Options::chunkVectorWidth). Kernels too small to chunk are the same in all.
//
// Last, the walking scenes (the default scene and the walking examples), from source to callable
// code with the large arms of their `if`s compiled as shared functions (as now,
// Options::outlineInsts) and in place, best of 5 each: front (source to kernel), JIT wall and
// CPU, and Mpx/s at 600x400. The default scene's source to callable is front + JIT wall.
#include "bench/BenchScenes.h"
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fmt/format.h>
#include <map>
#include <string>
#include <thread>
#include <vector>

using namespace moire;
using Clock = std::chrono::steady_clock;

namespace {

std::string sceneOf(int layers) {
    std::string text = "scene { size = (400, 300) }\n";
    for (int i = 0; i < layers; ++i)
        text += fmt::format(
            "layer {{ family = circles; spacing = 6; stroke = 1.7; origin = ({}, 0) }}\n", i);
    return text;
}

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// One JIT setting on one scene: source-to-kernel excluded.
struct JitFigures {
    double wall = 0, cpu = 0, mpxPerS = 0;
};

JitFigures measureJit(const SceneProgram& program, const LlvmJitBackend::Options& options) {
    JitFigures f;
    LlvmJitBackend jit(options); // fresh: nothing cached
    auto t0 = Clock::now();
    double c0 = cpuSeconds();
    auto kernel = jit.compile(program.kernel);
    f.cpu = cpuSeconds() - c0;
    f.wall = since(t0);
    FrameRequest req;
    req.width = 600;
    req.height = 400;
    FrameValues fv;
    std::string diags;
    if (!evaluateFrame(program, req, fv, diags)) {
        fmt::print(stderr, "{}", diags);
        std::exit(1);
    }
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    double best = 1e30;
    for (int i = 0; i < 3; ++i) {
        auto t = Clock::now();
        Image img = runKernel(*kernel, frame);
        best = std::min(best, since(t));
    }
    f.mpxPerS = req.width * static_cast<double>(req.height) / 1e6 / best;
    return f;
}

// The best of `repeat` fresh compiles (and renders) of one setting.
JitFigures bestJit(const SceneProgram& program, const LlvmJitBackend::Options& options,
                   int repeat) {
    JitFigures best{1e30, 1e30, 0};
    for (int i = 0; i < repeat; ++i) {
        JitFigures f = measureJit(program, options);
        best = {std::min(best.wall, f.wall), std::min(best.cpu, f.cpu),
                std::max(best.mpxPerS, f.mpxPerS)};
    }
    return best;
}

// Walking scenes with arms outlined (now) and in place, side by side.
void outlinedArms() {
    fmt::print(
        "\nWalking scenes, LLVM JIT with large arms as shared functions (now) and in place:\n"
        "ms from source to kernel (front) and to callable code (wall / CPU), best of 5;\n"
        "600x400 Mpx/s\n");
    fmt::print("{:<18} {:>8} | {:>15} {:>7} | {:>15} {:>7} | {:>9} {:>9} {:>9}\n", "scene", "front",
               "now: wall/CPU", "Mpx/s", "in place", "Mpx/s", "wall x", "CPU x", "Mpx/s x");
    LlvmJitBackend::Options inPlace;
    inPlace.outlineInsts = 0;
    for (const bench::Scene& s : bench::defaultScenes()) {
        if (s.name != "default" && s.name.find("walk") == std::string::npos) continue;
        double front = 1e30;
        std::unique_ptr<SceneProgram> program;
        for (int i = 0; i < 5; ++i) {
            auto t0 = Clock::now();
            CompileResult r = compileScene(s.path, s.text, {});
            front = std::min(front, since(t0));
            if (!r.program) {
                fmt::print(stderr, "{}", r.diagnostics);
                std::exit(1);
            }
            program = std::move(r.program);
        }
        JitFigures now = bestJit(*program, {}, 5), old = bestJit(*program, inPlace, 5);
        fmt::print("{:<18} {:>8.1f} | {:>7.1f}/{:<7.1f} {:>7.1f} | {:>7.1f}/{:<7.1f} {:>7.1f} | "
                   "{:>8.2f}x {:>8.2f}x {:>8.2f}x\n",
                   s.name, 1e3 * front, 1e3 * now.wall, 1e3 * now.cpu, now.mpxPerS, 1e3 * old.wall,
                   1e3 * old.cpu, old.mpxPerS, old.wall / now.wall, old.cpu / now.cpu,
                   now.mpxPerS / old.mpxPerS);
    }
}

struct Row {
    int layers = 0;
    std::vector<std::pair<std::string, double>> seconds; // stage, then the totals
    size_t kernelInsts = 0;
    JitFigures now, unhinted, classic;
    bool hasClassic = false;
};

Row measure(int layers, bool jitToo, bool spirv, bool classic) {
    Row row;
    row.layers = layers;
    CompileOptions options;
    options.stageSeconds = &row.seconds;
    auto t0 = Clock::now();
    CompileResult r = compileScene("bench.moire", sceneOf(layers), options);
    double front = since(t0);
    if (!r.program) {
        fmt::print(stderr, "{}", r.diagnostics);
        std::exit(1);
    }
    row.kernelInsts = r.program->kernel.instCount();
    row.seconds.emplace_back("= source to kernel", front);

    if (jitToo) {
        row.now = measureJit(*r.program, {});
        row.seconds.emplace_back("jit", row.now.wall);
        row.seconds.emplace_back("= source to JIT code", front + row.now.wall);
        if (classic) {
            LlvmJitBackend::Options noHint;
            noHint.chunkVectorWidth = 0;
            row.unhinted = measureJit(*r.program, noHint);
            LlvmJitBackend::Options old;
            old.classicChunks = true;
            old.compileThreads = 1;
            row.classic = measureJit(*r.program, old);
            row.hasClassic = true;
        }
    }

    if (spirv) {
        auto t2 = Clock::now();
        std::string glsl = glsl::emitGlsl(r.program->kernel);
        double emit = since(t2);
        auto t3 = Clock::now();
        std::vector<uint32_t> words = glsl::compileSpirv(r.program->kernel);
        double total = since(t3); // compileSpirv emits the GLSL again, then runs glslang
        row.seconds.emplace_back("glsl emit", emit);
        row.seconds.emplace_back("glslang", total - emit);
        row.seconds.emplace_back("= source to SPIR-V", front + total);
    }
    return row;
}

} // namespace

int main(int argc, char** argv) {
    std::vector<int> counts = {10, 100, 1000};
    bool spirv = true, jitToo = true, classic = true;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--layers" && i + 1 < argc) {
            counts.clear();
            std::string list = argv[++i];
            for (size_t p = 0; p < list.size();) {
                size_t comma = list.find(',', p);
                counts.push_back(std::atoi(list.substr(p, comma - p).c_str()));
                p = comma == std::string::npos ? list.size() : comma + 1;
            }
        } else if (a == "--no-spirv") {
            spirv = false;
        } else if (a == "--no-jit") {
            jitToo = false;
        } else if (a == "--no-classic") {
            classic = false;
        } else {
            fmt::print(stderr,
                       "usage: moire_compile_bench [--layers 10,100,1000] [--no-jit] [--no-spirv] "
                       "[--no-classic]\n");
            return 2;
        }
    }

    std::vector<Row> rows;
    for (int n : counts) rows.push_back(measure(n, jitToo, spirv, classic));

    // One line per stage: seconds and milliseconds per layer at each size, and the per-layer
    // cost relative to the smallest size (1.0 = linear).
    fmt::print("{:<22}", "stage");
    for (const Row& r : rows) fmt::print(" | {:>6} layers: s   ms/layer  x", r.layers);
    fmt::print("\n");
    for (size_t s = 0; s < rows[0].seconds.size(); ++s) {
        fmt::print("{:<22}", rows[0].seconds[s].first);
        double base = rows[0].seconds[s].second / rows[0].layers;
        for (const Row& r : rows) {
            double sec = r.seconds[s].second, perLayer = sec / r.layers;
            fmt::print(" | {:>16.3f} {:>9.3f} {:>4.1f}", sec, 1e3 * perLayer,
                       base > 0 ? perLayer / base : 0.0);
        }
        fmt::print("\n");
    }
    fmt::print("{:<22}", "kernel instructions");
    for (const Row& r : rows)
        fmt::print(" | {:>16} {:>9.1f} {:>4.1f}", r.kernelInsts, double(r.kernelInsts) / r.layers,
                   (double(r.kernelInsts) / r.layers) /
                       (double(rows[0].kernelInsts) / rows[0].layers));
    fmt::print("\n");

    if (jitToo) outlinedArms();
    if (!jitToo || !rows[0].hasClassic) return 0;
    fmt::print("\nLLVM JIT, chunked kernels now, without the width hint, and classic ({} hardware\n"
               "threads): seconds to callable code (wall / CPU), 600x400 render Mpx/s (fastest of "
               "3)\n",
               std::max(1u, std::thread::hardware_concurrency()));
    fmt::print("{:>7} | {:>15} {:>7} | {:>15} {:>7} | {:>15} {:>7} | {:>11} {:>11}\n", "layers",
               "now: wall/CPU s", "Mpx/s", "no hint", "Mpx/s", "classic", "Mpx/s", "CPU hint/no",
               "Mpx/s n/old");
    for (const Row& r : rows)
        fmt::print(
            "{:>7} | {:>7.3f}/{:<7.3f} {:>7.2f} | {:>7.3f}/{:<7.3f} {:>7.2f} | {:>7.3f}/{:<7.3f} "
            "{:>7.2f} | {:>11.2f} {:>11.2f}\n",
            r.layers, r.now.wall, r.now.cpu, r.now.mpxPerS, r.unhinted.wall, r.unhinted.cpu,
            r.unhinted.mpxPerS, r.classic.wall, r.classic.cpu, r.classic.mpxPerS,
            r.now.cpu / r.unhinted.cpu, r.now.mpxPerS / r.classic.mpxPerS);
    return 0;
}
