#include "runtime/cli/Commands.h"

#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/backend/js/JsFrame.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/cli/Region.h"
#include "runtime/cli/Shared.h"
#include "runtime/cli/StopSignals.h"
#include "runtime/FloorNote.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/ImageStream.h"
#include "runtime/output/MemoryBudget.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/Render.h"
#include "runtime/print/PhysicalSize.h"
#include "runtime/TextFile.h"
#include "runtime/vulkan/VulkanBackend.h"
#include "runtime/vulkan/VulkanContext.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <future>
#include <optional>
#include <unistd.h>

namespace moire::cli {

namespace fs = std::filesystem;

// The helpers every command shares: Shared.h.

bool readScene(const std::string& path, Source& out) {
    if (path.empty()) {
        EmbeddedScene d = defaultScene();
        out = {d.path, d.text};
        return true;
    }
    std::string reason;
    if (path == kStdinPath) {
        out.path = "<stdin>"; // as diagnostics name it
        if (readStandardInput(out.text, reason)) return true;
        fmt::print(stderr, "moire: error: cannot read the scene from standard input: {}\n", reason);
        return false;
    }
    out.path = path;
    if (readWholeFile(path, out.text, reason)) return true;
    fmt::print(stderr, "moire: error: cannot read '{}': {}\n", path, reason);
    return false;
}

std::unique_ptr<SceneProgram> compileOrReport(const Source& src, const CompileOptions& options) {
    CompileResult r = compileScene(src.path, src.text, options);
    if (!r.diagnostics.empty()) fmt::print(stderr, "{}", r.diagnostics);
    return std::move(r.program);
}

namespace {

// One side of a size: decimal digits only (no sign, space or exponent), 1 to maxSide.
// from_chars reports a value past int's range instead of wrapping it, as sscanf's %d did
// ("4294967297" read as 1).
bool parseSide(std::string_view t, int& v, int maxSide) {
    if (t.empty() || t.size() > 9 ||
        !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    int n = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
    if (ec != std::errc() || end != t.data() + t.size() || n < 1 || n > maxSide) return false;
    v = n;
    return true;
}

} // namespace

bool parseSize(const std::string& s, int& w, int& h, int maxSide) {
    const size_t x = s.find_first_of("xX");
    if (x == std::string::npos) return false;
    const std::string_view all(s);
    int pw = 0, ph = 0;
    if (!parseSide(all.substr(0, x), pw, maxSide) || !parseSide(all.substr(x + 1), ph, maxSide))
        return false;
    w = pw, h = ph;
    return true;
}

bool checkTime(double t, const char* option) {
    if (std::isfinite(t)) return true;
    fmt::print(stderr, "moire: error: {} must be a finite time in seconds, not {}\n", option, t);
    return false;
}

bool checkDpi(double dpi) {
    // 0 is the default: no resolution recorded. Stored as a 32-bit float in the file.
    if (dpi == 0.0 || (std::isfinite(dpi) && dpi > 0.0 && dpi <= kMaxDpi)) return true;
    fmt::print(stderr,
               "moire: error: --dpi must be a number of dots per inch above 0 and at most {:.0f} "
               "(or 0: none recorded), not {}\n",
               kMaxDpi, dpi);
    return false;
}

bool checkMemory(const FrameFootprint& frame) {
    const std::string problem = memoryProblem(frame);
    if (problem.empty()) return true;
    fmt::print(stderr, "moire: error: {}\n", problem);
    return false;
}

bool parseDepth(const std::string& s, PixelDepth& d) {
    if (s.empty())
        d = PixelDepth::Default;
    else if (s == "8")
        d = PixelDepth::U8;
    else if (s == "16")
        d = PixelDepth::U16;
    else if (s == "half")
        d = PixelDepth::Half;
    else if (s == "float" || s == "32")
        d = PixelDepth::Float;
    else
        return false;
    return true;
}

std::string describe(const Backend& backend) {
    if (auto* vk = dynamic_cast<const VulkanBackend*>(&backend))
        return "vulkan on " + vk->deviceName();
    return backend.name();
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Stages::Stages(const Verbosity& verbosity)
    : verbose_(verbosity.verbose), last_(std::chrono::steady_clock::now()) {}

void Stages::done(const std::string& what) {
    const auto now = std::chrono::steady_clock::now();
    if (verbose_)
        fmt::print(stderr, "moire: {} ({:.1f} ms)\n", what,
                   std::chrono::duration<double, std::milli>(now - last_).count());
    last_ = now;
}

std::unique_ptr<Backend> openBackend(const std::string& name, int device) {
    try {
        return makeBackend(name, BackendOptions{.device = device, .cacheKernels = true});
    } catch (const BackendError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return nullptr;
    }
}

bool checkImageOptions(const ImageArgs& args, ImageOptions& out) {
    if (!args.size.empty() && !parseSize(args.size, out.width, out.height, args.maxSide)) {
        fmt::print(stderr,
                   "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to {}), not '{}'\n",
                   args.maxSide, args.size);
        return false;
    }
    if (!parseDepth(args.depth, out.depth)) {
        fmt::print(stderr, "moire: error: --depth must be 8, 16, half or float, not '{}'\n",
                   args.depth);
        return false;
    }
    out.output = args.output;
    if (out.output.empty())
        out.output = (args.scene.empty()         ? std::string("default")
                      : args.scene == kStdinPath ? std::string("stdin")
                                                 : fs::path(args.scene).stem().string()) +
                     ".png";
    out.format = out.output == kStdoutPath ? std::string("png") : imageFormatOf(out.output);
    if (out.format.empty()) {
        fmt::print(
            stderr,
            "moire: error: cannot write '{}': unknown image format; use .png, .tif, .exr or .jpg\n",
            out.output);
        return false;
    }
    if (std::string problem = depthProblem(out.format, out.depth); !problem.empty()) {
        fmt::print(stderr, "moire: error: cannot write '{}': {}\n", out.output, problem);
        return false;
    }
    return checkBackendArgs(args.backend, args.device);
}

bool checkBackendArgs(const std::string& backend, int device) {
    const std::vector<std::string>& names = backendNames();
    if (!backend.empty() && std::find(names.begin(), names.end(), backend) == names.end()) {
        fmt::print(stderr, "moire: error: unknown backend '{}'; the backends are {}\n", backend,
                   fmt::join(names, ", "));
        return false;
    }
    if (device >= 0 && !backend.empty() && backend != "vulkan") {
        fmt::print(stderr, "moire: error: --device chooses a Vulkan device; it needs --backend "
                           "vulkan\n");
        return false;
    }
    return true;
}

namespace {

// A name given to `flag` (--view, --filter), read by `named` into `out` when given; false,
// after an error that lists the names (`list`), when it names none.
template <class T, class Named>
bool namedOption(const char* flag, const std::string& given, Named named, const std::string& list,
                 std::optional<T>& out) {
    if (given.empty()) return true;
    out = named(given);
    if (out) return true;
    fmt::print(stderr, "moire: error: {} must be {}, not '{}'\n", flag, list, given);
    return false;
}

// --view, --overlay, --filter, --envelope-gain and --envelope-taps, into the compile options.
bool checkViewOptions(const RenderArgs& args, CompileOptions& options) {
    if (args.overlay) options.overlay = true;
    if (!namedOption("--view", args.view, sema::viewNamed, sema::viewList(), options.view) ||
        !checkFilterOption(args.filter, options))
        return false;
    if (args.envelopeGain) {
        if (!std::isfinite(*args.envelopeGain) || std::abs(*args.envelopeGain) > 1e6) {
            fmt::print(stderr,
                       "moire: error: --envelope-gain must be a number from -1e6 to 1e6, "
                       "not {}\n",
                       *args.envelopeGain);
            return false;
        }
        options.envelopeGain = args.envelopeGain;
    }
    if (args.envelopeTaps) {
        const double m = *args.envelopeTaps;
        if (!(m >= 1 && m <= sema::kMaxEnvelopeTaps && m == std::floor(m))) {
            fmt::print(stderr,
                       "moire: error: --envelope-taps must be a whole number from 1 to {}, "
                       "not {}\n",
                       sema::kMaxEnvelopeTaps, m);
            return false;
        }
        options.envelopeTaps = args.envelopeTaps;
    }
    return true;
}

} // namespace

std::string filterHelp() {
    return "How strokes are sampled: " + sema::filterList() +
           " (default: the scene's filter, else mean; docs/filtering.md)";
}

bool checkFilterOption(const std::string& given, CompileOptions& options) {
    return namedOption("--filter", given, sema::filterNamed, sema::filterList(), options.filter);
}

int render(const RenderArgs& args) {
    if (!checkTime(args.time, "--time") || !checkDpi(args.dpi)) return kExitUsage;
    CompileOptions compileOptions;
    if (!checkViewOptions(args, compileOptions)) return kExitUsage;
    ImageOptions image;
    std::string size, why; // --size in pixels, or on paper at --dpi (PhysicalSize.h)
    if (!print::sizeInPixels(args.size, args.dpi, kMaxImageSide, size, why)) {
        fmt::print(stderr, "moire: error: {}\n", why);
        return kExitUsage;
    }
    if (!checkImageOptions({args.scene, args.output, size, args.depth, args.backend, args.device},
                           image))
        return kExitUsage;
    const int w = image.width, h = image.height;
    const bool toStdout = image.output == kStdoutPath;
    if (toStdout && isatty(STDOUT_FILENO)) {
        fmt::print(stderr, "moire: error: -o - writes a PNG to standard output, which is a "
                           "terminal; redirect it to a file or a pipe\n");
        return kExitUsage;
    }
    if (args.compression != -1 && (args.compression < 0 || args.compression > 9)) {
        fmt::print(stderr,
                   "moire: error: --compression must be a zlib level from 0 (none) to 9 "
                   "(smallest), not {}\n",
                   args.compression);
        return kExitUsage;
    }
    if (args.compression != -1 && image.format != "png") {
        fmt::print(stderr,
                   "moire: error: --compression sets a PNG's zlib level; '{}' is not a PNG\n",
                   image.output);
        return kExitUsage;
    }
    std::optional<Region> region;
    if (!args.region.empty()) {
        std::string why;
        if (!(region = parseRegion(args.region, why))) {
            fmt::print(stderr, "moire: error: --region {}\n", why);
            return kExitUsage;
        }
        if (image.format == "jpeg") {
            fmt::print(stderr,
                       "moire: error: --region: a JPEG cannot record where the region sits in "
                       "its frame; write the region as .png, .tif or .exr\n");
            return kExitUsage;
        }
    }
    const std::string output = toStdout ? std::string("standard output") : image.output;
    // From here on SIGINT and SIGTERM stop the render between tiles: status 128 + the
    // signal, a line saying so, and no file (and no temporary) written.
    StopSignals signals;
    auto interrupted = [&] {
        fmt::print(stderr, "moire: interrupted: {} was not written\n", output);
        return 128 + StopSignals::received();
    };
    // The JIT (the default backend, which cannot be missing) starts LLVM on another thread
    // while the scene is read and compiled: a few milliseconds of every render. Another
    // backend is opened first, so that a missing device is said before anything else.
    const bool jitBackend = args.backend == "jit";
    std::future<std::unique_ptr<Backend>> opening;
    std::unique_ptr<Backend> backend;
    if (jitBackend)
        opening = std::async(std::launch::async, [&] { return openBackend("jit", -1); });
    else if (!(backend = openBackend(args.backend, args.device)))
        return kExitMachine;

    auto t0 = std::chrono::steady_clock::now();
    Stages stages(args.verbosity);
    Source src;
    if (!readScene(args.scene, src)) return kExitIo;
    compileOptions.defines = args.defines;
    auto program = compileOrReport(src, compileOptions);
    if (!program) return kExitScene;
    if (opening.valid() && !(backend = opening.get())) return kExitMachine;
    stages.done(fmt::format("compiled {}", src.path));
    if (StopSignals::received()) return interrupted();
    const double compiledAt = secondsSince(t0);

    FrameRequest req;
    req.time = args.time;
    req.width = w;
    req.height = h;
    FrameValues frame;
    std::string diags;
    if (!evaluateFrame(*program, req, frame, diags)) {
        fmt::print(stderr, "{}", diags);
        return kExitScene;
    }
    if (!args.verbosity.quiet)
        fmt::print(stderr, "{}",
                   strokeFloorNotes(*program, compileOptions.filter, frame.pixelSize));
    // The image: the frame, or its region (the kernel still sees the whole frame).
    ExecOptions exec;
    WriteOptions wo;
    int outW = frame.width, outH = frame.height;
    if (region) {
        if (std::string why = regionProblem(*region, frame.width, frame.height); !why.empty()) {
            fmt::print(stderr, "moire: error: --region {}\n", why);
            return kExitUsage;
        }
        exec.region = TileRect{region->x0, region->y0, region->x1, region->y1};
        outW = region->width(), outH = region->height();
        // A region that is the whole frame is written as the whole frame.
        if (outW != frame.width || outH != frame.height) {
            wo.originX = region->x0, wo.originY = region->y0;
            wo.fullWidth = frame.width, wo.fullHeight = frame.height;
        }
    }
    // The size may be the scene's own: checked against the format once it is known.
    if (std::string problem = sizeProblem(image.format, outW, outH); !problem.empty()) {
        fmt::print(stderr, "moire: error: cannot write '{}': {}\n", output, problem);
        return kExitUsage;
    }
    wo.depth = image.depth;
    wo.dpi = args.dpi;
    wo.compression = args.compression;
    wo.threads = args.threads;
    // Every format and backend is streamed: the kernel runs band by band and each band goes
    // to the file as soon as the bands above it have (ImageStream.h), so no image of the whole
    // frame is made and memory is bounded by a few bands.
    FrameFootprint footprint;
    footprint.width = outW;
    footprint.height = outH;
    footprint.channels = program->kernel.numOutputs;
    footprint.format = image.format;
    footprint.gpu = args.backend == "vulkan";
    footprint.sink = FrameSink::Streamed;
    footprint.threads = args.threads;
    footprint.depth = image.depth;
    footprint.streamed = !toStdout;
    if (!checkMemory(footprint)) return kExitMachine;

    exec.threads = args.threads;
    exec.cancelled = [] { return StopSignals::received() != 0; };
    bool tty = isatty(fileno(stderr));
    bool shown = false;
    if (!args.verbosity.quiet) {
        exec.progress = [&](double fraction) {
            // Only renders that take over a second get a progress line.
            if (secondsSince(t0) < 1.0 || !tty) return;
            fmt::print(stderr, "\rmoire: rendering {}x{} on {} {:3.0f}%", outW, outH,
                       backend->name(), fraction * 100.0);
            std::fflush(stderr);
            shown = true;
        };
    }
    std::unique_ptr<ImageStream> stream;
    BandTimes times;
    double kernelCompile = 0.0;
    try {
        const auto c0 = std::chrono::steady_clock::now();
        std::unique_ptr<CompiledKernel> kernel = backend->compile(program->kernel);
        kernelCompile = secondsSince(c0);
        const KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
        stream = openImageStream(toStdout ? kStdoutPath : output, image.format, outW, outH, wo);
        const int channels = kernel->numOutputs();
        const int bandRows = stream->bandRows();
        runKernelInBands(
            *kernel, kf, exec, bandRows,
            [&](int band, int first, int count, const float* rows, size_t stride) {
                stream->addRows(band * bandRows + first, count, rows, stride, channels);
            },
            &times, kPngStepRows);
    } catch (const BackendError& e) { // the device lost, or out of memory
        if (shown) fmt::print(stderr, "\n");
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitMachine;
    } catch (const IoError& e) {
        if (shown) fmt::print(stderr, "\n");
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    if (StopSignals::received()) {
        if (shown) fmt::print(stderr, "\n");
        stream.reset(); // the temporary goes, the file is never made
        return interrupted();
    }
    std::string cached;
    if (auto* jit = dynamic_cast<const LlvmJitBackend*>(backend.get()); jit && jit->storeHits())
        cached = fmt::format(" ({} module{} of compiled code from the cache)", jit->storeHits(),
                             jit->storeHits() == 1 ? "" : "s");
    double renderedAt = secondsSince(t0);
    if (times.kernel + times.sink > 0) {
        // Kernel and encoder ran interleaved on the same threads: their wall time (the
        // kernel's compile aside) is split in proportion to the thread time each took.
        const double pipeline = renderedAt - compiledAt - kernelCompile;
        renderedAt -= pipeline * times.sink / (times.kernel + times.sink);
    }

    if (shown) fmt::print(stderr, "\n");
    stages.done(fmt::format("rendered {}x{} on {}{}", outW, outH, describe(*backend), cached));
    // The end of the file (a PNG's last chunk, a TIFF's directory, the fsync of gigabytes)
    // is a stage of its own on the progress line, not a bar sitting at 100%.
    if (shown) {
        fmt::print(stderr, "moire: writing {}...", output);
        std::fflush(stderr);
    }
    try {
        stream->finish();
    } catch (const IoError& e) {
        if (shown) fmt::print(stderr, "\n");
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    if (shown) fmt::print(stderr, " done\n");
    stages.done(fmt::format("wrote {}", output));
    double seconds = secondsSince(t0);
    // The whole time, then where it went: reading and compiling the scene, evaluating the
    // frame and running the kernel (the backend's kernel compile included), and encoding and
    // writing the file (the encoder's share of the pipeline, and ending the file).
    if (!args.verbosity.quiet)
        fmt::print(stderr,
                   "moire: wrote {} ({}x{}, {}, {:.0f} ms: compile {:.0f}, render {:.0f}, "
                   "encode and write {:.0f})\n",
                   output, outW, outH, describe(*backend), seconds * 1000.0, compiledAt * 1000.0,
                   (renderedAt - compiledAt) * 1000.0, (seconds - renderedAt) * 1000.0);
    return kExitOk;
}

int check(const CheckArgs& args) {
    if (args.format == "json") return checkJson(args.scenes);
    int status = kExitOk;
    auto fail = [&](int code) {
        if (status == kExitOk) status = code;
    };
    for (const std::string& path : args.scenes) {
        Stages stages(args.verbosity);
        Source src;
        if (!readScene(path, src)) {
            fail(kExitIo);
            continue;
        }
        auto program = compileOrReport(src);
        if (!program) {
            fail(kExitScene);
            continue;
        }
        FrameValues frame;
        std::string diags;
        if (!evaluateFrame(*program, FrameRequest{}, frame, diags)) {
            fmt::print(stderr, "{}", diags);
            fail(kExitScene);
            continue;
        }
        if (args.verbosity.verbose) {
            std::string timings;
            for (const TimingValues& t : frame.timings)
                timings +=
                    fmt::format("{}{} {:g} s", timings.empty() ? "" : ", ", t.name, t.cycle());
            stages.done(fmt::format("checked {}: {}x{}, timings: {}", src.path, frame.width,
                                    frame.height, timings.empty() ? "none" : timings));
        }
        if (!args.verbosity.quiet) fmt::print("{}: ok\n", path);
    }
    return status;
}

int devices(const Verbosity& verbosity) {
    std::vector<vk::DeviceInfo> list;
    try {
        list = vk::listDevices();
    } catch (const BackendError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitMachine;
    }
    if (list.empty()) {
        fmt::print(stderr, "moire: error: no Vulkan device found (the driver lists none)\n");
        return kExitMachine;
    }
    // One line a device: index, type, API version, name, and which one --device defaults to.
    const int chosen = vk::defaultDevice(list);
    if (!verbosity.quiet)
        for (const vk::DeviceInfo& d : list)
            fmt::print("{:<3}{:<11}Vulkan {:<10}{}{}\n", d.index, d.type,
                       vk::versionString(d.apiVersion), d.name,
                       d.index == chosen ? "  (default)"
                       : d.usable        ? ""
                                         : fmt::format("  (unusable: {})", d.whyNot));
    if (verbosity.verbose)
        fmt::print(stderr,
                   "moire: --device defaults to the first usable discrete GPU, else the first "
                   "usable device: {}\n",
                   chosen);
    return kExitOk;
}

int compile(const CompileArgs& args) {
    static const char* kDumps[] = {"ast",  "ir",   "ir-ad",   "frame", "kernel",
                                   "llvm", "glsl", "glsl-es", "js",    "spirv"};
    if (std::find(std::begin(kDumps), std::end(kDumps), args.dump) == std::end(kDumps)) {
        fmt::print(stderr,
                   "moire: error: --dump must be one of ast, ir, ir-ad, frame, kernel, llvm, glsl, "
                   "glsl-es, js, spirv; not '{}'\n",
                   args.dump);
        return kExitUsage;
    }
    if (args.output.empty()) {
        fmt::print(stderr, "moire: error: -o needs a file name, or - for standard output\n");
        return kExitUsage;
    }
    Stages stages(args.verbosity);
    Source src;
    if (!readScene(args.scene, src)) return kExitIo;
    CompileOptions options;
    options.layerFields = args.layerFields;
    auto program = compileOrReport(src, options);
    if (!program) return kExitScene;
    stages.done(fmt::format("compiled {}", src.path));
    std::string text;
    if (args.dump == "ast")
        text = ast::printModule(program->userModule());
    else if (args.dump == "ir")
        text = ir::print(program->lowered);
    else if (args.dump == "ir-ad")
        text = ir::print(program->derived);
    else if (args.dump == "frame")
        text = ir::print(program->frame);
    else if (args.dump == "kernel")
        text = ir::print(program->kernel);
    else if (args.dump == "glsl")
        text = glsl::emitGlsl(program->kernel);
    else if (args.dump == "glsl-es")
        text = glsl::emitGlsl(program->kernel, glsl::Dialect::WebGl);
    else if (args.dump == "js")
        text = js::emitFrameJs(program->frame) + "\n";
    else if (args.dump == "spirv")
        text = glsl::disassembleSpirv(glsl::compileSpirv(program->kernel));
    else if (args.dump == "llvm")
        text = LlvmJitBackend().dumpLlvm(program->kernel);
    stages.done(fmt::format("made the {} dump", args.dump));
    try {
        if (args.output == kStdoutPath) {
            writeStandardOutput(text.data(), text.size());
        } else {
            prepareOutputDirectory(args.output);
            writeFileAtomically(args.output, text.data(), text.size());
        }
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    return kExitOk;
}

} // namespace moire::cli
