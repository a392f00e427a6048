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
// Then, for two_rings, where the Vulkan path's time goes: our kernel and a plain hand-written
// GLSL kernel of the same maths, run through the same executor, with the host's time split
// into recording and submitting, waiting for the device, and copying the result out, and the
// device's own time (timestamps) into the shader and the copy to host-visible memory.
// Without a Vulkan device the Vulkan columns say why and the JIT's are still printed.
#include "bench/BenchScenes.h"
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/Compile.h"
#include "runtime/output/Render.h"
#include "runtime/vulkan/VulkanContext.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <regex>
#include <time.h>

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

// The frame's values at w x h.
FrameValues frameAt(const SceneProgram& program, int w, int h) {
    FrameValues fv;
    std::string diags;
    evaluateFrame(program, FrameRequest{.width = w, .height = h}, fv, diags);
    return fv;
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
    const FrameValues fv = frameAt(*r.program, w, h);
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

// two_rings.moire written by hand as the smallest GLSL kernel of its maths: two circle
// families (spacing 8, stroke 2.2, centres (-40, 0) and (40, 0), camera zoom 1.2 on a
// 1200 x 800 scene), each a smoothstep coverage of the distance to the nearest ring, painted
// over the background. The floor of the stroke and the antialiasing width follow the pixel
// size as the compiler's lowering does. The same interface as GlslKernel.h's, less the
// uniforms: its numbers are constants.
std::string plainTwoRings() {
    return fmt::format(R"(#version 450
layout(local_size_x = {}, local_size_y = {}, local_size_z = 1) in;
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ vec4 o[]; }} O;
layout(push_constant) uniform Frame {{ int imageW; int imageH; int x0; int y0; int w; int h; }} F;
float coverage(vec2 p, vec2 centre, float halfStroke, float aa) {{
    float phase = length(p - centre) * 0.125;
    float d = abs(phase - floor(phase + 0.5)) * 8.0;
    float t = clamp((d - (halfStroke - aa)) / (2.0 * aa), 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}}
void main() {{
    int gx = int(gl_GlobalInvocationID.x), gy = int(gl_GlobalInvocationID.y);
    if (gx >= F.w || gy >= F.h) return;
    vec2 size = vec2(F.imageW, F.imageH);
    float s = max(1200.0 / size.x, 800.0 / size.y) / 1.2;
    vec2 p = vec2(float(F.x0 + gx) + 0.5 - 0.5 * size.x, 0.5 * size.y - (float(F.y0 + gy) + 0.5)) * s;
    float halfStroke = max(1.1, s * 1.15), aa = s * 0.7;
    vec3 ink = vec3({}, {}, {});
    vec4 c = vec4({}, {}, {}, 1.0);
    float a = coverage(p, vec2(-40.0, 0.0), halfStroke, aa);
    c = vec4(mix(c.rgb, ink, a), c.a * (1.0 - a) + a);
    a = coverage(p, vec2(40.0, 0.0), halfStroke, aa);
    c = vec4(mix(c.rgb, ink, a), c.a * (1.0 - a) + a);
    O.o[gy * F.w + gx] = vec4(c.rgb / c.a, c.a);
}}
)",
                       glsl::kLocalSizeX, glsl::kLocalSizeY, 0x14 / 255.0, 0x14 / 255.0,
                       0x18 / 255.0, 0xf6 / 255.0, 0xf3 / 255.0, 0xec / 255.0);
}

// CPU time of the whole process, all threads: on a CPU device (lavapipe) the device's own
// work, and a figure that the machine's other load disturbs much less than elapsed time.
double cpuMs() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

struct Breakdown {
    double frameMs = 1e30; // host time of the whole run() (best frame)
    double cpuMs = 1e30;   // the process's CPU time during a run (least of the frames)
    vk::RunTimes times;    // of that frame
    std::vector<float> pixels;
};

Breakdown timeRuns(vk::Context& context, VkPipeline pipeline, const std::vector<float>& uniforms,
                   int w, int h, int repeat) {
    Breakdown b;
    b.pixels.assign(static_cast<size_t>(w) * h * 4, 0.0f);
    for (int i = 0; i < repeat + 1; ++i) { // the first run allocates the buffers: not timed
        vk::RunTimes t;
        auto t0 = Clock::now();
        const double c0 = cpuMs();
        context.run(pipeline, uniforms, w, h, TileRect{0, 0, w, h}, 4, b.pixels.data(),
                    static_cast<size_t>(w) * 4, vk::RunOptions{.times = &t});
        const double frame = ms(t0), cpu = cpuMs() - c0;
        if (i > 0 && frame < b.frameMs) b.frameMs = frame, b.times = t;
        if (i > 0) b.cpuMs = std::min(b.cpuMs, cpu);
    }
    return b;
}

