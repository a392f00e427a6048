#include "runtime/cli/PrintCommand.h"

#include "runtime/cli/DefineOption.h"
#include "runtime/cli/Shared.h"
#include "runtime/cli/StopSignals.h"
#include "runtime/FloorNote.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageStream.h"
#include "runtime/output/OutputFile.h"
#include "runtime/print/Marks.h"
#include "runtime/print/SheetLayout.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <unistd.h>

namespace moire::cli {

namespace fs = std::filesystem;

namespace {

constexpr double kMostBleedMm = 1000.0;
constexpr double kMostScale = 1e9; // world units per millimetre
// Rows a CPU worker renders at a time: each step is finished (margin and marks) and handed
// to the stream while it is in the cache (the stream chooses the band).
constexpr int kStepRows = 8;

// One sheet to write: the program that draws it and the file it goes to.
struct Sheet {
    std::unique_ptr<SceneProgram> program;
    std::string path;
    bool transparent = false; // a separation: the margin is clear, not white
};

bool checkPrintArgs(const PrintArgs& a, print::PaperSize& paper) {
    std::string why;
    if (a.paper.empty()) {
        fmt::print(stderr, "moire: error: --paper is needed: {}, or a size such as 610x406mm\n",
                   print::paperNames());
        return false;
    }
    if (!print::parsePaper(a.paper, paper, why)) {
        fmt::print(stderr, "moire: error: --paper: {}\n", why);
        return false;
    }
    if (!(std::isfinite(a.dpi) && a.dpi > 0 && a.dpi <= kMaxDpi)) {
        fmt::print(stderr,
                   "moire: error: --dpi must be a number of dots per inch above 0 and at most "
                   "{:.0f}, not {}\n",
                   kMaxDpi, a.dpi);
        return false;
    }
    if (!(std::isfinite(a.bleed) && a.bleed >= 0 && a.bleed <= kMostBleedMm)) {
        fmt::print(stderr,
                   "moire: error: --bleed must be a width in millimetres from 0 to {:.0f}, not "
                   "{}\n",
                   kMostBleedMm, a.bleed);
        return false;
    }
    if (a.scale && !(std::isfinite(*a.scale) && *a.scale > 0 && *a.scale <= kMostScale)) {
        fmt::print(stderr,
                   "moire: error: --scale must be a number of world units per millimetre above 0 "
                   "and at most {:g}, not {}\n",
                   kMostScale, *a.scale);
        return false;
    }
    return checkTime(a.time, "-t/--time");
}

// The frame at `request`, or its diagnostics printed and false.
bool frameOf(const SceneProgram& program, const FrameRequest& request, FrameValues& frame) {
    std::string diags;
    if (evaluateFrame(program, request, frame, diags)) return true;
    fmt::print(stderr, "{}", diags);
    return false;
}

// Renders one sheet into `stream`, band by band on any backend (runKernelInBands): the
// kernel's rows, the margin and the marks laid on them (Marks.h), then handed over, so no
// more than a few bands are ever held. False when stopped by a signal.
bool renderSheet(const CompiledKernel& kernel, const KernelFrame& kf, const ExecOptions& exec,
                 const print::SheetLayout& layout, const std::vector<print::MarkShape>& marks,
                 const float margin[4], ImageStream& stream) {
    const int channels = kernel.numOutputs();
    const bool finish = layout.art.x0 > 0; // a margin to clear and mark
    const int bandRows = stream.bandRows();
    return runKernelInBands(
        kernel, kf, exec, bandRows,
        [&](int band, int first, int count, const float* rows, size_t stride) {
            const int y = band * bandRows + first;
            if (!finish) {
                stream.addRows(y, count, rows, stride, channels);
                return;
            }
            // The worker's rows are read-only to the sink: finished in a copy of the step.
            thread_local std::vector<float> copy;
            copy.assign(rows, rows + stride * static_cast<size_t>(count));
            print::finishRows(layout, marks, margin, y, count, copy.data(), stride, channels);
            stream.addRows(y, count, copy.data(), stride, channels);
        },
        nullptr, kStepRows);
}

} // namespace

std::string separationPath(const std::string& output, const std::string& layer) {
    const fs::path p(output);
    fs::path name = p.stem();
    name += "-" + layer;
    name += p.extension();
    return (p.parent_path() / name).string();
}

CLI::App* addPrintCommand(CLI::App& app, PrintArgs& args, std::vector<std::string>& rawDefines) {
    CLI::App* cmd = app.add_subcommand(
        "print", "Render a scene at physical size on a print sheet, with bleed and marks");
    cmd->add_option("scene", args.scene,
                    "The .moire scene, - for standard input (default: the embedded default "
                    "scene)");
    addDefineOption(cmd, rawDefines);
    cmd->add_option("-o,--output", args.output,
                    "The sheet to write: .tif (16/8-bit), .png (8/16-bit), .exr (float/half), "
                    ".jpg (default: <scene>.tif)");
    cmd->add_option("--paper", args.paper,
                    fmt::format("The paper (the trim): {}, or WIDTHxHEIGHT in mm, cm or in",
                                print::paperNames()))
        ->required();
    CLI::Option* land =
        cmd->add_flag("--landscape", args.landscape, "Lay the paper's long side across");
    cmd->add_flag("--portrait", args.portrait, "Stand the paper's long side upright")
        ->excludes(land);
    cmd->add_option("--dpi", args.dpi, "Dots per inch, above 0 (recorded in the file)")->required();
    cmd->add_option("--bleed", args.bleed,
                    "Millimetres of artwork past the trim on every side (default 0)");
    cmd->add_flag("--marks", args.marks,
                  "Add a 12 mm margin with crop marks and registration targets");
    cmd->add_option("--scale", args.scale,
                    "World units per millimetre of paper (default: the scene's frame fitted to "
                    "the trim)");
    cmd->add_flag("--separate", args.separate,
                  "One sheet a layer, OUTPUT-<layer>, the layer's ink as alpha on a transparent "
                  "ground");
    cmd->add_option("-t,--time", args.time, "Clock time t in seconds (default 0)");
    cmd->add_option("--backend", args.backend, "jit (default), interp or vulkan");
    cmd->add_option("--device", args.device,
                    "Vulkan device index for --backend vulkan (see 'moire devices')")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--depth", args.depth, "Bits per channel: 8, 16, half or float");
    cmd->add_option("--threads", args.threads, "Worker threads (default: all cores)");
    cmd->add_option("--filter", args.filter, filterHelp());
    CLI::Option* q = cmd->add_flag("-q,--quiet", args.verbosity.quiet, "Print nothing but errors");
    cmd->add_flag("-v,--verbose", args.verbosity.verbose,
                  "Also print each stage and how long it took")
        ->excludes(q);
    cmd->footer(
        "A sheet is pixels = round(millimetres / 25.4 * dpi) a side: the trim (the paper), the\n"
        "bleed around it, and with --marks a margin for the marks. Without --portrait or\n"
        "--landscape the paper's long side lies along the scene frame's. The sheet is written\n"
        "band by band, in bounded memory, and renamed into place when complete (docs/print.md).\n"
        "Exit status: 0 done; 1 the scene has errors; 2 a wrong command line; 3 a file that\n"
        "cannot be written; 4 no usable device; 130 interrupted.");
    return cmd;
}

int print(const PrintArgs& args) {
    print::PaperSize paper;
    if (!checkPrintArgs(args, paper)) return kExitUsage;
    CompileOptions filterOnly; // --filter, checked before anything is opened or written
    if (!checkFilterOption(args.filter, filterOnly)) return kExitUsage;
    ImageOptions image;
    const std::string output =
        args.output.empty() ? (args.scene.empty()         ? std::string("default")
                               : args.scene == kStdinPath ? std::string("stdin")
                                                          : fs::path(args.scene).stem().string()) +
                                  ".tif"
                            : args.output;
    if (output == kStdoutPath) {
        fmt::print(stderr, "moire: error: print writes files; -o - (standard output) is for "
                           "render\n");
        return kExitUsage;
    }
    if (!checkImageOptions({args.scene, output, "", args.depth, args.backend, args.device}, image))
        return kExitUsage;
    if (args.separate && image.format == "jpeg") {
        fmt::print(stderr, "moire: error: --separate writes each layer's ink as alpha, which JPEG "
                           "cannot hold; use .tif, .png or .exr\n");
        return kExitUsage;
    }
    std::unique_ptr<Backend> backend = openBackend(args.backend, args.device);
    if (!backend) return kExitMachine;

    Stages stages(args.verbosity);
    Source src;
    if (!readScene(args.scene, src)) return kExitIo;
    CompileOptions options;
    options.defines = args.defines;
    options.pixelSize = true;
    options.filter = filterOnly.filter;
    std::vector<Sheet> sheets;
    auto whole = compileOrReport(src, options);
    if (!whole) return kExitScene;
    FrameValues scene;
    FrameRequest request;
    request.time = args.time;
    if (!frameOf(*whole, request, scene)) return kExitScene;
    if (args.separate) {
        for (size_t i = 0; i < whole->checked.layers.size(); ++i) {
            options.separateLayer = static_cast<int>(i);
            auto one = compileOrReport(src, options);
            if (!one) return kExitScene;
            // A layer without a name is called by its place, from 1 (layer2).
            const std::string& name = whole->checked.layers[i].decl->name;
            sheets.push_back(
                {std::move(one),
                 separationPath(output, name.empty() ? fmt::format("layer{}", i + 1) : name),
                 true});
        }
        if (sheets.empty()) {
            fmt::print(stderr, "moire: error: --separate: the scene has no layers\n");
            return kExitScene;
        }
    } else {
        sheets.push_back({std::move(whole), output, false});
    }
    stages.done(fmt::format("compiled {}", src.path));

    print::SheetRequest sr;
    sr.paper = paper;
    sr.orientation = args.landscape  ? print::Orientation::Landscape
                     : args.portrait ? print::Orientation::Portrait
                                     : print::Orientation::Auto;
    sr.dpi = args.dpi;
    sr.bleedMm = args.bleed;
    sr.marks = args.marks;
    sr.scale = args.scale.value_or(0.0);
    sr.sceneWidth = scene.sceneWidth;
    sr.sceneHeight = scene.sceneHeight;
    sr.zoom = scene.zoom;
    const print::SheetLayout layout = print::layoutSheet(sr);
    if (layout.trim.width() < 1 || layout.trim.height() < 1) {
        fmt::print(stderr,
                   "moire: error: a {:g} x {:g} mm paper at {:g} dpi is less than a pixel a side; "
                   "raise --dpi\n",
                   layout.paperWidthMm, layout.paperHeightMm, args.dpi);
        return kExitUsage;
    }
    if (layout.width > kMaxImageSide || layout.height > kMaxImageSide) {
        fmt::print(stderr,
                   "moire: error: a {:g} x {:g} mm sheet at {:g} dpi is {}x{} pixels, more than "
                   "{} a side; lower --dpi\n",
                   layout.paperWidthMm, layout.paperHeightMm, args.dpi, layout.width, layout.height,
                   kMaxImageSide);
        return kExitUsage;
    }
    const std::vector<print::MarkShape> marks = print::sheetMarks(layout, args.dpi);
    // Streamed as render streams: a few bands in memory, never the sheet (MemoryBudget.h).
    if (!checkMemory({.width = static_cast<int>(layout.width),
                      .height = static_cast<int>(layout.height),
                      .sink = FrameSink::Streamed,
                      .format = image.format,
                      .gpu = args.backend == "vulkan",
                      .threads = args.threads,
                      .depth = image.depth,
                      .streamed = true}))
        return kExitMachine;

    StopSignals signals;
    const bool tty = isatty(fileno(stderr));
    const auto t0 = std::chrono::steady_clock::now();
    WriteOptions wo;
    wo.depth = image.depth;
    wo.dpi = args.dpi;
    wo.threads = args.threads;
    for (Sheet& sheet : sheets) {
        request.width = static_cast<int>(layout.width);
        request.height = static_cast<int>(layout.height);
        request.pixelSize = layout.pixelSize;
        FrameValues frame;
        if (!frameOf(*sheet.program, request, frame)) return kExitScene;
        if (!args.verbosity.quiet && &sheet == &sheets.front())
            fmt::print(stderr, "{}",
                       strokeFloorNotes(*sheet.program, options.filter, frame.pixelSize));
        ExecOptions exec;
        exec.threads = args.threads;
        exec.cancelled = [] { return StopSignals::received() != 0; };
        bool shown = false;
        if (!args.verbosity.quiet)
            exec.progress = [&](double fraction) {
                if (secondsSince(t0) < 1.0 || !tty) return;
                fmt::print(stderr, "\rmoire: printing {} {}x{} {:3.0f}%", sheet.path, frame.width,
                           frame.height, fraction * 100.0);
                std::fflush(stderr);
                shown = true;
            };
        // The progress line ended, then one line of error.
        auto failed = [&](const std::exception& e, int status) {
            if (shown) fmt::print(stderr, "\n");
            fmt::print(stderr, "moire: error: {}\n", e.what());
            return status;
        };
        const float white[4] = {1, 1, 1, 1}, clear[4] = {0, 0, 0, 0};
        try {
            std::unique_ptr<CompiledKernel> kernel = backend->compile(sheet.program->kernel);
            const KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
            prepareOutputDirectory(sheet.path);
            removeStaleTemporaries(sheet.path);
            std::unique_ptr<ImageStream> stream = openImageStream(
                sheet.path, imageFormatOf(sheet.path), frame.width, frame.height, wo);
            const bool done = renderSheet(*kernel, kf, exec, layout, marks,
                                          sheet.transparent ? clear : white, *stream);
            if (shown) fmt::print(stderr, "\n");
            if (!done || StopSignals::received()) {
                fmt::print(stderr, "moire: interrupted: {} was not written\n", sheet.path);
                return 128 + StopSignals::received();
            }
            stream->finish();
        } catch (const BackendError& e) { // the device lost, or out of memory
            return failed(e, kExitMachine);
        } catch (const IoError& e) {
            return failed(e, kExitIo);
        }
        stages.done(fmt::format("wrote {}", sheet.path));
        if (!args.verbosity.quiet)
            fmt::print(stderr, "moire: wrote {} ({}x{} px, {:g} x {:g} mm{} at {:g} dpi, {})\n",
                       sheet.path, frame.width, frame.height, layout.paperWidthMm,
                       layout.paperHeightMm, layout.landscape ? " landscape" : "", args.dpi,
                       describe(*backend));
    }
    return kExitOk;
}

} // namespace moire::cli
