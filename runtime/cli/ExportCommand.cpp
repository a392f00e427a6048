#include "runtime/cli/ExportCommand.h"

#include "compiler/lower/ClipClock.h"
#include "runtime/cli/DefineOption.h"
#include "runtime/cli/Shared.h"
#include "runtime/export/PiecePage.h"
#include "runtime/FrameEval.h"
#include "runtime/output/OutputFile.h"

#include <filesystem>
#include <fmt/format.h>

namespace moire::cli {

namespace fs = std::filesystem;

namespace {
// The page's clock advances at the display's rate; the loop is found at a rate fine enough
// that its rounding to whole frames is invisible.
constexpr double kLoopFps = 1000.0;
} // namespace

CLI::App* addExportCommand(CLI::App& app, ExportArgs& args, std::vector<std::string>& rawDefines) {
    CLI::App* cmd = app.add_subcommand(
        "export", "Write a scene as one HTML page that draws it live in a browser (WebGL2)");
    cmd->add_option("scene", args.scene,
                    "The .moire scene, - for standard input (default: the embedded default "
                    "scene)");
    cmd->add_option("-o,--output", args.output,
                    "The page to write (default: <scene>.html); - for standard output");
    cmd->add_option("--size", args.size, "Canvas size WIDTHxHEIGHT, replacing the scene's");
    cmd->add_option("--time", args.time, "Clock time t in seconds when the page opens (default 0)");
    cmd->add_flag("--paused", args.paused, "Open with the clock stopped");
    cmd->add_option("--filter", args.filter, filterHelp());
    addDefineOption(cmd, rawDefines);
    CLI::Option* q = cmd->add_flag("-q,--quiet", args.verbosity.quiet, "Print nothing but errors");
    cmd->add_flag("-v,--verbose", args.verbosity.verbose,
                  "Also print each stage and how long it took")
        ->excludes(q);
    cmd->footer("The page holds the scene compiled twice: the pixel kernel as a WebGL2 fragment\n"
                "shader and the frame program as JavaScript, so the clock and the sliders (one\n"
                "per param; -D sets where they start) run in the browser without moire. The page\n"
                "is written beside its name and renamed into place when complete.\n"
                "Exit status: 0 done; 1 the scene has errors; 2 a wrong command line; 3 a file\n"
                "that cannot be read or written.");
    return cmd;
}

int exportPiece(const ExportArgs& args) {
    Stages stages(args.verbosity);
    int w = 0, h = 0;
    if (!args.size.empty() && !parseSize(args.size, w, h, kMaxFrameSide)) {
        fmt::print(stderr,
                   "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to {}), not '{}'\n",
                   kMaxFrameSide, args.size);
        return kExitUsage;
    }
    if (!checkTime(args.time, "--time")) return kExitUsage;
    CompileOptions compileOptions;
    if (!checkFilterOption(args.filter, compileOptions)) return kExitUsage;
    Source src;
    if (!readScene(args.scene, src)) return kExitIo;
    compileOptions.defines = args.defines;
    std::unique_ptr<SceneProgram> program = compileOrReport(src, compileOptions);
    if (!program) return kExitScene;
    stages.done("compiled " + src.path);

    // The frame as the page opens: its size, and whether it can be drawn at all.
    FrameValues frame;
    std::string diags;
    if (!evaluateFrame(*program, FrameRequest{args.time, w, h, nullptr, kMaxFrameSide}, frame,
                       diags)) {
        fmt::print(stderr, "{}", diags);
        return kExitScene;
    }
    const clip::Motion motion{frame.timings, clip::readsClock(*program),
                              clip::movesWithClock(*program)};
    const clip::Length length = clip::defaultLength(motion, 0.0, kLoopFps);

    PieceOptions options;
    options.title = args.scene.empty()         ? std::string("default")
                    : args.scene == kStdinPath ? std::string("stdin")
                                               : fs::path(args.scene).stem().string();
    options.width = frame.width;
    options.height = frame.height;
    options.time = args.time;
    options.playing = !args.paused;
    options.moves = motion.moves;
    // A clock read directly (no timing bounds it) runs on; otherwise it wraps at the loop.
    if (length.error.empty() && !length.still)
        options.loop = static_cast<double>(length.frames) / kLoopFps;
    const std::string page = piecePage(*program, options);
    stages.done("translated the kernel to GLSL ES and the frame program to JavaScript");

    const std::string output = args.output.empty() ? options.title + ".html" : args.output;
    try {
        if (output == kStdoutPath) {
            writeStandardOutput(page.data(), page.size());
        } else {
            prepareOutputDirectory(output);
            removeStaleTemporaries(output);
            writeFileAtomically(output, page.data(), page.size());
        }
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    stages.done("wrote " + output);
    if (!args.verbosity.quiet && output != kStdoutPath)
        fmt::print(stderr, "moire: wrote {} ({}x{}, {} KiB)\n", output, frame.width, frame.height,
                   (page.size() + 1023) / 1024);
    return kExitOk;
}

} // namespace moire::cli
