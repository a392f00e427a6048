// The walking-family solver's work, measured side by side (spec §9.1-9.2, Table 4).
//
//   build/bin/moire_walking_bench [--size WxH] [--cost-only] [--repeat N] [scene.moire ...]
//
// For seven scenes, every pixel is solved three ways and the evaluations of the radius rho
// are counted:
//  - Reference: the exhaustive stride-1 scan (tests/reference), stopping only when the
//    drift bound closes;
//  - Sweep: the fixed enumeration a renderer would use without a certificate (seed at
//    rho(p)/s, a fixed neighbourhood, Newton refinement: tests/reference/WalkingSweep, the
//    double copy of the IR's WalkingVariant::Solver::Sweep). Never shipped;
//  - Window: the shipped solver, run by the interpreter in its counting mode.
// It also reports the share of pixels whose coverage differs from the reference's by more
// than 8/255, for Sweep and Window, and the JIT's throughput on the default scene.
//
// Then the JIT's cost per evaluation, for the default scene and the walking examples (or the
// scenes given) at 1920x1080 on one thread, scalar and in lanes: the frame's CPU time, the
// interpreter's count of evaluations per pixel (on every fourth pixel of every fourth row),
// and from them and the clock the core cycles each evaluation of rho costs, so the distance
// to what the machine can do is visible. --cost-only prints that table alone.
#include "bench/BenchScenes.h"
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "compiler/lower/CameraModel.h"
#include "compiler/lower/WalkingFamily.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"
#include "tests/reference/WalkingReference.h"
#include "tests/reference/WalkingSweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;
namespace ref = moire::reference;

