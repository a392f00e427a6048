// `moire view`: a window on a scene that reloads as the file is saved, with the camera and
// each layer's placement under the mouse (spec §8.4). The picture is rendered off the
// window's thread (FrameRenderer) by the backend given, at the window's framebuffer size, and
// shown as a texture on one full-window quad (OpenGL 2.1, so Mesa's llvmpipe under Xvfb
// runs it as well as any GPU driver).
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Defines.h"
#include "compiler/sema/Views.h"

#include <optional>
#include <string>

namespace moire::view {

struct ViewerOptions {
    std::string scenePath;     // empty: the embedded default scene, not reloaded
    int width = 0, height = 0; // the window in screen units; 0: the scene's size
    double time = 0.0;         // the clock at start
    bool paused = false;
    int threads = 0;     // CPU kernels' worker threads; 0: one per core
    int debounceMs = 30; // quiet after a save before rebuilding
    // For tests: on stdout, `frame N WxH t=T full|preview v=V` per frame shown (WxH the
    // pixels rendered, V the version of the view's state they show), and `placed v=V` after
    // the placement `p` prints.
    bool trace = false;
    std::string backendLabel;               // for the status line
    Defines defines;                        // `-D` values, applied to every build
    std::optional<sema::FilterMode> filter; // --filter, replacing the scene's; unset: the scene's
};

// Opens the window and runs until it is closed; returns the process exit status (0, or 1
// when the scene cannot be read or no window can be opened).
int runViewer(Backend& backend, const ViewerOptions& options);

} // namespace moire::view
