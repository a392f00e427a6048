// Helpers the subcommands share (defined in Commands.cpp).
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/ImageIO.h"

#include <chrono>
#include <memory>
#include <string>

namespace moire::cli {

struct Source {
    std::string path;
    std::string text;
};

// Reads a scene, or the embedded default when `path` is empty. Prints the reason and returns
// false when the file cannot be read.
bool readScene(const std::string& path, Source& out);
// Compiles, printing any diagnostics; null when the scene has errors.
std::unique_ptr<SceneProgram> compileOrReport(const Source& src,
                                              const CompileOptions& options = {});
// "WIDTHxHEIGHT", each side 1 to kMaxImageSide.
bool parseSize(const std::string& s, int& w, int& h);
// --depth: "" (the format's default), 8, 16, half, float.
bool parseDepth(const std::string& s, PixelDepth& d);
// The backend as a closing line names it: Vulkan says which device drew the image.
std::string describe(const Backend& backend);
double secondsSince(std::chrono::steady_clock::time_point t0);
// The backend by name. One that cannot run here (no Vulkan driver or device, a bad device
// index) is the user's to fix: prints one line and returns null.
std::unique_ptr<Backend> openBackend(const std::string& name, int device);

} // namespace moire::cli
