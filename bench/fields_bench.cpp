// What an encoded field costs per pixel (the analogue of the spec's Table 7), measured side
// by side in one run.
//
//   build/bin/moire_fields_bench [--size WxH] [--repeat N]
//
// For every preset of stdlib/fields.moire: a vertical-line layer with the field encoded, and
// the same layer without it. The field's cost is the difference, in milliseconds per
// megapixel, on the JIT (best of N) and on the interpreter (once), with the instructions the
// field adds to the kernel. Last, a layer with no field costs the same kernel (same
// structural hash) whether or not the scene declares fields it does not use.
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;
using Clock = std::chrono::steady_clock;

namespace {

struct Compiled {
    std::unique_ptr<SceneProgram> program;
    FrameValues frame;
};

Compiled compile(const std::string& text, int w, int h) {
    CompileResult r = compileScene("bench.moire", text);
    if (!r.program) {
        fmt::print(stderr, "{}", r.diagnostics);
        std::exit(1);
    }
    Compiled c{std::move(r.program), {}};
    FrameRequest req;
    req.width = w;
    req.height = h;
    std::string diags;
    if (!evaluateFrame(*c.program, req, c.frame, diags)) {
        fmt::print(stderr, "{}", diags);
        std::exit(1);
    }
    return c;
}

// Milliseconds per megapixel: the fastest of `repeat` renders.
double msPerMpx(Backend& backend, const Compiled& c, int repeat) {
    auto kernel = backend.compile(c.program->kernel);
    KernelFrame frame{c.frame.uniforms.data(), c.frame.width, c.frame.height};
    double best = 1e30;
    for (int i = 0; i < repeat; ++i) {
        auto t0 = Clock::now();
        runKernel(*kernel, frame);
        best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best * 1e3 / (c.frame.width * static_cast<double>(c.frame.height) / 1e6);
}

std::string layer(const std::string& field) {
    std::string s =
        "scene { size = (1200, 800) }\nlayer { family = lines; spacing = 5.8; stroke = 1.5";
    if (!field.empty()) s += "; field = " + field;
    return s + " }\n";
}

} // namespace

int main(int argc, char** argv) {
    int w = 1920, h = 1080, repeat = 5;
    for (int i = 1; i + 1 < argc; ++i) {
        std::string a = argv[i];
        if (a == "--size")
            std::sscanf(argv[++i], "%dx%d", &w, &h);
        else if (a == "--repeat")
            repeat = std::max(1, std::atoi(argv[++i]));
    }
    LlvmJitBackend jit;
    InterpBackend interp;

    // The interpreter renders a smaller frame (its cost per pixel does not depend on size).
    const int iw = std::max(1, w / 4), ih = std::max(1, h / 4);
    Compiled plain = compile(layer(""), w, h), plainSmall = compile(layer(""), iw, ih);
    const double jitBase = msPerMpx(jit, plain, repeat),
                 interpBase = msPerMpx(interp, plainSmall, 1);
    const size_t baseInsts = plain.program->kernel.instCount();

    fmt::print(
        "Cost of one encoded field per pixel, {}x{} (JIT best of {}), in ms per megapixel\n\n", w,
        h, repeat);
    fmt::print("{:<16} {:>7} {:>12} {:>12} {:>9}   {:>12} {:>12}\n", "preset", "+instr", "interp",
               "JIT", "int/JIT", "layer (JIT)", "layer (int)");
    for (const char* preset : {"saddle", "dipole", "bumps", "swirl", "ripple", "terrain"}) {
        Compiled c = compile(layer(preset), w, h), small = compile(layer(preset), iw, ih);
        const double j = msPerMpx(jit, c, repeat), i = msPerMpx(interp, small, 1);
        const long added =
            static_cast<long>(c.program->kernel.instCount()) - static_cast<long>(baseInsts);
        // The field's own cost is what it adds to the same layer; timing noise can make a
        // cheap field read as slightly negative, which is shown as it was measured.
        fmt::print("{:<16} {:>7} {:>12.3f} {:>12.3f} {:>8.0f}x   {:>12.3f} {:>12.1f}\n", preset,
                   added, i - interpBase, j - jitBase,
                   (i - interpBase) / std::max(1e-9, j - jitBase), j, i);
    }
    fmt::print("{:<16} {:>7} {:>12} {:>12} {:>9}   {:>12.3f} {:>12.1f}\n", "no field", 0, "-", "-",
               "-", jitBase, interpBase);

    // A field declared but not used by a layer costs that layer nothing: its kernel is the
    // same program, not merely a similar one.
    Compiled declared = compile("field unused = saddle + terrain * dipole\n" + layer(""), w, h);
    const bool same =
        ir::structuralHash(declared.program->kernel) == ir::structuralHash(plain.program->kernel);
    fmt::print(
        "\nA layer with no field: {} kernel instructions; the same kernel when the scene declares\n"
        "fields it does not use: {}\n",
        baseInsts, same ? "yes (identical structural hash)" : "NO");
    return same ? 0 : 1;
}
