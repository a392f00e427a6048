// The views' cost against the plain render, measured side by side in one run.
//
//   build/bin/moire_views_bench [--size WxH] [--repeat N] [scene.moire ...]
//
// For the default scene and every example (or the scenes given): the JIT's frame time of the
// pattern and of every other view (sema/Views.h: the envelope, §4.4, one phase sample per
// layer then 24 taps of arithmetic; the split; the ratio view, the character search of
// §4.2-4.3 per pixel) and of the pattern with the fringe overlay, on the same frame, repeated
// with the fastest run kept, and each one's time over the pattern's. A stack with a lattice
// sweeps M^2 / 4 taps (the rank-two sweep, 144 at the default M), each re-solving the lattice.
// A view a scene's layers cannot take (the envelope of a family given by its distance alone)
// is marked '-', its reason listed below.
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
std::optional<double> frameTime(const Scene& s, sema::ViewMode view, bool overlay, int width,
                                int height, int repeat, std::string& why) {
    CompileOptions opt;
    opt.view = view;
    opt.overlay = overlay;
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
    // The columns: every view but the pattern, then the pattern with the overlay.
    struct Column {
        std::string name;
        sema::ViewMode view;
        bool overlay;
    };
    std::vector<Column> columns;
    for (const sema::ViewName& v : sema::viewNames())
        if (v.mode != sema::ViewMode::Pattern) columns.push_back({v.name, v.mode, false});
    columns.push_back({"overlay", sema::ViewMode::Pattern, true});
    fmt::print("{:<22} {:>10}", "scene", "pattern ms");
    for (const Column& c : columns) fmt::print(" {:>17}", c.name + " ms (x)");
    fmt::print("\n");
    std::vector<std::string> notes;
    for (const Scene& s : scenes) {
        std::string why;
        std::optional<double> pattern =
            frameTime(s, sema::ViewMode::Pattern, false, width, height, repeat, why);
        if (!pattern) {
            fmt::print("{:<22} not drawn: {}\n", s.name, why);
            continue;
        }
        fmt::print("{:<22} {:>10.2f}", s.name, *pattern * 1e3);
        for (const Column& c : columns) {
            std::optional<double> t = frameTime(s, c.view, c.overlay, width, height, repeat, why);
            if (!t) {
                fmt::print(" {:>17}", "-");
                notes.push_back(fmt::format("{} {}: {}", s.name, c.name, why));
                continue;
            }
            fmt::print(" {:>17}", fmt::format("{:.2f} ({:.2f}x)", *t * 1e3, *t / *pattern));
        }
        fmt::print("\n");
    }
    fmt::print("\n(x): the view's frame time over the pattern's, same scene, frame and JIT.\n"
               "The envelope's default is 24 taps (envelope_taps).\n");
    for (const std::string& n : notes) fmt::print("- {}\n", n);
    return 0;
}
