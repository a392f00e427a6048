// The `moire` command line.
#include "compiler/diag/Diagnostics.h"
#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

int main(int argc, char** argv) {
    using namespace moire;
    CLI::App app{"moire: a compiler and renderer for moire-pattern scenes (.moire files)", "moire"};
    app.set_version_flag("--version", "moire " MOIRE_VERSION);
    app.require_subcommand(0, 1);
    app.footer(
        "Run 'moire COMMAND --help' for a command's options. Without a scene, render uses the\n"
        "embedded default scene.");

    cli::RenderArgs renderArgs;
    CLI::App* renderCmd = app.add_subcommand("render", "Render a scene to an image file");
    renderCmd->add_option("scene", renderArgs.scene,
                          "The .moire scene (default: the embedded default scene)");
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
    renderCmd->add_option("--dpi", renderArgs.dpi, "Print resolution to record in the file");
    renderCmd->add_option("--threads", renderArgs.threads, "Worker threads (default: all cores)");
    renderCmd->add_flag("-q,--quiet", renderArgs.quiet, "Print nothing but errors");

    std::vector<std::string> checkScenes;
    bool checkQuiet = false;
    CLI::App* checkCmd = app.add_subcommand("check", "Check scenes for errors without rendering");
    checkCmd->add_option("scenes", checkScenes, "The .moire scenes")->required();
    checkCmd->add_flag("-q,--quiet", checkQuiet, "Print nothing but errors");

    CLI::App* devicesCmd = app.add_subcommand("devices", "List the Vulkan devices");

    cli::CompileArgs compileArgs;
    CLI::App* compileCmd = app.add_subcommand("compile", "Show a stage of the compiler");
    compileCmd->add_option("scene", compileArgs.scene,
                           "The .moire scene (default: the embedded default scene)");
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
        if (*checkCmd) return cli::check(checkScenes, checkQuiet);
        if (*compileCmd) return cli::compile(compileArgs);
        if (*devicesCmd) return cli::devices();
        fmt::print("{}", app.help());
        return 0;
    } catch (const InternalError& e) {
        fmt::print(stderr, "moire: {}\nPlease report this with the scene that caused it.\n",
                   e.what());
        return cli::kExitInternal;
    } catch (const std::exception& e) {
        fmt::print(stderr, "moire: internal error: {}\n", e.what());
        return cli::kExitInternal;
    }
}