namespace {

struct Layer {
    const char* family; // circles, triangles, squares, hexagons
    int facets;
    double spacing, phase, offsetX, offsetY, turnDeg, stroke;
};

struct Scene {
    const char* name;
    double zoom;
    std::vector<Layer> layers;
};

// The seven scenes of the spec's Table 4, in our own parameters.
std::vector<Scene> scenes() {
    return {
        {"Triangle, rotation", 1.0, {{"triangles", 3, 8, 0, 0, 0, 1.2, 1.5}}},
        {"Hexagon, rotation, zoomed out", 0.25, {{"hexagons", 6, 8, 0, 0, 0, 0.8, 1.5}}},
        {"Triangle, translation", 1.0, {{"triangles", 3, 8, 0, 1.5, 0.6, 0, 1.5}}},
        {"Triangle, offset = spacing", 1.0, {{"triangles", 3, 8, 0, 8, 0, 0.4, 1.5}}},
        {"Square, rotation + translation", 1.0, {{"squares", 4, 8, 0, 1.2, 0.5, 0.9, 1.5}}},
        {"Deep zoom-out, small rotation", 0.12, {{"squares", 4, 6, 0, 0, 0, 0.15, 1.5}}},
        {"Two circle families, interfering",
         1.0,
         {{"circles", 0, 7, 0, 0.9, 0.2, 0.6, 1.6}, {"circles", 0, 7, 0, -0.9, 0.2, -0.6, 1.6}}},
    };
}

std::string sceneText(const Scene& s, int w, int h) {
    std::string t =
        fmt::format("scene {{ size = ({}, {}) }}\ncamera {{ zoom = {} }}\n", w, h, s.zoom);
    for (const Layer& l : s.layers)
        t += fmt::format(
            "layer {{ family = {}; spacing = {}; phase = {}; offset = ({}, {}); turn = {}deg; "
            "stroke = {} }}\n",
            l.family, l.spacing, l.phase, l.offsetX, l.offsetY, l.turnDeg, l.stroke);
    return t;
}

ref::Walking walking(const Layer& l) {
    return {l.facets,  l.spacing, l.phase,
            l.offsetX, l.offsetY, l.turnDeg * std::numbers::pi / 180.0};
}

double coverage(double d, double h, double a) {
    double u = std::clamp((d - (h - a)) / (2 * a), 0.0, 1.0);
    return 1.0 - u * u * (3 - 2 * u);
}

// The interpreter's environment for a w x h frame's uniforms, writing into `out`.
InterpEnv frameEnv(const FrameValues& fv, int w, int h, std::vector<double>& out) {
    InterpEnv env;
    env.imageW = w;
    env.imageH = h;
    env.uniforms = fv.uniforms.data();
    env.numUniforms = fv.uniforms.size();
    env.outputs = out.data();
    return env;
}

struct Row {
    double refEvals = 0, sweepEvals = 0, windowEvals = 0;
    double sweepDiffer = 0, windowDiffer = 0;
};

Row measure(const Scene& s, int w, int h) {
    CompileOptions opt;
    opt.layerFields = true;
    opt.tally = true;
    CompileResult r = compileScene(s.name, sceneText(s, w, h), opt);
    if (!r.program) {
        fmt::print(stderr, "{}", r.diagnostics);
        std::exit(1);
    }
    const SceneProgram& p = *r.program;
    FrameValues fv;
    std::string diags;
    if (!evaluateFrame(p, FrameRequest{}, fv, diags)) {
        fmt::print(stderr, "{}", diags);
        std::exit(1);
    }
    Interpreter interp(p.kernel);
    std::vector<double> out(p.kernel.numOutputs), regs;
    InterpEnv env = frameEnv(fv, w, h, out);

    // The scene's size is the image's, so the camera fits it at one world unit a pixel.
    lower::CameraT<double> cam;
    cam.width = w;
    cam.height = h;
    cam.pixel = lower::fitScale<double>(w, h, w, h) / s.zoom;
    cam.turned = cam.centred = false;
    Row row;
    long samples = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            env.pixelX = x + 0.5;
            env.pixelY = y + 0.5;
            interp.run(env, regs);
            const ir::Vec2T<double> world = lower::toWorld(cam, {x + 0.5, y + 0.5});
            const double wx = world.x, wy = world.y;
            // One interpreter run solves every layer; its count is shared out evenly.
            row.windowEvals += static_cast<double>(Interpreter::lastTally(lower::kRadiusTally));
            for (size_t i = 0; i < s.layers.size(); ++i) {
                const Layer& l = s.layers[i];
                const lower::StrokeBandT<double> band = lower::strokeBandOf(l.stroke, cam.pixel);
                const double hw = band.h, a = band.a;
                const double guard = lower::walkGuard(band, l.spacing);
                ref::Walking wk = walking(l);
                ref::Nearest exact = ref::nearest(wk, wx, wy, guard);
                ref::SweepResult sw = ref::sweep(wk, wx, wy, guard, lower::kSweepNeighbours);
                row.refEvals += static_cast<double>(exact.evaluations);
                row.sweepEvals += sw.evaluations;
                const double truth = coverage(exact.distance, hw, a);
                const double window =
                    coverage(out[p.layout.distanceSlot(static_cast<int>(i))], hw, a);
                row.windowDiffer += std::fabs(window - truth) > 8.0 / 255;
                row.sweepDiffer += std::fabs(coverage(sw.distance, hw, a) - truth) > 8.0 / 255;
                ++samples;
            }
        }
    }
    row.refEvals /= samples;
    row.sweepEvals /= samples;
    row.windowEvals /= samples;
    row.sweepDiffer /= samples;
    row.windowDiffer /= samples;
    return row;
}

// JIT throughput on the embedded default scene at 1920x1080, best of five.
double defaultSceneMpxPerSecond() {
    EmbeddedScene d = defaultScene();
    CompileResult r = compileScene(d.path, d.text);
    FrameRequest req;
    req.width = 1920;
    req.height = 1080;
    FrameValues fv;
    std::string diags;
    if (!r.program || !evaluateFrame(*r.program, req, fv, diags)) return 0.0;
    LlvmJitBackend jit;
    auto kernel = jit.compile(r.program->kernel);
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    double best = 1e30;
    for (int i = 0; i < 5; ++i) {
        auto t0 = std::chrono::steady_clock::now();
        runKernel(*kernel, frame);
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return 1920.0 * 1080.0 / 1e6 / best;
}

// The "cpu MHz" of /proc/cpuinfo's first processor, in Hz (0 when there is none).
double cpuinfoClockHz() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("cpu MHz", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos) return std::atof(line.c_str() + colon + 1) * 1e6;
        }
    return 0.0;
}

