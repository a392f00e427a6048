// The `moire` command line. The options several commands share (the scene, -o, --size,
// --time, --backend and --device, --depth, --threads, -q and -v) are declared once, below,
// so that they read and behave the same in every command that takes them.
#include "compiler/diag/Diagnostics.h"
#include "compiler/sema/Views.h"
#include "lsp/Server.h"
#include "runtime/cli/Commands.h"
#include "runtime/cli/DefineOption.h"
#include "runtime/cli/ExportCommand.h"
#include "runtime/cli/FarmCommand.h"
#include "runtime/cli/PrintCommand.h"
#include "runtime/cli/ServeCommand.h"
#include "runtime/cli/Shared.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/JitCache.h"

#include <CLI/CLI.hpp>
#include <csignal>
#include <fmt/format.h>
#include <new>

namespace {

using namespace moire;

// The exit statuses, at the end of each command's --help (docs/cli.md has them all).
std::string exitStatuses(const char* scene) {
    return fmt::format("Exit status: 0 done; 1 {}; 2 a wrong command line; 3 a file that cannot "
                       "be\nread or written; 4 no usable device or not enough memory; 130 "
                       "interrupted.",
                       scene);
}

CLI::Option* addScene(CLI::App* cmd, std::string& scene, bool stdinToo = true,
                      bool defaultToo = true) {
    return cmd->add_option("scene", scene,
                           fmt::format("The .moire scene{}{}",
                                       stdinToo ? ", - for standard input" : "",
                                       defaultToo ? " (default: the embedded default scene)" : ""));
}

void addSize(CLI::App* cmd, std::string& size, const char* what = "Image") {
    cmd->add_option("--size", size,
                    fmt::format("{} size WIDTHxHEIGHT, replacing the scene's", what));
}

void addTime(CLI::App* cmd, double& time, const char* what = "Clock time t in seconds") {
    cmd->add_option("--time", time, fmt::format("{} (default 0)", what));
}

void addBackend(CLI::App* cmd, std::string& backend, int& device,
                const char* which = "jit (default), interp or vulkan") {
    cmd->add_option("--backend", backend, which);
    cmd->add_option("--device", device,
                    "Vulkan device index for --backend vulkan (see 'moire devices'; default: "
                    "the first discrete GPU, else the first device)")
        ->check(CLI::NonNegativeNumber);
}

void addDepth(CLI::App* cmd, std::string& depth, const char* what = "Bits per channel") {
    cmd->add_option("--depth", depth, fmt::format("{}: 8, 16, half or float", what));
}

void addThreads(CLI::App* cmd, int& threads) {
    cmd->add_option("--threads", threads, "Worker threads (default: all cores)");
}

void addDebounce(CLI::App* cmd, int& ms) {
    cmd->add_option("--debounce", ms,
                    "Milliseconds of quiet after a change before rebuilding (default 30)")
        ->check(CLI::Range(0, 10000));
}

void addVerbosity(CLI::App* cmd, cli::Verbosity& v, const char* quiet = "Print nothing but errors",
                  const char* verbose = "Also print each stage and how long it took") {
    CLI::Option* q = cmd->add_flag("-q,--quiet", v.quiet, quiet);
    cmd->add_flag("-v,--verbose", v.verbose, verbose)->excludes(q);
}

// --filter, on every command that draws a scene (docs/filtering.md).
void addFilter(CLI::App* cmd, std::string& filter) {
    cmd->add_option("--filter", filter, cli::filterHelp());
}

// The options of the commands that draw one image of a scene (render, watch).
template <class Args>
void addImageOptions(CLI::App* cmd, Args& args) {
    addSize(cmd, args.size);
    addTime(cmd, args.time);
    addBackend(cmd, args.backend, args.device);
    addDepth(cmd, args.depth);
    addThreads(cmd, args.threads);
}

} // namespace

