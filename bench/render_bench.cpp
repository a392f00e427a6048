// Render throughput and compile latency, measured side by side in one run.
//
//   build/bin/moire_bench [--size WxH] [--repeat N] [scene.moire ...]
//
// For the default scene and every example (or the scenes given): the time from source text
// to callable JIT code, then Mpx/s of the reference interpreter and of the JIT at 1920x1080,
// and their ratio. Each render is repeated and the fastest run kept (other work on the
// machine can only add time).
#include "bench/BenchScenes.h"
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <thread>

using namespace moire;
using bench::defaultScenes;
using bench::Scene;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Fastest of `repeat` renders, in seconds.
double timeRender(const CompiledKernel& kernel, const KernelFrame& frame, int repeat) {
    double best = 1e30;
    for (int i = 0; i < repeat; ++i) {
        auto t0 = Clock::now();
        Image img = runKernel(kernel, frame);
        best = std::min(best, seconds(t0));
    }
    return best;
}

} // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, repeat = 3;
    std::vector<Scene> scenes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--size" && i + 1 < argc)
            std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--repeat" && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else
            scenes.push_back(bench::sceneFile(a));
    }
    if (scenes.empty()) scenes = defaultScenes();

    fmt::print("moire render benchmark: {}x{}, best of {}, {} threads\n\n", width, height, repeat,
               std::max(1u, std::thread::hardware_concurrency()));
    fmt::print("{:<18} {:>10} {:>10} {:>12} {:>12} {:>9}\n", "scene", "front ms", "jit ms",
               "interp Mpx/s", "jit Mpx/s", "jit/int");
    const double mpx = width * static_cast<double>(height) / 1e6;
    for (const Scene& s : scenes) {
        // Source to callable code: parse, check, lower, AD, passes, then LLVM (a fresh JIT so
        // nothing is cached).
        auto t0 = Clock::now();
        CompileResult r = compileScene(s.path, s.text);
        if (!r.program) {
            fmt::print(stderr, "{}", r.diagnostics);
            return 1;
        }
        double front = seconds(t0);
        LlvmJitBackend jit;
        auto t1 = Clock::now();
        auto jitKernel = jit.compile(r.program->kernel);
        double codegen = seconds(t1);

        FrameRequest req;
        req.width = width;
        req.height = height;
        FrameValues fv;
        std::string diags;
        if (!evaluateFrame(*r.program, req, fv, diags)) {
            fmt::print(stderr, "{}", diags);
            return 1;
        }
        KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
        InterpBackend interp;
        auto interpKernel = interp.compile(r.program->kernel);
        double tInterp = timeRender(*interpKernel, frame, 1); // slow: once is enough
        double tJit = timeRender(*jitKernel, frame, repeat);
        fmt::print("{:<18} {:>10.2f} {:>10.2f} {:>12.2f} {:>12.1f} {:>8.0f}x\n", s.name,
                   front * 1e3, codegen * 1e3, mpx / tInterp, mpx / tJit, tInterp / tJit);
    }
    fmt::print(
        "\nfront: parse, checks, lowering, AD and IR passes; jit: LLVM translation, -O2 and\n"
        "machine code. Parse to callable code is their sum.\n");
    return 0;
}
