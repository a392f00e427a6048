// Render throughput and compile latency, measured side by side in one run.
//
//   build/bin/moire_bench [--size WxH] [--repeat N] [--lanes N] [--interp] [--fields]
//                         [scene.moire ...]
//
// For the default scene and every example (or the scenes given): the time from source text
// to callable JIT code, then Mpx/s at 1920x1080 of the JIT in its two shapes side by side,
// scalar (one pixel a step, left to LLVM's loop vectoriser) and in lanes (the host's SIMD
// width, control flow under masks: what `moire` runs), and their ratio; with --interp, the
// reference interpreter too; with --fields, the kernel also outputs every layer's index,
// distance and index gradient (CompileOptions::layerFields, what the probes and the views that
// read the fields ask for). Each render is repeated and the fastest run kept (other work on
// the machine can only add time).
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

} // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, repeat = 3;
    bool withInterp = false;
    CompileOptions compileOptions;
    int lanesOption = LlvmJitBackend::Options::kHostLanes;
    std::vector<Scene> scenes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (bench::sizeOrRepeat(argc, argv, i, width, height, repeat))
            continue;
        else if (a == "--lanes" && i + 1 < argc)
            lanesOption = std::atoi(argv[++i]);
        else if (a == "--interp")
            withInterp = true;
        else if (a == "--fields")
            compileOptions.layerFields = true;
        else
            scenes.push_back(bench::sceneFile(a));
    }
    if (scenes.empty()) scenes = defaultScenes();

    fmt::print("moire render benchmark: {}x{}, best of {}, {} threads\n\n", width, height, repeat,
               std::max(1u, std::thread::hardware_concurrency()));
    LlvmJitBackend::Options scalarOptions;
    scalarOptions.lanes = 1;
    LlvmJitBackend::Options jitOptions;
    jitOptions.lanes = lanesOption;
    const unsigned lanes = LlvmJitBackend(jitOptions).lanes();
    fmt::print("{:<20} {:>8} {:>8} {:>8} {:>12} {:>12} {:>8}", "scene", "front ms", "jit ms",
               "x1 ms", "scalar Mpx/s", fmt::format("x{} Mpx/s", lanes), "ratio");
    if (withInterp) fmt::print(" {:>12} {:>8}", "interp Mpx/s", "jit/int");
    fmt::print("\n");
    const double mpx = width * static_cast<double>(height) / 1e6;
    for (const Scene& s : scenes) {
        // Source to callable code: parse, check, lower, AD, passes, then LLVM (a fresh JIT so
        // nothing is cached).
        auto t0 = Clock::now();
        CompileResult r = compileScene(s.path, s.text, compileOptions);
        if (!r.program) {
            fmt::print(stderr, "{}", r.diagnostics);
            return 1;
        }
        double front = seconds(t0);
        LlvmJitBackend jit(jitOptions), scalar(scalarOptions);
        auto t1 = Clock::now();
        auto jitKernel = jit.compile(r.program->kernel);
        double codegen = seconds(t1);
        auto t2 = Clock::now();
        auto scalarKernel = scalar.compile(r.program->kernel);
        double scalarCodegen = seconds(t2);

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
        double tScalar = bench::bestRender(*scalarKernel, frame, repeat);
        double tJit = bench::bestRender(*jitKernel, frame, repeat);
        fmt::print("{:<20} {:>8.2f} {:>8.2f} {:>8.2f} {:>12.1f} {:>12.1f} {:>7.2f}x", s.name,
                   front * 1e3, codegen * 1e3, scalarCodegen * 1e3, mpx / tScalar, mpx / tJit,
                   tScalar / tJit);
        if (withInterp) {
            InterpBackend interp;
            auto interpKernel = interp.compile(r.program->kernel);
            double tInterp = bench::bestRender(*interpKernel, frame, 1); // slow: once is enough
            fmt::print(" {:>12.2f} {:>7.0f}x", mpx / tInterp, tInterp / tJit);
        }
        fmt::print("\n");
    }
    fmt::print(
        "\nfront: parse, checks, lowering, AD and IR passes; jit: LLVM translation, passes and\n"
        "machine code in lanes (x1: scalar). Parse to callable code is front + jit. ratio: the\n"
        "lanes' Mpx/s over the scalar JIT's, on the same kernel and frame.\n");
    return 0;
}
