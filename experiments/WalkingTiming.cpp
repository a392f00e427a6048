#include "experiments/WalkingTiming.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "compiler/lower/WalkingFamily.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>

namespace moire::exp {

namespace {

// The compiled scene and its frame's values, or an exit with the diagnostics.
struct Compiled {
    std::unique_ptr<SceneProgram> program;
    FrameValues frame;
};
Compiled compile(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h, bool tally) {
    CompileOptions opt;
    opt.walking = v;
    opt.tally = tally;
    // The paper's tables time and judge the solver's point-sampled picture (§9): under the mean
    // filter the ink also reads the distance inside the stroke, which the accept early exit
    // (§7.1) leaves to whichever member it met first.
    opt.filter = sema::FilterMode::Point;
    CompileResult r = compileScene(s.name, walkingSceneText(s, w, h), opt);
    Compiled out;
    std::string diags = r.diagnostics;
    FrameRequest req;
    req.width = w;
    req.height = h;
    if (!r.program || !evaluateFrame(*r.program, req, out.frame, diags)) {
        std::fprintf(stderr, "%s: %s\n", s.name.c_str(), diags.c_str());
        std::exit(1);
    }
    out.program = std::move(r.program);
    return out;
}

// CPU seconds this process has run on every thread: unlike the wall clock, not the time
// other work on a shared machine holds the core.
double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

} // namespace

std::string walkingSceneText(const WalkingScene& s, int w, int h) {
    return "scene { size = (" + std::to_string(w) + ", " + std::to_string(h) + ") }\n" + s.body +
           "\n";
}

int jitLanes() {
    return static_cast<int>(LlvmJitBackend().lanes());
}

double jitSeconds(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h, int lanes,
                  int repeat) {
    Compiled c = compile(s, v, w, h, false);
    LlvmJitBackend::Options options;
    options.lanes = lanes;
    LlvmJitBackend jit(options);
    auto kernel = jit.compile(c.program->kernel);
    KernelFrame frame{c.frame.uniforms.data(), c.frame.width, c.frame.height};
    ExecOptions one;
    one.threads = 1;
    // At least `repeat` runs, and for a fast frame more, up to half a second of them: the
    // fastest of many is what a busy shared machine lets through.
    double best = INFINITY, spent = 0.0;
    for (int i = 0; i < repeat || (repeat > 1 && spent < 0.5 && i < 50); ++i) {
        const double t0 = cpuSeconds();
        runKernel(*kernel, frame, one);
        const double t = cpuSeconds() - t0;
        best = std::min(best, t);
        spent += t;
    }
    return best;
}

double evaluationsPerPixel(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h,
                           int step) {
    Compiled c = compile(s, v, w, h, true);
    Interpreter interp(c.program->kernel);
    std::vector<double> out(c.program->kernel.numOutputs);
    InterpEnv env;
    env.imageW = w;
    env.imageH = h;
    env.uniforms = c.frame.uniforms.data();
    env.numUniforms = c.frame.uniforms.size();
    env.outputs = out.data();
    return interp.meanTally(env, step / 2, step, lower::kRadiusTally);
}

Image jitImage(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h) {
    Compiled c = compile(s, v, w, h, false);
    LlvmJitBackend jit;
    auto kernel = jit.compile(c.program->kernel);
    KernelFrame frame{c.frame.uniforms.data(), c.frame.width, c.frame.height};
    return runKernel(*kernel, frame);
}

double shareDiffering(const Image& a, const Image& b, double tolerance) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels) return 1.0;
    size_t off = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        off += std::fabs(double(a.pixels[i]) - double(b.pixels[i])) > tolerance;
    return a.pixels.empty() ? 0.0 : double(off) / double(a.pixels.size());
}

double inkOf(const Image& img) {
    double ink = 0, n = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i)
        if (img.channels < 4 || i % img.channels != 3) ink += 1.0 - img.pixels[i], ++n;
    return n > 0 ? ink / n : 0.0;
}

std::string ratio(double r) {
    char buf[32];
    std::snprintf(buf, sizeof buf, r >= 10 ? "%.1fx" : "%.2fx", r);
    return buf;
}

} // namespace moire::exp
