// LLVM's optimisation pipelines weighed against the frames they give, side by side in one run.
//
//   build/bin/moire_pipeline_bench [--size WxH] [--repeat N] [scene.moire ...]
//
// For the default scene and every example (or the scenes given), the kernel is compiled by a
// fresh JIT (nothing cached) in each setting: code in lanes with the Lean pipeline (what
// `moire` runs), -O1 and -O2, each with LLVM's code generation at its -O2 and -O1 levels; and
// scalar code at -O2 (the loop vectoriser's shape). Printed per setting: milliseconds from IR
// to callable code (and how much of it is LLVM's optimisation), and the frame's Mpx/s at
// 1920x1080 (fastest of N); then each setting's compile time and frame time relative to the
// default. Source-to-IR time is the same in every setting and left out.
#include "bench/BenchScenes.h"
#include "compiler/backend/llvm/LlvmJit.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fmt/format.h>

using namespace moire;
using Clock = std::chrono::steady_clock;
using Pipeline = LlvmJitBackend::Pipeline;

namespace {

struct Setting {
    const char* name;
    int lanes;
    Pipeline pipeline;
    bool codegenLess;
};

const Setting kSettings[] = {
    {"lanes lean", LlvmJitBackend::Options::kHostLanes, Pipeline::Lean, false},
    {"lanes lean cg1", LlvmJitBackend::Options::kHostLanes, Pipeline::Lean, true},
    {"lanes O1", LlvmJitBackend::Options::kHostLanes, Pipeline::O1, false},
    {"lanes O2", LlvmJitBackend::Options::kHostLanes, Pipeline::O2, false},
    {"scalar O2", 1, Pipeline::O2, false},
};

double seconds(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

} // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, repeat = 3;
    std::vector<bench::Scene> scenes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (bench::sizeOrRepeat(argc, argv, i, width, height, repeat))
            continue;
        else
            scenes.push_back(bench::sceneFile(a));
    }
    if (scenes.empty()) scenes = bench::defaultScenes();
    const double mpx = width * static_cast<double>(height) / 1e6;
    fmt::print("moire pipeline benchmark: {}x{}, best of {}\n\n", width, height, repeat);
    fmt::print("{:<18} {:<15} {:>8} {:>8} {:>10} {:>9} {:>9}\n", "scene", "setting", "jit ms",
               "opt ms", "Mpx/s", "compile", "frame");
    for (const bench::Scene& s : scenes) {
        bench::CompiledScene c = bench::compileFrame(s, width, height);
        KernelFrame frame = c.frame();
        // One frame first, untimed, so that the first setting does not pay for the process's
        // first touch of frame-sized memory.
        bench::bestRender(*LlvmJitBackend().compile(c.program->kernel), frame, 1);
        double baseCompile = 0, baseFrame = 0;
        for (const Setting& setting : kSettings) {
            LlvmJitBackend::Options o;
            o.lanes = setting.lanes;
            o.pipeline = setting.pipeline;
            o.codegenLess = setting.codegenLess;
            LlvmJitBackend jit(o);
            auto t0 = Clock::now();
            auto kernel = jit.compile(c.program->kernel);
            double compile = seconds(t0);
            double best = bench::bestRender(*kernel, frame, repeat);
            if (&setting == &kSettings[0]) baseCompile = compile, baseFrame = best;
            fmt::print("{:<18} {:<15} {:>8.1f} {:>8.1f} {:>10.1f} {:>8.2f}x {:>8.2f}x\n",
                       &setting == &kSettings[0] ? s.name : "", setting.name, compile * 1e3,
                       jit.llvmSeconds().optimise * 1e3, mpx / best, compile / baseCompile,
                       best / baseFrame);
        }
    }
    fmt::print("\njit ms: IR to callable code; opt ms: the part in LLVM's optimisation passes.\n"
               "compile, frame: this setting's compile time and frame time over the first "
               "setting's\n(lanes lean: what moire runs). cg1: code generation at LLVM's -O1.\n");
    return 0;
}
