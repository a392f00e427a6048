// The JIT and the Vulkan backend side by side in one run (the spec's §8.1, Table 3 in spirit).
//
//   build/bin/moire_gpu_bench [--size WxH] [--repeat N] [--device N] [scene.moire ...]
//
// For the default scene and every example (or the scenes given), per backend:
//  - from source to first pixels: the front end (parse, checks, lowering, AD, passes), code
//    generation (LLVM; or GLSL + glslang to SPIR-V), the rest of `compile` (for Vulkan, the
//    pipeline), and the first frame;
//  - the cached rebuild: the same scene compiled again with one number changed, which must
//    reuse the compiled kernel;
//  - throughput in Mpx/s, best of N frames, and milliseconds per megapixel.
// Without a Vulkan device the Vulkan columns say why and the JIT's are still printed.
#include "bench/BenchScenes.h"
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/Compile.h"
#include "runtime/output/Render.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <regex>

using namespace moire;
using bench::defaultScenes;
using bench::Scene;
using Clock = std::chrono::steady_clock;

namespace {

double ms(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The scene with its first number nudged: a number-only edit.
std::string nudged(const std::string& text) {
    std::smatch m;
    std::regex number(R"((spacing\s*=\s*)([0-9.]+))");
    if (!std::regex_search(text, m, number)) return text + "\n";
    double v = std::stod(m[2].str()) * 1.01;
    return m.prefix().str() + m[1].str() + fmt::format("{}", v) + m.suffix().str();
}

struct Timing {
    double front = 0, codegen = 0, compile = 0, firstFrame = 0, rebuild = 0, mpxPerS = 0;
    bool rebuildHit = false;
    std::string error;
};

Timing measure(const std::string& backendName, const Scene& s, int w, int h, int repeat,
               int device) {
    Timing t;
    std::unique_ptr<Backend> backend;
    try {
        BackendOptions options;
        if (backendName == "vulkan") options.device = device;
        backend = makeBackend(backendName, options);
    } catch (const std::exception& e) {
        t.error = e.what();
        return t;
    }
    if (!backend) {
        t.error = "this build has no '" + backendName + "' backend";
        return t;
    }
    auto t0 = Clock::now();
    CompileResult r = compileScene(s.path, s.text);
    t.front = ms(t0);
    if (!r.program) {
        t.error = r.diagnostics;
        return t;
    }
    if (backendName == "vulkan") { // code generation alone: GLSL and glslang
        auto tc = Clock::now();
        glsl::compileSpirv(r.program->kernel);
        t.codegen = ms(tc);
    }
    FrameRequest req;
    req.width = w;
    req.height = h;
    FrameValues fv;
    std::string diags;
    evaluateFrame(*r.program, req, fv, diags);
    auto t1 = Clock::now();
    auto kernel = backend->compile(r.program->kernel);
    t.compile = ms(t1);
    kernel.reset();
    auto t2 = Clock::now();
    renderFrame(*r.program, *backend, fv);
    t.firstFrame = ms(t2);

    // A number-only edit: the front end runs again, the kernel comes from the cache.
    auto t3 = Clock::now();
    CompileResult edited = compileScene(s.path, nudged(s.text));
    if (edited.program) {
        backend->compile(edited.program->kernel);
        t.rebuildHit = edited.program->kernelHash == r.program->kernelHash;
    }
    t.rebuild = ms(t3);

    double best = 1e30;
    for (int i = 0; i < repeat; ++i) {
        auto t4 = Clock::now();
        renderFrame(*r.program, *backend, fv);
        best = std::min(best, ms(t4));
    }
    t.mpxPerS = (w * static_cast<double>(h) / 1e6) / (best / 1e3);
    return t;
}

} // namespace

int main(int argc, char** argv) {
    int w = 1920, h = 1080, repeat = 3, device = -1;
    std::vector<Scene> scenes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--size" && i + 1 < argc)
            std::sscanf(argv[++i], "%dx%d", &w, &h);
        else if (a == "--repeat" && i + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--device" && i + 1 < argc)
            device = std::atoi(argv[++i]);
        else
            scenes.push_back(bench::sceneFile(a));
    }
    if (scenes.empty()) scenes = defaultScenes();

    fmt::print("JIT and Vulkan side by side: {}x{}, best of {} frames\n", w, h, repeat);
    fmt::print(
        "times in ms; 'to pixels' = front end + code generation and pipeline + first frame\n\n");
    fmt::print("{:<20} {:<7} {:>7} {:>8} {:>9} {:>9} {:>10} {:>9} {:>9} {:>9}\n", "scene",
               "backend", "front", "codegen", "compile", "1st frame", "to pixels", "rebuild",
               "Mpx/s", "ms/Mpx");
    for (const Scene& s : scenes) {
        for (const char* name : {"jit", "vulkan"}) {
            Timing t = measure(name, s, w, h, repeat, device);
            if (!t.error.empty()) {
                fmt::print("{:<20} {:<7} unavailable: {}\n", s.name, name, t.error);
                continue;
            }
            fmt::print("{:<20} {:<7} {:>7.1f} {:>8.1f} {:>9.1f} {:>9.1f} {:>10.1f} {:>8.1f}{} "
                       "{:>9.1f} {:>9.2f}\n",
                       s.name, name, t.front, t.codegen, t.compile, t.firstFrame,
                       t.front + t.compile + t.firstFrame, t.rebuild, t.rebuildHit ? " " : "!",
                       t.mpxPerS, 1e3 / t.mpxPerS);
        }
    }
    fmt::print(
        "\ncodegen: GLSL and glslang (Vulkan only; the JIT's LLVM work is all in 'compile').\n"
        "compile: the backend's compile call (LLVM -O2 and machine code; or SPIR-V and the Vulkan\n"
        "pipeline). rebuild: the scene with a number changed, front end included, kernel from the\n"
        "cache ('!' marks a rebuild that missed it).\n");
    return 0;
}