int main(int argc, char** argv) {
    using namespace moire;
    // A file size limit (ulimit -f) must fail the write that crosses it with EFBIG, reported
    // as "cannot write 'x.png': File too large", not kill moire with nothing said; ffmpeg
    // inherits the setting.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"moire: a compiler and renderer for moire-pattern scenes (.moire files)", "moire"};
    app.set_version_flag("--version", "moire " MOIRE_VERSION);
    app.require_subcommand(0, 1);
    app.footer("Run 'moire COMMAND --help' for a command's options. Exit statuses: docs/cli.md.\n"
               "The JIT keeps compiled kernels in " +
               (JitCache::rootDirectory().empty() ? std::string("no folder (the cache is off)")
                                                  : JitCache::rootDirectory()) +
               " (MOIRE_CACHE_DIR moves it, MOIRE_CACHE_DIR=off turns it off); delete that "
               "folder to clear it.");

    cli::RenderArgs renderArgs;
    CLI::App* renderCmd = app.add_subcommand(
        "render", "Render a scene to an image file (--backend: jit, interp or vulkan)");
    addScene(renderCmd, renderArgs.scene);
    std::vector<std::string> rawDefines; // -D on whichever command runs (DefineOption.h)
    cli::addDefineOption(renderCmd, rawDefines);
    renderCmd->add_option("-o,--output", renderArgs.output,
                          "Image to write: .png (8/16-bit), .tif (16/8-bit), .exr (float/half), "
                          ".jpg; - for a PNG on standard output (default: <scene>.png)");
    addImageOptions(renderCmd, renderArgs);
    renderCmd->add_option("--region", renderArgs.region,
                          "Render only the window X0,Y0,X1,Y1 of the frame (pixels of the full "
                          "frame, X1 and Y1 excluded), its place recorded in the file for "
                          "'moire assemble'; .png, .tif or .exr");
    renderCmd->add_option("--dpi", renderArgs.dpi,
                          "Print resolution to record in the file, in dots per inch (above 0, "
                          "at most 1000000; default 0: none recorded)");
    renderCmd->add_option("--compression", renderArgs.compression,
                          fmt::format("PNG's zlib level, 0 (none, fastest) to 9 (smallest, "
                                      "slowest); default {}",
                                      kPrintCompression));
    renderCmd->add_option("--view", renderArgs.view,
                          "What to draw: " + sema::viewList() +
                              " (default: the scene's view, else pattern; docs/views.md)");
    renderCmd->add_flag("--overlay", renderArgs.overlay,
                        "Lay the fringe curves of the winning character over the view where a "
                        "fringe stands, as the scene's overlay = true does (docs/views.md)");
    addFilter(renderCmd, renderArgs.filter);
    renderCmd->add_option("--envelope-gain", renderArgs.envelopeGain,
                          "The envelope's contrast about its pivot, replacing the scene's "
                          "envelope_gain (default 3)");
    renderCmd->add_option("--envelope-taps", renderArgs.envelopeTaps,
                          "The envelope's taps per index period, a whole number from 1 to 1024, "
                          "replacing the scene's envelope_taps (default 24)");
    addVerbosity(renderCmd, renderArgs.verbosity);
    renderCmd->footer(
        "The image is written beside its name and renamed into place when complete; a missing\n"
        "directory is created. A write that fails (a full disk) is an error and leaves any\n"
        "earlier file as it was. Ctrl-C stops the render with status 130 and writes nothing.\n" +
        exitStatuses("the scene has errors"));

    cli::AssembleArgs assembleArgs;
    CLI::App* assembleCmd =
        app.add_subcommand("assemble", "Join region tiles (render --region) into the whole image");
    assembleCmd
        ->add_option("tiles", assembleArgs.tiles,
                     "The tiles: .png, .tif or .exr files written by render --region")
        ->required();
    assembleCmd
        ->add_option("-o,--output", assembleArgs.output, "Image to write: .png, .tif, .exr or .jpg")
        ->required();
    assembleCmd->add_option("--size", assembleArgs.size,
                            "The frame WIDTHxHEIGHT the tiles must make (default: the size they "
                            "record)");
    addDepth(assembleCmd, assembleArgs.depth, "Bits per channel (default: the tiles')");
    assembleCmd->add_option(
        "--compression", assembleArgs.compression,
        fmt::format("PNG's zlib level, 0 to 9; default {}, as render's", kPrintCompression));
    addThreads(assembleCmd, assembleArgs.threads);
    addVerbosity(assembleCmd, assembleArgs.verbosity);
    assembleCmd->footer(
        "Each tile's place in the frame is read from the file. The tiles must cover the frame\n"
        "exactly once, and agree in frame size, channels, depth and resolution. The whole is\n"
        "written band by band, as render writes it: the tiles of a frame assemble into the\n"
        "very file render makes of the whole with the same options.\n"
        "Exit status: 0 done; 2 a wrong command line, or tiles that do not make one frame;\n"
        "3 a tile that cannot be read or an image that cannot be written; 130 interrupted.");

    cli::ClipArgs clipArgs;
    CLI::App* clipCmd = app.add_subcommand(
        "clip", "Render an animation: numbered images or a video (.mp4, .webm, .gif)");
    addScene(clipCmd, clipArgs.scene);
    cli::addDefineOption(clipCmd, rawDefines);
    clipCmd->add_option("-o,--output", clipArgs.output,
                        "Frames as a numbered image name (frame_%04d.png; .png, .tif, .exr, .jpg) "
                        "or one video file (.mp4, .webm, .gif; needs ffmpeg)");
    clipCmd->add_option("--fps", clipArgs.fps, "Frames per second")->required();
    addSize(clipCmd, clipArgs.size, "Frame");
    clipCmd->add_option("--from", clipArgs.from, "Clock time of frame 0 in seconds (default 0)");
    CLI::Option* toOpt = clipCmd->add_option(
        "--to", clipArgs.to,
        "End time in seconds, not included (default: the timings' loop length)");
    CLI::Option* framesOpt =
        clipCmd->add_option("--frames", clipArgs.frames,
                            "N frames, or frames A..B (inclusive) numbered as in the whole clip");
    toOpt->excludes(framesOpt);
    addBackend(clipCmd, clipArgs.backend, clipArgs.device);
    addDepth(clipCmd, clipArgs.depth, "Bits per channel of image frames");
    addThreads(clipCmd, clipArgs.threads);
    addFilter(clipCmd, clipArgs.filter);
    clipCmd->add_flag("--plan", clipArgs.plan,
                      "Print the frames the clip would have and why; render nothing");
    addVerbosity(clipCmd, clipArgs.verbosity);
    clipCmd->footer(
        "Frame n is drawn at exactly t = FROM + n / FPS, so any range can be rendered apart\n"
        "(--frames A..B keeps the whole clip's numbering) and the same range twice gives the\n"
        "same files. Without --to or --frames the clip is one loop: the least common multiple\n"
        "of the cycles (delay + period, twice the period for pingpong) of the timings it uses,\n"
        "at most 10 minutes. Timings that run once extend it until they are at rest, and the\n"
        "clip then does not join seamlessly. A scene that does not move gives one frame.\n"
        "A missing output directory is created. Ctrl-C stops after the frame in hand: the\n"
        "frames written are complete, a video is not written; the exit status is 130.\n" +
        exitStatuses("the scene has errors, or a frame cannot be rendered"));

    cli::WatchArgs watchArgs;
    CLI::App* watchCmd = app.add_subcommand(
        "watch", "Re-render an image each time the scene is saved (headless live coding)");
    addScene(watchCmd, watchArgs.scene, false, false)->required();
    cli::addDefineOption(watchCmd, rawDefines);
    watchCmd->add_option("-o,--output", watchArgs.output,
                         "Image to keep up to date (default: <scene>.png); replaced atomically");
    addImageOptions(watchCmd, watchArgs);
    addDebounce(watchCmd, watchArgs.debounceMs);
    addFilter(watchCmd, watchArgs.filter);
    watchCmd->add_flag("--once", watchArgs.once, "Render the scene as it is now and exit");
    addVerbosity(watchCmd, watchArgs.verbosity, "Print nothing but diagnostics",
                 "Also print how long each save took to read and compile");
    watchCmd->footer(
        "Each good save re-renders the image (written beside it, then renamed over it, so an\n"
        "image viewer never reads half a file); a save with errors prints them and leaves the\n"
        "last good image. Saves that change only numbers reuse the compiled kernel. Ctrl-C\n"
        "stops (exit 0). With --once: " +
        exitStatuses("the scene has errors"));

    cli::ViewArgs viewArgs;
    CLI::App* viewCmd =
        app.add_subcommand("view", "Open a window on a scene that reloads as the file is saved");
    addScene(viewCmd, viewArgs.scene, false);
    cli::addDefineOption(viewCmd, rawDefines);
    addBackend(viewCmd, viewArgs.backend, viewArgs.device,
               "vulkan or jit (default: vulkan on a GPU, else jit), or interp");
    addSize(viewCmd, viewArgs.size, "Window (in screen units)");
    addTime(viewCmd, viewArgs.time, "Clock time t to start at");
    viewCmd->add_flag("--paused", viewArgs.paused, "Start with the clock stopped");
    addThreads(viewCmd, viewArgs.threads);
    addDebounce(viewCmd, viewArgs.debounceMs);
    addFilter(viewCmd, viewArgs.filter);
    viewCmd->add_flag("--trace", viewArgs.trace, "Print a line per frame shown")->group("");
    addVerbosity(viewCmd, viewArgs.verbosity, "Print nothing but errors",
                 "Also say which backend draws and why");
    viewCmd->footer(
        "Mouse: the wheel zooms about the cursor; a drag pans, or moves the selected layer;\n"
        "alt-drag (or ctrl-drag) turns the selected layer about the world origin; a click on a\n"
        "stroke selects its layer. Keys: 1-9 select a layer, 0 or Esc none; space pauses and\n"
        "plays; . and , step a frame; the arrows move the clock 1 s (shift: 0.1 s); r resets\n"
        "the view; s saves a still beside the scene; p prints the placement; w writes it\n"
        "into the scene file; Tab shows the parameter panel (a slider per param, the clock)\n"
        "and W writes its values into the scene file; e shows the envelope (again: the\n"
        "pattern); h hides the status line; q quits. Saves reload; a save with\n"
        "errors keeps the last good picture under the diagnostics.");

    cli::ServeArgs serveArgs;
    CLI::App* serveCmd = app.add_subcommand(
        "serve", "Show a scene on a page in the browser that reloads as the file is saved");
    addScene(serveCmd, serveArgs.scene, false, false)->required();
    cli::addDefineOption(serveCmd, rawDefines);
    CLI::Option* hostOpt = serveCmd->add_option(
        "--host", serveArgs.host, "Address to listen on (default 127.0.0.1: this machine only)");
    serveCmd->add_option("--port", serveArgs.port, "Port to listen on (default 0: any free port)");
    addBackend(serveCmd, serveArgs.backend, serveArgs.device);
    addSize(serveCmd, serveArgs.size, "Frame");
    addTime(serveCmd, serveArgs.time, "Clock time t to start at");
    serveCmd->add_flag("--paused", serveArgs.paused, "Start with the clock stopped");
    addThreads(serveCmd, serveArgs.threads);
    addDebounce(serveCmd, serveArgs.debounceMs);
    addFilter(serveCmd, serveArgs.filter);
    addVerbosity(serveCmd, serveArgs.verbosity);
    serveCmd->footer("The first line on standard output is the page's address, with a token made "
                     "for this run:\nrequests without it are refused. Ctrl-C stops (exit 0). "
                     "docs/serve.md describes the page.");

    cli::CheckArgs checkArgs;
    CLI::App* checkCmd = app.add_subcommand("check", "Check scenes for errors without rendering");
    checkCmd->add_option("scenes", checkArgs.scenes, "The .moire scenes, - for standard input")
        ->required();
    checkCmd
        ->add_option("--format", checkArgs.format,
                     "text (default), or json: the diagnostics as JSON on standard output")
        ->check(CLI::IsMember({"text", "json"}));
    addVerbosity(checkCmd, checkArgs.verbosity, "Print nothing but errors",
                 "Also print each scene's size and timings, and how long it took to check");
    checkCmd->footer("Exit status: 0 every scene is good; otherwise the first failing scene's: 1 "
                     "it has\nerrors, 3 it cannot be read; 2 a wrong command line.");

    cli::Verbosity devicesVerbosity;
    CLI::App* devicesCmd = app.add_subcommand("devices", "List the Vulkan devices");
    addVerbosity(devicesCmd, devicesVerbosity,
                 "Print nothing: the exit status says whether there is a device",
                 "Also say why --device picks its default");
    devicesCmd->footer("Exit status: 0 a usable device; 4 none (no driver, or no device).");

    cli::CompileArgs compileArgs;
    CLI::App* compileCmd = app.add_subcommand(
        "compile", "Show a compiler stage: the AST, the IR, LLVM IR, GLSL or SPIR-V (--dump)");
    addScene(compileCmd, compileArgs.scene);
    compileCmd->add_option(
        "--dump", compileArgs.dump,
        "ast, ir, ir-ad, frame, kernel, llvm, glsl, glsl-es, js or spirv (default ir)");
    compileCmd->add_flag("--fields", compileArgs.layerFields,
                         "Also output each layer's index and distance");
    compileCmd->add_option("-o,--output", compileArgs.output,
                           "The file to write the stage to (default -: standard output)");
    addVerbosity(compileCmd, compileArgs.verbosity, "Print nothing but errors",
                 "Also print how long the scene took to compile");
    compileCmd->footer(exitStatuses("the scene has errors"));

    cli::FmtArgs fmtArgs;
    CLI::App* fmtCmd =
        app.add_subcommand("fmt", "Rewrite scenes in the canonical layout (docs/formatting.md)");
    fmtCmd->add_option("files", fmtArgs.files, "The .moire files, - for standard input")
        ->required();
    fmtCmd->add_flag("--check", fmtArgs.check,
                     "Write nothing; name the files that formatting would change");
    addVerbosity(fmtCmd, fmtArgs.verbosity, "Print nothing but errors (--check: not the names)",
                 "Also say of each file whether it was rewritten");
    fmtCmd->footer("Exit status: 0 every file is formatted (or was rewritten); otherwise the first "
                   "failing\nfile's: 1 it has errors, or --check would change it; 3 it cannot be "
                   "read or written;\n2 a wrong command line.");
    cli::NamesArgs namesArgs;
    CLI::App* namesCmd = app.add_subcommand(
        "names", "List the language's keywords, properties, families, functions and other names");
    namesCmd->add_flag("--json", namesArgs.json, "As JSON, grouped by kind (for editors)");
    addVerbosity(namesCmd, namesArgs.verbosity, "Print the names and nothing else",
                 "Also say how many names of each kind there are");
    namesCmd->footer("Exit status: 0 done; 2 a wrong command line.");
    cli::ExportArgs exportArgs;
    CLI::App* exportCmd = cli::addExportCommand(app, exportArgs, rawDefines);
    cli::FarmArgs farmArgs;
    CLI::App* farmCmd = cli::addFarmCommand(app, farmArgs, rawDefines);
    cli::PrintArgs printArgs;
    CLI::App* printCmd = cli::addPrintCommand(app, printArgs, rawDefines);
    CLI::App* lspCmd = app.add_subcommand(
        "lsp", "Serve the Language Server Protocol on standard input and output (docs/editors.md)");
    lspCmd->footer("Started by an editor, not by hand. Exit status: 0 after shutdown, else 1.");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : cli::kExitUsage;
    }
    if (!rawDefines.empty()) {
        Defines defines;
        std::string diagnostics;
        if (!cli::collectDefines(argc, argv, defines, diagnostics)) {
            fmt::print(stderr, "{}", diagnostics);
            return cli::kExitUsage;
        }
        renderArgs.defines = clipArgs.defines = watchArgs.defines = viewArgs.defines = defines;
        exportArgs.defines = printArgs.defines = defines;
        farmArgs.defines = defines;
        serveArgs.defines = defines;
    }
    try {
        if (*renderCmd) return cli::render(renderArgs);
        if (*assembleCmd) return cli::assemble(assembleArgs);
        if (*clipCmd) {
            clipArgs.hasTo = toOpt->count() > 0;
            return cli::clip(clipArgs);
        }
        if (*watchCmd) return cli::watch(watchArgs);
        if (*viewCmd) return cli::view(viewArgs);
        if (*serveCmd) {
            serveArgs.hostGiven = hostOpt->count() > 0;
            return cli::serve(serveArgs);
        }
        if (*checkCmd) return cli::check(checkArgs);
        if (*compileCmd) return cli::compile(compileArgs);
        if (*devicesCmd) return cli::devices(devicesVerbosity);
        if (*fmtCmd) return cli::formatFiles(fmtArgs);
        if (*namesCmd) return cli::names(namesArgs);
        if (*exportCmd) return cli::exportPiece(exportArgs);
        if (*farmCmd) return cli::farm(farmArgs, rawDefines);
        if (*printCmd) return cli::print(printArgs);
        if (*lspCmd) return lsp::runServer(0, 1);
        fmt::print("{}", app.help());
        return 0;
    } catch (const std::bad_alloc&) {
        // The estimate before a render (MemoryBudget.h) catches the sizes known to be too
        // large; this is whatever else runs out, said as the user's problem, not ours.
        fmt::print(stderr, "moire: error: out of memory\n");
        return cli::kExitMachine;
    } catch (const InternalError& e) {
        fmt::print(stderr, "moire: {}\nPlease report this with the scene that caused it.\n",
                   e.what());
        return cli::kExitInternal;
    } catch (const std::exception& e) {
        fmt::print(stderr, "moire: internal error: {}\n", e.what());
        return cli::kExitInternal;
    }
}