// CPU seconds this process has run, on every thread: unlike the wall clock, it does not count
// the time other work on a shared machine holds the core.
double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The core clock in Hz. Measured: a chain of dependent integer additions retires one a
// cycle, so additions per second is the clock the kernel actually ran at (a virtual machine's
// /proc/cpuinfo gives the nominal rate, and turbo moves it). Elsewhere, /proc/cpuinfo.
double measuredClockHz() {
#if defined(__x86_64__)
    uint64_t x = 0;
    constexpr int kRounds = 2'000'000;
    double best = 0;
    for (int trial = 0; trial < 5; ++trial) {
        double t0 = cpuSeconds();
        for (int i = 0; i < kRounds; ++i)
            asm volatile(".rept 100\n\taddq $1, %0\n\t.endr" : "+r"(x)); // 100 in a chain
        double t = cpuSeconds() - t0;
        best = std::max(best, 100.0 * kRounds / t);
    }
    return best;
#else
    return cpuinfoClockHz();
#endif
}

// The scenes whose layers walk: the default scene and the walking examples.
std::vector<bench::Scene> walkingScenes() {
    EmbeddedScene d = defaultScene();
    std::vector<bench::Scene> out{{"default", d.path, d.text}};
    for (const char* name : {"walking_triangles", "walking_squares", "unwinding_walk"})
        out.push_back(
            bench::sceneFile(fmt::format("{}/examples/{}.moire", MOIRE_SOURCE_DIR, name)));
    return out;
}

bool frameOf(const SceneProgram& p, int w, int h, FrameValues& fv) {
    FrameRequest req;
    req.width = w;
    req.height = h;
    std::string diags;
    if (evaluateFrame(p, req, fv, diags)) return true;
    fmt::print(stderr, "{}", diags);
    return false;
}

// Evaluations of rho per pixel, counted by the interpreter on every fourth pixel of every
// fourth row (the tally counts every layer's evaluations); -1 when the scene fails.
double evaluationsPerPixel(const bench::Scene& s, int w, int h) {
    CompileOptions opt;
    opt.tally = true;
    CompileResult r = compileScene(s.path, s.text, opt);
    FrameValues fv;
    if (!r.program || !frameOf(*r.program, w, h, fv)) return -1;
    Interpreter interp(r.program->kernel);
    std::vector<double> out(r.program->kernel.numOutputs);
    InterpEnv env = frameEnv(fv, w, h, out);
    return interp.meanTally(env, 1, 4, lower::kRadiusTally);
}

// CPU seconds for the JIT (with `lanes` pixels a step) to render one frame on one thread:
// the fastest of `repeat`.
double jitFrameSeconds(const bench::Scene& s, int w, int h, int repeat, int lanes) {
    CompileResult r = compileScene(s.path, s.text);
    FrameValues fv;
    if (!r.program || !frameOf(*r.program, w, h, fv)) return -1;
    LlvmJitBackend::Options options;
    options.lanes = lanes;
    LlvmJitBackend jit(options);
    auto kernel = jit.compile(r.program->kernel);
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    ExecOptions one;
    one.threads = 1;
    double best = 1e30;
    for (int i = 0; i < repeat; ++i) {
        double t0 = cpuSeconds();
        runKernel(*kernel, frame, one);
        best = std::min(best, cpuSeconds() - t0);
    }
    return best;
}

