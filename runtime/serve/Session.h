// What a `moire serve` page shows and how its controls change it, with no HTTP in sight: the
// scene's last good build (reloaded on every save), the diagnostics of a bad save, the view's
// pan and zoom, the view and the overlay, the clock, and the frames the render thread makes.
// The server (Server.h) turns requests into calls here; the unit tests and the benchmark call
// them directly.
//
// Every change bumps a version and asks the render thread for a frame of the new state; every
// change and every frame publishes the state (stateJson) on the channel the page's event
// stream reads. A save with errors keeps the last good build and its picture under the
// diagnostics; the next good save takes them away.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "compiler/Parameters.h"
#include "runtime/live/SceneReloader.h"
#include "runtime/serve/FrameWorker.h"
#include "runtime/serve/StateChannel.h"
#include "runtime/view/ViewCamera.h"
#include "runtime/view/ViewClock.h"

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace moire::serve {

// A request the session refuses (a value out of range, an unknown view): the reason, one line.
class RequestError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct SessionOptions {
    std::string scene;         // the scene file (the only file the server reads)
    CompileOptions compile;    // the mode is set to Interactive (the view's pan and zoom)
    int width = 0, height = 0; // a fixed frame size (--size); 0: the scene's, until the page's
    double time = 0.0;
    bool paused = false;
    int threads = 0; // render and encode threads; 0: one per core
    FileWatch::Options watch;
    std::string backend; // the backend's name, for the page
    // Called with each new state of the file after the first (on the reload thread), for the
    // terminal: a good build, or a bad one with its diagnostics.
    std::function<void(const BuildResult&)> onReload;
};

// The largest zoom step one gesture may ask for, either way.
constexpr double kMaxZoomStep = 100.0;
// Frames the page may still fetch by id after newer ones replaced them.
constexpr size_t kFramesKept = 4;

class Session {
  public:
    // Throws std::runtime_error (one line) when the scene's directory cannot be watched.
    Session(Backend& backend, SessionOptions options);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Builds the scene as it is now (on the calling thread), asks for its first frame, and
    // starts following the file. The BuildResult says whether the scene had errors.
    BuildResult start();
    // Stops following the file and rendering; closes the channel (the event streams end).
    void stop();

    // --- The page's requests: each returns the version whose frame will show the change, or
    // throws RequestError with the reason it was refused.

    // The frame's size in pixels: the picture's box on the page (ignored with a fixed size).
    uint64_t resize(int width, int height);
    // "pattern", "envelope", "split", "ratio", or "scene" (the scene's own view); the overlay
    // on or off, or the scene's own (nullopt). Both are structure: the scene is built again.
    uint64_t setView(const std::string& view);
    uint64_t setOverlay(std::optional<bool> overlay);
    // Gestures, in the frame's pixels from its top-left corner (pixel centres at i + 0.5).
    uint64_t zoom(double x, double y, double factor);
    uint64_t pan(double fromX, double fromY, double toX, double toY);
    uint64_t resetView();
    // A parameter's value (Parameters.h: radians for an angle, straight sRGB for a colour, 0
    // or 1 for a boolean), or its default again (nullopt). Uniforms only: never a rebuild.
    // Refused when the scene has no such parameter or checkParameterValue refuses the value.
    uint64_t setParameter(const std::string& name, std::optional<std::vector<double>> value);
    // The parameter called `name` in the build on the page, if there is one.
    std::optional<Parameter> parameter(const std::string& name) const;
    // The parameters as the page builds its sliders from them (ParameterValues.h).
    std::string parametersJson() const;
    // The clock.
    uint64_t play();
    uint64_t pause();
    uint64_t seek(double time);

    StateChannel& channel() { return channel_; }
    // The state the page sees, as JSON (docs/live.md lists its fields).
    std::string stateJson() const;
    struct Frame {
        uint64_t id = 0;
        int width = 0, height = 0;
        std::shared_ptr<const std::vector<uint8_t>> rgba; // straight sRGB, rows top to bottom
    };
    // A frame by its id, while it is among the last kFramesKept; nothing after that.
    std::optional<Frame> frame(uint64_t id) const;
    // The same frame as a PNG file (made on the first request); null when it is gone.
    std::shared_ptr<const std::vector<unsigned char>> framePng(uint64_t id) const;
    // The version of the newest change, and of the newest frame published (tests).
    uint64_t version() const;
    uint64_t shownVersion() const;

  private:
    struct Shown {
        uint64_t id = 0, version = 0;
        int width = 0, height = 0;
        double time = 0.0, renderMs = 0.0;
        bool reused = false;
        std::vector<std::array<double, 4>> parameters; // each parameter's value in the frame
    };

    // The reloader's thread (and start, and setView): a new state of the file.
    void reloaded(const BuildResult& result);
    // The render thread: a finished frame.
    void framed(EncodedFrame frame);
    // Builds the scene again with the view and overlay now asked for (structure).
    void rebuild();
    // Records a change and asks for its frame; the caller holds mutex_.
    uint64_t changedLocked();
    FrameJob jobLocked(double time) const;
    void publishLocked();
    std::string stateJsonLocked() const;
    // The parameters' JSON (the page's sliders): the slider's value, or the frame's.
    std::string parametersJsonLocked() const;
    // The scene's camera at the clock's time, for the gestures; the last known when the
    // frame cannot be evaluated.
    view::SceneCamera sceneCameraLocked();
    void tick(); // the clock's thread

    Backend& backend_;
    SessionOptions options_;
    std::mutex rebuildMutex_; // one rebuild at a time
    std::unique_ptr<SceneReloader> reloader_;

    mutable std::mutex mutex_;
    std::shared_ptr<const LiveProgram> build_;
    std::string buildKind_; // "structure" or "numbers": how the last good build came
    double kernelMs_ = 0.0;
    std::string buildErrors_; // the file's diagnostics while its last save has errors
    std::string frameError_;  // why the last frame could not be drawn
    std::optional<sema::ViewMode> viewOverride_;
    std::optional<bool> overlayOverride_;
    view::ViewAdjust view_;
    view::SceneCamera camera_;
    // The sliders' values by parameter name: kept across saves while the parameter keeps its
    // type and the value its range.
    std::map<std::string, std::vector<double>> parameterValues_;
    int width_ = 0, height_ = 0;
    view::ViewClock clock_;
    uint64_t version_ = 0;
    uint64_t nextFrameId_ = 1;
    Shown shown_;
    std::deque<Frame> frames_;
    mutable std::mutex pngMutex_; // one PNG made at a time, outside mutex_
    mutable std::deque<std::pair<uint64_t, std::shared_ptr<const std::vector<unsigned char>>>>
        pngs_;

    StateChannel channel_;
    std::unique_ptr<FrameWorker> worker_;
    std::condition_variable clockWake_;
    bool stopping_ = false;
    std::thread clockThread_;
};

} // namespace moire::serve
