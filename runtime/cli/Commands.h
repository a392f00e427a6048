// The `moire` subcommands. Each returns the process exit status (docs/cli.md):
#pragma once

#include "compiler/Defines.h"

#include <optional>
#include <string>
#include <vector>

namespace moire::cli {

constexpr int kExitOk = 0;
constexpr int kExitScene = 1;     // the scene has errors: its diagnostics were printed
constexpr int kExitUsage = 2;     // the command line asks for something moire does not do
constexpr int kExitIo = 3;        // a file cannot be read or written (or ffmpeg cannot make it)
constexpr int kExitMachine = 4;   // no usable Vulkan device, not enough memory, the GPU failed
constexpr int kExitInternal = 70; // a bug in moire (sysexits' EX_SOFTWARE)
// Stopped by SIGINT or SIGTERM: 128 + the signal (130, 143).

// -q and -v, which every command takes.
struct Verbosity {
    bool quiet = false;   // nothing but errors
    bool verbose = false; // also each stage and how long it took, on stderr
};

struct RenderArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // empty: <scene stem>.png in the current directory
    std::string size;   // "WxH", empty: the scene's
    // --region "X0,Y0,X1,Y1": only that window of the frame, at the frame's pixel grid, its
    // place recorded in the file for `moire assemble`; empty: the whole frame.
    std::string region;
    double time = 0.0;
    std::string backend = "jit";
    int device = -1;   // --device (vulkan): -1 the first discrete GPU, else the first device
    std::string depth; // 8, 16, half, float
    double dpi = 0.0;
    int compression = -1; // --compression: PNG's zlib level, -1 the default (ImageIO.h)
    int threads = 0;
    // --view and the envelope's settings, replacing the scene's (sema/Views.h).
    std::string view; // empty: the scene's
    std::optional<double> envelopeGain = std::nullopt, envelopeTaps = std::nullopt;
    bool overlay = false; // --overlay: the fringe curves over the view, whatever the scene says
    std::string filter;   // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
    Defines defines; // -D NAME=VALUE
};
int render(const RenderArgs& args);

// `moire assemble`: region tiles (render --region) joined into the whole frame, written as
// render writes a whole frame (AssembleCommand.cpp).
struct AssembleArgs {
    std::vector<std::string> tiles;
    std::string output;
    std::string size;     // "WxH": the frame the tiles must make; empty: the one they name
    std::string depth;    // empty: the tiles' (the format's default when it cannot hold it)
    int compression = -1; // PNG's zlib level; -1: render's default
    int threads = 0;
    Verbosity verbosity;
};
int assemble(const AssembleArgs& args);

// `moire clip`: frame n at exactly t = from + n / fps, to numbered images or a video.
// Exits 130 (143 for SIGTERM) when interrupted, after the frame in hand.
struct ClipArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // image pattern (frame_%04d.png) or video (.mp4, .webm, .gif)
    double fps = 0.0;
    std::string size; // "WxH", empty: the scene's
    double from = 0.0;
    double to = 0.0; // with hasTo: frames before this time
    bool hasTo = false;
    std::string frames; // "N" or "A..B"; empty: --to, or the timings' loop
    std::string backend = "jit";
    int device = -1;
    std::string depth; // image frames only
    int threads = 0;
    bool plan = false;  // print the schedule, render nothing
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
    Defines defines; // -D NAME=VALUE
};
int clip(const ClipArgs& args);

// `moire watch`: re-renders `output` (atomically replaced) on every good save of the scene and
// prints diagnostics for bad ones, until interrupted (exit 0).
struct WatchArgs {
    std::string scene;
    std::string output; // empty: <scene stem>.png
    std::string size;   // "WxH", empty: the scene's
    double time = 0.0;
    std::string backend = "jit";
    int device = -1;
    std::string depth;
    int threads = 0;
    int debounceMs = 30;
    bool once = false;  // render the current file and exit (no watching)
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
    Defines defines; // -D NAME=VALUE
};
int watch(const WatchArgs& args);

// `moire view`: the interactive window (runtime/view/), reloading as the scene is edited.
struct ViewArgs {
    std::string scene;   // empty: the embedded default scene (no reload)
    std::string backend; // empty: vulkan on a hardware GPU, else jit
    int device = -1;
    std::string size; // initial window size "WxH" in screen coordinates; empty: the scene's
    double time = 0.0;
    bool paused = false;
    int threads = 0;
    int debounceMs = 30;
    bool trace = false; // hidden: a line per frame shown, and after `p` a marker (tests)
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
    Defines defines; // -D NAME=VALUE
};
int view(const ViewArgs& args);

// `moire check`: every scene is checked; the status is the first failing scene's.
struct CheckArgs {
    std::vector<std::string> scenes; // "-": standard input
    std::string format = "text";     // or "json" (checkJson)
    Verbosity verbosity;
};
int check(const CheckArgs& args);
// `check --format=json`: every scene's diagnostics as one JSON document (CheckJson.cpp).
int checkJson(const std::vector<std::string>& scenes);

// Lists the Vulkan devices --device can name (-q: none, the status says whether any).
int devices(const Verbosity& verbosity);

struct CompileArgs {
    std::string scene;
    std::string dump = "ir"; // ast, ir, ir-ad, frame, kernel, llvm, glsl, spirv
    bool layerFields = false;
    std::string output = "-"; // the file the dump goes to; "-": standard output
    Verbosity verbosity;
};
int compile(const CompileArgs& args);

// `moire fmt`: every file is formatted in place (only when that changes it; - : standard
// input to standard output), or with --check listed when formatting would change it. The
// status is the first failing file's (FmtCommand.cpp).
struct FmtArgs {
    std::vector<std::string> files; // "-": standard input
    bool check = false;
    Verbosity verbosity;
};
int formatFiles(const FmtArgs& args);

// `moire names`: the language's names by kind (compiler/LanguageNames.h), as text or JSON.
struct NamesArgs {
    bool json = false;
    Verbosity verbosity;
};
int names(const NamesArgs& args);

} // namespace moire::cli