// The cost table: cycles per evaluation of rho = frame CPU seconds x clock / (pixels x
// evaluations per pixel), for the scalar JIT (one pixel a step) and the JIT in lanes. A
// kernel of L lanes spending C core cycles per evaluation keeps each lane L x C cycles on
// one: the "per lane" figure, which is the scalar one when the lanes buy nothing.
void costTable(const std::vector<bench::Scene>& scenes, int repeat) {
    constexpr int w = 1920, h = 1080;
    const double clock = measuredClockHz(), nominal = cpuinfoClockHz();
    const int lanes = static_cast<int>(LlvmJitBackend().lanes());
    fmt::print("JIT cost per evaluation of rho, {}x{}, one thread, CPU time, best of {}\n", w, h,
               repeat);
    fmt::print(
        "clock {:.0f} MHz (dependent additions), /proc/cpuinfo says {:.0f} MHz; lanes: {}\n\n",
        clock / 1e6, nominal / 1e6, lanes);
    fmt::print("{:<18} {:>8} | {:>9} {:>11} | {:>9} {:>11} {:>9} | {:>8}\n", "", "", "scalar", "",
               "lanes", "", "", "");
    fmt::print("{:<18} {:>8} | {:>9} {:>11} | {:>9} {:>11} {:>9} | {:>8}\n", "scene", "evals/px",
               "ms/frame", "cycles/eval", "ms/frame", "cycles/eval", "per lane", "speed-up");
    const double pixels = static_cast<double>(w) * h;
    for (const bench::Scene& s : scenes) {
        double evals = evaluationsPerPixel(s, w, h);
        double scalar = jitFrameSeconds(s, w, h, repeat, 1);
        double inLanes = jitFrameSeconds(s, w, h, repeat, lanes);
        if (evals < 0 || scalar < 0 || inLanes < 0) std::exit(1);
        // With no walking layer there is nothing to divide by: the cycles read 0.
        double perEval = evals > 0 ? clock / (pixels * evals) : 0.0;
        fmt::print(
            "{:<18} {:>8.2f} | {:>9.1f} {:>11.0f} | {:>9.1f} {:>11.1f} {:>9.0f} | {:>7.2f}x\n",
            s.name, evals, scalar * 1e3, scalar * perEval, inLanes * 1e3, inLanes * perEval,
            inLanes * perEval * lanes, scalar / inLanes);
    }
}

} // namespace

int main(int argc, char** argv) {
    int w = 320, h = 200, repeat = 3;
    bool costOnly = false;
    std::vector<bench::Scene> given;
    for (int i = 1; i < argc; ++i) {
        if (bench::sizeOrRepeat(argc, argv, i, w, h, repeat)) continue;
        std::string a = argv[i];
        if (a == "--cost-only")
            costOnly = true;
        else
            given.push_back(bench::sceneFile(a));
    }
    if (costOnly) {
        costTable(given.empty() ? walkingScenes() : given, repeat);
        return 0;
    }

    fmt::print("Walking-family solver: evaluations of rho per pixel and layer, {}x{} pixels\n\n", w,
               h);
    fmt::print("{:<34} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9}\n", "scene", "Ref.", "Sweep", "Window",
               "Sweep/Win", "Sweep>8", "Window>8");
    double sumWindow = 0, sumSweep = 0, worstDiffer = 0;
    std::vector<Scene> all = scenes();
    for (const Scene& s : all) {
        Row row = measure(s, w, h);
        sumWindow += row.windowEvals;
        sumSweep += row.sweepEvals;
        worstDiffer = std::max(worstDiffer, row.windowDiffer);
        fmt::print("{:<34} {:>8.1f} {:>8.1f} {:>8.1f} {:>8.1f}x {:>8.2f}% {:>8.2f}%\n", s.name,
                   row.refEvals, row.sweepEvals, row.windowEvals, row.sweepEvals / row.windowEvals,
                   100 * row.sweepDiffer, 100 * row.windowDiffer);
    }
    double meanWindow = sumWindow / all.size(), meanSweep = sumSweep / all.size();
    fmt::print("\nmean Window {:.1f} evaluations/pixel (target <= 12), {:.1f}x fewer than Sweep "
               "(target >= 15x),\n"
               "worst share of Window pixels off the reference by > 8/255: {:.3f}% (target 0)\n",
               meanWindow, meanSweep / meanWindow, 100 * worstDiffer);
    fmt::print("JIT, default scene at 1920x1080: {:.1f} Mpx/s\n\n", defaultSceneMpxPerSecond());
    costTable(given.empty() ? walkingScenes() : given, repeat);
    return 0;
}
