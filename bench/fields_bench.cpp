// What an encoded field costs per pixel (the analogue of the spec's Table 7), measured side
// by side in one run.
//
//   build/bin/moire_fields_bench [--size WxH] [--repeat N]
//
// For every preset of stdlib/fields.moire: a vertical-line layer with the field encoded, and
// the same layer without it, rendered in turn, in milliseconds per megapixel on the JIT (best
// of N) and on the interpreter (once), with the instructions the field adds to the kernel. The
// field's cost is the difference of the two, printed beside both measured times: a cheap field
// can measure faster than the plain layer (timing noise), and such a difference is no cost to
// divide, so the interpreter/JIT ratio of the costs is printed only where both stand clear of
// the noise.
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

struct SideBySide {
    double plain, field; // milliseconds per megapixel
};

// The fastest of `repeat` renders of each of two layers of the same size, rendered in turn,
// so that both see the same load on the machine: a baseline measured once, apart, can catch
// a busy moment and come out slower than the layers it is subtracted from.
SideBySide msPerMpx(Backend& backend, const Compiled& plain, const Compiled& field, int repeat) {
    auto plainKernel = backend.compile(plain.program->kernel);
    auto fieldKernel = backend.compile(field.program->kernel);
    auto time = [](const CompiledKernel& kernel, const Compiled& c) {
        KernelFrame frame{c.frame.uniforms.data(), c.frame.width, c.frame.height};
        auto t0 = Clock::now();
        runKernel(kernel, frame);
        return std::chrono::duration<double>(Clock::now() - t0).count();
    };
    double bestPlain = 1e30, bestField = 1e30;
    for (int i = 0; i < repeat; ++i) {
        bestPlain = std::min(bestPlain, time(*plainKernel, plain));
        bestField = std::min(bestField, time(*fieldKernel, field));
    }
    const double mpx = plain.frame.width * static_cast<double>(plain.frame.height) / 1e6;
    return {bestPlain * 1e3 / mpx, bestField * 1e3 / mpx};
}

// Differences smaller than this share of the plain layer's time are not told apart from
// timing noise. On a busy machine the noise is larger: more --repeat narrows it on the JIT.
constexpr double kNoise = 0.02;

// The field's cost as a signed difference, "~0" where it is within the noise.
std::string cost(double withField, double base) {
    const double d = withField - base;
    if (std::abs(d) < kNoise * base) return "~0";
    return base < 100 ? fmt::format("{:+.3f}", d) : fmt::format("{:+.1f}", d);
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
    const size_t baseInsts = plain.program->kernel.instCount();

    fmt::print(
        "Cost of one encoded field per pixel, {}x{} (JIT best of {}), in ms per megapixel\n\n", w,
        h, repeat);
    fmt::print("{:<8} {:>6}   {:>24}   {:>26}   {:>7}\n", "", "", "JIT", "interpreter", "int/JIT");
    fmt::print("{:<8} {:>6}   {:>7} {:>7} {:>8}   {:>7} {:>7} {:>10}   {:>7}\n", "preset", "+instr",
               "plain", "field", "cost", "plain", "field", "cost", "cost");
    for (const char* preset : {"saddle", "dipole", "bumps", "swirl", "ripple", "terrain"}) {
        Compiled c = compile(layer(preset), w, h), small = compile(layer(preset), iw, ih);
        const SideBySide j = msPerMpx(jit, plain, c, repeat);
        const SideBySide i = msPerMpx(interp, plainSmall, small, 1);
        const long added =
            static_cast<long>(c.program->kernel.instCount()) - static_cast<long>(baseInsts);
        const bool clear =
            j.field - j.plain >= kNoise * j.plain && i.field - i.plain >= kNoise * i.plain;
        const std::string ratio =
            clear ? fmt::format("{:.0f}x", (i.field - i.plain) / (j.field - j.plain)) : "-";
        fmt::print("{:<8} {:>6}   {:>7.3f} {:>7.3f} {:>8}   {:>7.1f} {:>7.1f} {:>10}   {:>7}\n",
                   preset, added, j.plain, j.field, cost(j.field, j.plain), i.plain, i.field,
                   cost(i.field, i.plain), ratio);
    }
    fmt::print(
        "\nplain: the layer without a field; field: with it, the two rendered in turn;\n"
        "cost: field - plain, \"~0\" within {:.0f}% of plain (timing noise), with no ratio.\n",
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