void printBreakdownRow(const char* name, const Breakdown& b, double mpx) {
    const vk::RunTimes& t = b.times;
    fmt::print("{:<8} {:>7.1f} {:>8.1f} {:>7.1f} {:>7} {:>8.2f} {:>8.1f} {:>9.1f} {:>8}  {:>8}\n",
               name, b.frameMs, mpx / (b.frameMs / 1e3), b.cpuMs, t.chunks, t.submitMs, t.waitMs,
               t.copyOutMs, t.deviceTimes ? fmt::format("{:.1f}", t.kernelMs) : "-",
               t.deviceTimes ? fmt::format("{:.1f}", t.deviceCopyMs) : "-");
}

void vulkanBreakdown(int w, int h, int repeat, int device) {
    fmt::print("\nVulkan, where the time goes: two_rings at {}x{}, our kernel and a plain GLSL "
               "kernel of the same maths\nthrough the same executor (best of {} frames; ms)\n",
               w, h, repeat);
    Scene scene = bench::sceneFile(std::string(MOIRE_SOURCE_DIR) + "/examples/two_rings.moire");
    CompileResult r = compileScene(scene.path, scene.text);
    if (!r.program) {
        fmt::print("two_rings does not compile: {}\n", r.diagnostics);
        return;
    }
    std::shared_ptr<vk::Context> context;
    try {
        context = vk::Context::open(device);
    } catch (const std::exception& e) {
        fmt::print("unavailable: {}\n", e.what());
        return;
    }
    const FrameValues fv = frameAt(*r.program, w, h);
    std::vector<float> uniforms(fv.uniforms.begin(), fv.uniforms.end());

    VkPipeline ours = context->createPipeline(glsl::compileSpirv(r.program->kernel));
    VkPipeline plain = context->createPipeline(glsl::compileGlsl(plainTwoRings()));
    Breakdown o = timeRuns(*context, ours, uniforms, w, h, repeat);
    Breakdown p = timeRuns(*context, plain, {}, w, h, repeat);
    context->destroyPipeline(ours);
    context->destroyPipeline(plain);

    const double mpx = w * static_cast<double>(h) / 1e6;
    fmt::print("{:<8} {:>7} {:>8} {:>7} {:>7} {:>8} {:>8} {:>9} {:>8}  {:>8}\n", "kernel", "frame",
               "Mpx/s", "cpu", "chunks", "submit", "wait", "copy-out", "shader", "dev-copy");
    printBreakdownRow("ours", o, mpx);
    printBreakdownRow("plain", p, mpx);
    // No ratio of times too small to measure (a copy that did not happen).
    auto ratio = [](double a, double b) {
        return b >= 0.05 ? fmt::format("{:.2f}x", a / b) : std::string("-");
    };
    const vk::RunTimes &ot = o.times, &pt = p.times;
    fmt::print("{:<8} {:>7} {:>8} {:>7} {:>7} {:>8} {:>8} {:>9} {:>8}  {:>8}\n", "ours/pl.",
               ratio(o.frameMs, p.frameMs), "", ratio(o.cpuMs, p.cpuMs), "",
               ratio(ot.submitMs, pt.submitMs), ratio(ot.waitMs, pt.waitMs),
               ratio(ot.copyOutMs, pt.copyOutMs),
               ot.deviceTimes ? ratio(ot.kernelMs, pt.kernelMs) : "-",
               ot.deviceTimes ? ratio(ot.deviceCopyMs, pt.deviceCopyMs) : "-");
    double worst = 0;
    for (size_t i = 0; i < o.pixels.size(); ++i)
        worst = std::max(worst, static_cast<double>(std::fabs(o.pixels[i] - p.pixels[i])));
    fmt::print(
        "the two kernels' outputs differ by at most {:.2g} (the same maths: under 0.01)\n"
        "cpu: the process's CPU time in the frame, all threads (the device's, on a CPU device);\n"
        "submit: recording and submitting; wait: blocked on the device; copy-out: into the "
        "caller's image;\nshader, dev-copy: the device's timestamps around the dispatch "
        "and the copy to host-visible memory.\n",
        worst);
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
        "compile: the backend's compile call (LLVM's passes and machine code; or SPIR-V and the "
        "Vulkan\n"
        "pipeline). rebuild: the scene with a number changed, front end included, kernel from the\n"
        "cache ('!' marks a rebuild that missed it).\n");
    vulkanBreakdown(w, h, repeat, device);
    return 0;
}
