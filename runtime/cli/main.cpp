// The `moire` command line.
#include "compiler/diag/Diagnostics.h"
#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <csignal>
#include <fmt/format.h>
#include <new>

int main(int argc, char** argv) {
    using namespace moire;
    // A file size limit (ulimit -f) must fail the write that crosses it with EFBIG, reported
    // as "cannot write 'x.png': File too large", not kill moire with nothing said; ffmpeg
    // inherits the setting.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"moire: a compiler and renderer for moire-pattern scenes (.moire files)", "moire"};
    app.set_version_flag("--version", "moire " MOIRE_VERSION);
    app.require_subcommand(0, 1);
    app.footer(
        "Run 'moire COMMAND --help' for a command's options. Without a scene, render uses the\n"
        "embedded default scene.");

    cli::RenderArgs renderArgs;
    CLI::App* renderCmd = app.add_subcommand("render", "Render a scene to an image file");
    renderCmd->add_option("scene", renderArgs.scene,
                          "The .moire scene, - for standard input (default: the embedded "
                          "default scene)");
    renderCmd->add_option(
        "-o,--output", renderArgs.output,
        "Image to write: .png (8/16-bit), .tif (16/8-bit), .exr (float/half), .jpg");
    renderCmd->add_option("--size", renderArgs.size,
                          "Image size WIDTHxHEIGHT, replacing the scene's");
    renderCmd->add_option("--time", renderArgs.time, "Clock time t in seconds (default 0)");
    renderCmd->add_option("--backend", renderArgs.backend, "jit (default), interp or vulkan");
    renderCmd
        ->add_option("--device", renderArgs.device,
                     "Vulkan device index for --backend vulkan (see 'moire devices'; default: "
                     "the first discrete GPU, else the first device)")
        ->check(CLI::NonNegativeNumber);
    renderCmd->add_option("--depth", renderArgs.depth, "Bits per channel: 8, 16, half or float");
    renderCmd->add_option("--dpi", renderArgs.dpi,
                          "Print resolution to record in the file, in dots per inch (above 0, "
                          "at most 1000000; default 0: none recorded)");
    renderCmd->add_option("--threads", renderArgs.threads, "Worker threads (default: all cores)");
    renderCmd->add_flag("-q,--quiet", renderArgs.quiet, "Print nothing but errors");
    renderCmd->footer(
        "The image is written beside its name and renamed into place when complete; a missing\n"
        "directory is created. A write that fails (a full disk) is an error and leaves any\n"
        "earlier file as it was. Ctrl-C stops the render with status 130 and writes nothing.");

    cli::ClipArgs clipArgs;
    CLI::App* clipCmd = app.add_subcommand(
        "clip", "Render an animation: numbered images or a video (.mp4, .webm, .gif)");
    clipCmd->add_option("scene", clipArgs.scene,
                        "The .moire scene, - for standard input (default: the embedded default "
                        "scene)");
    clipCmd->add_option("-o,--output", clipArgs.output,
                        "Frames as a numbered image name (frame_%04d.png; .png, .tif, .exr, .jpg) "
                        "or one video file (.mp4, .webm, .gif; needs ffmpeg)");
    clipCmd->add_option("--fps", clipArgs.fps, "Frames per second")->required();
    clipCmd->add_option("--size", clipArgs.size, "Frame size WIDTHxHEIGHT, replacing the scene's");
    clipCmd->add_option("--from", clipArgs.from, "Clock time of frame 0 in seconds (default 0)");
    CLI::Option* toOpt = clipCmd->add_option(
        "--to", clipArgs.to,
        "End time in seconds, not included (default: the timings' loop length)");
    CLI::Option* framesOpt =
        clipCmd->add_option("--frames", clipArgs.frames,
                            "N frames, or frames A..B (inclusive) numbered as in the whole clip");
    toOpt->excludes(framesOpt);
    clipCmd->add_option("--backend", clipArgs.backend, "jit (default), interp or vulkan");
    clipCmd
        ->add_option("--device", clipArgs.device,
                     "Vulkan device index for --backend vulkan (see 'moire devices')")
        ->check(CLI::NonNegativeNumber);
    clipCmd->add_option("--depth", clipArgs.depth,
                        "Bits per channel of image frames: 8, 16, half or float");
    clipCmd->add_option("--threads", clipArgs.threads, "Worker threads (default: all cores)");
    clipCmd->add_flag("--plan", clipArgs.plan,
                      "Print the frames the clip would have and why; render nothing");
    clipCmd->add_flag("-q,--quiet", clipArgs.quiet, "Print nothing but errors");
    clipCmd->footer(
        "Frame n is drawn at exactly t = FROM + n / FPS, so any range can be rendered apart\n"
        "(--frames A..B keeps the whole clip's numbering) and the same range twice gives the\n"
        "same files. Without --to or --frames the clip is one loop: the least common multiple\n"
        "of the cycles (delay + period, twice the period for pingpong) of the timings it uses,\n"
        "at most 10 minutes. Timings that run once extend it until they are at rest, and the\n"
        "clip then does not join seamlessly. A scene that does not move gives one frame.\n"
        "A missing output directory is created. Ctrl-C stops after the frame in hand: the\n"
        "frames written are complete, a video is not written; the exit status is 130.");

    cli::WatchArgs watchArgs;
    CLI::App* watchCmd = app.add_subcommand(
        "watch", "Re-render an image each time the scene is saved (headless live coding)");
    watchCmd->add_option("scene", watchArgs.scene, "The .moire scene")->required();
    watchCmd->add_option("-o,--output", watchArgs.output,
                         "Image to keep up to date (default: <scene>.png); replaced atomically");
    watchCmd->add_option("--size", watchArgs.size,
                         "Image size WIDTHxHEIGHT, replacing the scene's");
    watchCmd->add_option("--time", watchArgs.time, "Clock time t in seconds (default 0)");
    watchCmd->add_option("--backend", watchArgs.backend, "jit (default), interp or vulkan");
    watchCmd->add_option("--device", watchArgs.device, "Vulkan device index for --backend vulkan")
        ->check(CLI::NonNegativeNumber);
    watchCmd->add_option("--depth", watchArgs.depth, "Bits per channel: 8, 16, half or float");
    watchCmd->add_option("--threads", watchArgs.threads, "Worker threads (default: all cores)");
    watchCmd
        ->add_option("--debounce", watchArgs.debounceMs,
                     "Milliseconds of quiet after a change before rebuilding (default 30)")
        ->check(CLI::Range(0, 10000));
    watchCmd->add_flag("--once", watchArgs.once, "Render the scene as it is now and exit");
    watchCmd->add_flag("-q,--quiet", watchArgs.quiet, "Print nothing but diagnostics");
    watchCmd->footer(
        "Each good save re-renders the image (written beside it, then renamed over it, so an\n"
        "image viewer never reads half a file); a save with errors prints them and leaves the\n"
        "last good image. Saves that change only numbers reuse the compiled kernel. Ctrl-C\n"
        "stops (exit 0).");

    cli::ViewArgs viewArgs;
    CLI::App* viewCmd =
        app.add_subcommand("view", "Open a window on a scene that reloads as the file is saved");
    viewCmd->add_option("scene", viewArgs.scene,
                        "The .moire scene (default: the embedded default scene)");
    viewCmd->add_option("--backend", viewArgs.backend,
                        "vulkan or jit (default: vulkan on a GPU, else jit), or interp");
    viewCmd->add_option("--device", viewArgs.device, "Vulkan device index for --backend vulkan")
        ->check(CLI::NonNegativeNumber);
    viewCmd->add_option("--size", viewArgs.size,
                        "Window size WIDTHxHEIGHT in screen units (default: the scene's)");
    viewCmd->add_option("--time", viewArgs.time, "Clock time t to start at (default 0)");
    viewCmd->add_flag("--paused", viewArgs.paused, "Start with the clock stopped");
    viewCmd->add_option("--threads", viewArgs.threads, "Worker threads (default: all cores)");
    viewCmd
        ->add_option("--debounce", viewArgs.debounceMs,
                     "Milliseconds of quiet after a change before rebuilding (default 30)")
        ->check(CLI::Range(0, 10000));
    viewCmd->add_flag("--trace", viewArgs.trace, "Print a line per frame shown")->group("");
    viewCmd->footer(
        "Mouse: the wheel zooms about the cursor; a drag pans, or moves the selected layer;\n"
        "alt-drag (or ctrl-drag) turns the selected layer about the world origin; a click on a\n"
        "stroke selects its layer. Keys: 1-9 select a layer, 0 or Esc none; space pauses and\n"
        "plays; . and , step a frame; the arrows move the clock 1 s (shift: 0.1 s); r resets\n"
        "the view; s saves a still beside the scene; p prints the placement; w writes it\n"
        "into the scene file; h hides the status line; q quits. Saves reload; a save with\n"
        "errors keeps the last good picture under the diagnostics.");

    std::vector<std::string> checkScenes;
    bool checkQuiet = false;
    CLI::App* checkCmd = app.add_subcommand("check", "Check scenes for errors without rendering");
    checkCmd->add_option("scenes", checkScenes, "The .moire scenes, - for standard input")
        ->required();
    checkCmd->add_flag("-q,--quiet", checkQuiet, "Print nothing but errors");
    std::string checkFormat = "text";
    checkCmd
        ->add_option("--format", checkFormat,
                     "text (default), or json: the diagnostics as JSON on standard output")
        ->check(CLI::IsMember({"text", "json"}));

    CLI::App* devicesCmd = app.add_subcommand("devices", "List the Vulkan devices");

    cli::CompileArgs compileArgs;
    CLI::App* compileCmd = app.add_subcommand("compile", "Show a stage of the compiler");
    compileCmd->add_option("scene", compileArgs.scene,
                           "The .moire scene, - for standard input (default: the embedded "
                           "default scene)");
    compileCmd->add_option("--dump", compileArgs.dump,
                           "ast, ir, ir-ad, frame, kernel, llvm, glsl or spirv (default ir)");
    compileCmd->add_flag("--fields", compileArgs.layerFields,
                         "Also output each layer's index and distance");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : cli::kExitUsage;
    }
    try {
        if (*renderCmd) return cli::render(renderArgs);
        if (*clipCmd) {
            clipArgs.hasTo = toOpt->count() > 0;
            return cli::clip(clipArgs);
        }
        if (*watchCmd) return cli::watch(watchArgs);
        if (*viewCmd) return cli::view(viewArgs);
        if (*checkCmd) return cli::check(checkScenes, checkQuiet, checkFormat);
        if (*compileCmd) return cli::compile(compileArgs);
        if (*devicesCmd) return cli::devices();
        fmt::print("{}", app.help());
        return 0;
    } catch (const std::bad_alloc&) {
        // The estimate before a render (MemoryBudget.h) catches the sizes known to be too
        // large; this is whatever else runs out, said as the user's problem, not ours.
        fmt::print(stderr, "moire: error: out of memory\n");
        return cli::kExitUserError;
    } catch (const InternalError& e) {
        fmt::print(stderr, "moire: {}\nPlease report this with the scene that caused it.\n",
                   e.what());
        return cli::kExitInternal;
    } catch (const std::exception& e) {
        fmt::print(stderr, "moire: internal error: {}\n", e.what());
        return cli::kExitInternal;
    }
}
