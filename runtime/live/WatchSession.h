// Headless live coding (`moire watch`): each good state of the scene file is rendered and the
// image replaced atomically; each bad state is reported and the last good image stays. The
// command line prints the reports; tests and benchmarks read them.
#pragma once

#include "runtime/FrameEval.h"
#include "runtime/live/SceneReloader.h"
#include "runtime/output/ImageIO.h"
#include "runtime/TileExecutor.h"

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace moire {

struct WatchOptions {
    std::string scene;
    std::string output;   // the image kept up to date
    FrameRequest request; // the instant and size rendered (request.literals is ignored)
    WriteOptions write;
    ExecOptions exec;
    FileWatch::Options watch;
    Defines defines;                        // `-D` values, applied to every build
    std::optional<sema::FilterMode> filter; // --filter, replacing the scene's; unset: the scene's
};

// What happened to one state of the file.
struct WatchReport {
    BuildResult result; // what the build of this state gave
    bool wrote = false; // the output now holds this state's render
    // Why a bad state is bad: its text (errors, or a frame that cannot be drawn), a file (the
    // scene unreadable, the image unwritable), or the machine (memory, the device).
    enum class Failure { None, Scene, File, Machine };
    Failure failure = Failure::None;
    std::string diagnostics; // bad states: `file:line:col: error:` lines (or an I/O error)
    int width = 0, height = 0;
    double renderMs = 0.0;
    std::string notes; // good states: the stroke floor's notes (FloorNote.h), when any
    bool good() const { return wrote; }
};

class WatchSession {
  public:
    // Throws std::runtime_error (one line) when the scene's directory cannot be watched.
    WatchSession(Backend& backend, WatchOptions options);
    ~WatchSession();

    // Builds and renders the file as it is now, on the calling thread.
    WatchReport processNow();
    // Watches on a thread; `onReport` runs there after each new state is handled.
    void start(std::function<void(const WatchReport&)> onReport);
    void stop();

    SceneBuilder& builder() { return reloader_.builder(); }

  private:
    WatchReport handle(const BuildResult& ev);

    Backend& backend_;
    WatchOptions options_;
    SceneReloader reloader_;
};

} // namespace moire
