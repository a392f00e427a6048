// Helpers the subcommands share (defined in Commands.cpp).
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/cli/Commands.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/MemoryBudget.h"

#include <chrono>
#include <memory>
#include <string>

namespace moire::cli {

struct Source {
    std::string path;
    std::string text;
};

// The scene path that means standard input (render, clip, check, compile).
inline constexpr const char* kStdinPath = "-";
// The output path that means standard output (render -o -, compile -o -).
inline constexpr const char* kStdoutPath = "-";
// The largest --dpi: a 32-bit float in the file, and far past any printer.
constexpr double kMaxDpi = 1e6;

// Reads a scene, or the embedded default when `path` is empty, or standard input when it is
// "-". Prints the reason and returns false when the file cannot be read.
bool readScene(const std::string& path, Source& out);
// Compiles, printing any diagnostics; null when the scene has errors.
std::unique_ptr<SceneProgram> compileOrReport(const Source& src,
                                              const CompileOptions& options = {});
// --filter: the help line every drawing command gives it, and the check that reads it into
// `options.filter` (left unset when not given); false after an error naming both filters.
std::string filterHelp();
bool checkFilterOption(const std::string& given, CompileOptions& options);
// The options of the commands that write one image (render, watch), and what they mean.
struct ImageArgs {
    const std::string& scene;  // empty: the embedded default scene
    const std::string& output; // empty: <scene stem>.png
    const std::string& size;
    const std::string& depth;
    const std::string& backend;
    int device;
    int maxSide = kMaxImageSide; // kMaxFrameSide where the frame is held whole (watch)
};
struct ImageOptions {
    int width = 0, height = 0; // 0: the scene's size
    PixelDepth depth = PixelDepth::Default;
    std::string output; // kStdoutPath: standard output
    std::string format; // imageFormatOf(output); "png" for standard output
};
// Checks --backend (a known name; empty: chosen by the command) and --device (Vulkan only),
// printing the reason when one is wrong.
bool checkBackendArgs(const std::string& backend, int device);
// Checks --size, --depth, the output's format, the backend's name and --device, printing
// the reason for the first that is wrong.
bool checkImageOptions(const ImageArgs& args, ImageOptions& out);
// "WIDTHxHEIGHT", each side 1 to kMaxImageSide.
bool parseSize(const std::string& s, int& w, int& h, int maxSide = kMaxImageSide);
// --time, --from: a finite number of seconds; prints the reason when not.
bool checkTime(double t, const char* option);
// --dpi: 0 (none recorded) or finite, above 0 and at most kMaxDpi; prints the reason when not.
bool checkDpi(double dpi);
// Prints "moire: error: a WxH image needs about ..." and returns false when the frame will
// not fit in the memory this process can have (MemoryBudget.h).
bool checkMemory(const FrameFootprint& frame);
// --depth: "" (the format's default), 8, 16, half, float.
bool parseDepth(const std::string& s, PixelDepth& d);
// The backend as a closing line names it: Vulkan says which device drew the image.
std::string describe(const Backend& backend);
double secondsSince(std::chrono::steady_clock::time_point t0);
// -v's lines: "moire: <what> (12.3 ms)", each stage timed from the end of the one before.
class Stages {
  public:
    explicit Stages(const Verbosity& verbosity);
    void done(const std::string& what);

  private:
    bool verbose_;
    std::chrono::steady_clock::time_point last_;
};
// The backend by name. One that cannot run here (no Vulkan driver or device, a bad device
// index) is the user's to fix: prints one line and returns null.
std::unique_ptr<Backend> openBackend(const std::string& name, int device);

} // namespace moire::cli
