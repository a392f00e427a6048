// What an encoded field costs per pixel (the analogue of the spec's Table 7), measured side
// by side in one run.
//
//   build/bin/moire_fields_bench [--size WxH] [--repeat N]
//
// For every preset of stdlib/fields.moire: a vertical-line layer with the field encoded, and
// the same layer without it, in milliseconds per megapixel on the JIT (best of N) and on the
// interpreter (once), with the instructions the field adds to the kernel. The field's cost is
// the difference of the two, printed beside both measured times: a cheap field can measure
// faster than the plain layer (timing noise), and such a difference is no cost to divide, so
// the interpreter/JIT ratio of the costs is printed only where both stand clear of the noise.
// Last, a layer with no field costs the same kernel (same structural hash) whether or not the
// scene declares fields it does not use.
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
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

// Differences smaller than this share of the plain layer's time are not told apart from
// timing noise. On a busy machine the noise is larger: more --repeat narrows it on the JIT.
constexpr double kNoise = 0.02;

// The field's cost as a signed difference, "~0" where it is within the noise.
std::string cost(double withField, double base) {
    const double d = withField - base;
    if (std::abs(d) < kNoise * base) return fmt::format("~0 ({:+.3f})", d);
    return fmt::format("{:+.3f}", d);
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
    fmt::print("{:<10} {:>7}   {:>10} {:>16}   {:>10} {:>16}   {:>12}\n", "preset", "+instr",
               "JIT layer", "JIT field cost", "int layer", "int field cost", "int/JIT cost");
    fmt::print("{:<10} {:>7}   {:>10.3f} {:>16}   {:>10.1f} {:>16}   {:>12}\n", "no field", 0,
               jitBase, "-", interpBase, "-", "-");
    for (const char* preset : {"saddle", "dipole", "bumps", "swirl", "ripple", "terrain"}) {
        Compiled c = compile(layer(preset), w, h), small = compile(layer(preset), iw, ih);
        const double j = msPerMpx(jit, c, repeat), i = msPerMpx(interp, small, 1);
        const long added =
            static_cast<long>(c.program->kernel.instCount()) - static_cast<long>(baseInsts);
        const bool clear = j - jitBase >= kNoise * jitBase && i - interpBase >= kNoise * interpBase;
        const std::string ratio =
            clear ? fmt::format("{:.0f}x", (i - interpBase) / (j - jitBase)) : "-";
        fmt::print("{:<10} {:>7}   {:>10.3f} {:>16}   {:>10.1f} {:>16}   {:>12}\n", preset, added,
                   j, cost(j, jitBase), i, cost(i, interpBase), ratio);
    }
    fmt::print(
        "\nA field's cost is its layer's time less the plain layer's; \"~0\" is within {:.0f}%\n"
        "of the plain layer's time (timing noise), and has no ratio.\n",
        kNoise * 100);

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
