// The `moire` subcommands. Each returns the process exit status:
//   0 success, 1 the scene or a file is wrong (a diagnostic was printed),
//   2 the command line is wrong, 70 an internal error in moire.
#pragma once

#include <string>
#include <vector>

namespace moire::cli {

constexpr int kExitOk = 0;
constexpr int kExitUserError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInternal = 70;

struct RenderArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // empty: <scene stem>.png in the current directory
    std::string size;   // "WxH", empty: the scene's
    double time = 0.0;
    std::string backend = "jit";
    int device = -1;   // --device (vulkan): -1 the first discrete GPU, else the first device
    std::string depth; // 8, 16, half, float
    double dpi = 0.0;
    int threads = 0;
    bool quiet = false;
};
int render(const RenderArgs& args);

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
    bool plan = false; // print the schedule, render nothing
    bool quiet = false;
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
    bool once = false; // render the current file and exit (no watching)
    bool quiet = false;
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
};
int view(const ViewArgs& args);

int check(const std::vector<std::string>& scenes, bool quiet, const std::string& format = "text");
// `check --format=json`: every scene's diagnostics as one JSON document (CheckJson.cpp).
int checkJson(const std::vector<std::string>& scenes);

// Lists the Vulkan devices --device can name.
int devices();

struct CompileArgs {
    std::string scene;
    std::string dump = "ir"; // ast, ir, ir-ad, frame, kernel, llvm
    bool layerFields = false;
};
int compile(const CompileArgs& args);

} // namespace moire::cli
