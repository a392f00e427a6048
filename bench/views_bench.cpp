// The views' cost against the plain render, measured side by side in one run.
//
//   build/bin/moire_views_bench [--size WxH] [--repeat N] [scene.moire ...]
//
// For the default scene and every example (or the scenes given): the JIT's frame time of the
// pattern, the envelope (§4.4: one phase sample per layer, then 24 taps of arithmetic) and
// the split (the pattern left, the envelope right), on the same frame, repeated with the
// fastest run kept, and each view's time over the pattern's. A scene whose layers the
// envelope cannot sweep (a pencil, a lattice, a walking layer) is listed with the reason.
#include "bench/BenchScenes.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"

#include <algorithm>
#include <fmt/format.h>
#include <optional>
#include <thread>
#include <vector>

using namespace moire;
using bench::Scene;

namespace {

// The best frame time of `s` drawn as `view`, or nothing (with the first diagnostic line).
std::optional<double> frameTime(const Scene& s, sema::ViewMode view, int width, int height,
                                int repeat, std::string& why) {
    CompileOptions opt;
    opt.view = view;
    CompileResult r = compileScene(s.path, s.text, opt);
    if (!r.program) {
        why = r.diagnostics.substr(0, r.diagnostics.find('\n'));
        return std::nullopt;
    }
    LlvmJitBackend jit;
    auto kernel = jit.compile(r.program->kernel);
    FrameRequest req;
    req.width = width;
    req.height = height;
    FrameValues fv;
    if (!evaluateFrame(*r.program, req, fv, why)) return std::nullopt;
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    return bench::bestRender(*kernel, frame, repeat);
}

} // namespace

int main(int argc, char** argv) {
    int width = 960, height = 540, repeat = 5;
    std::vector<Scene> scenes;
    for (int i = 1; i < argc; ++i)
        if (!bench::sizeOrRepeat(argc, argv, i, width, height, repeat))
            scenes.push_back(bench::sceneFile(argv[i]));
    if (scenes.empty()) scenes = bench::defaultScenes();

    fmt::print("moire views benchmark: {}x{}, JIT, best of {}, {} threads\n\n", width, height,
               repeat, std::max(1u, std::thread::hardware_concurrency()));
    fmt::print("{:<22} {:>10} {:>11} {:>8} {:>9} {:>8}\n", "scene", "pattern ms", "envelope ms",
               "ratio", "split ms", "ratio");
    for (const Scene& s : scenes) {
        std::string why;
        std::optional<double> pattern =
            frameTime(s, sema::ViewMode::Pattern, width, height, repeat, why);
        std::optional<double> envelope =
            frameTime(s, sema::ViewMode::Envelope, width, height, repeat, why);
        if (!pattern || !envelope) {
            fmt::print("{:<22} not drawn: {}\n", s.name, why);
            continue;
        }
        std::optional<double> split =
            frameTime(s, sema::ViewMode::Split, width, height, repeat, why);
        fmt::print("{:<22} {:>10.2f} {:>11.2f} {:>7.2f}x {:>9.2f} {:>7.2f}x\n", s.name,
                   *pattern * 1e3, *envelope * 1e3, *envelope / *pattern, *split * 1e3,
                   *split / *pattern);
    }
    fmt::print("\nratio: the view's frame time over the pattern's, same scene, frame and JIT.\n"
               "The envelope's default is 24 taps (envelope_taps).\n");
    return 0;
}
