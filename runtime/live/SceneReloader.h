// The live-reload loop shared by `moire view`, `moire watch` and the latency benchmark: a
// thread that waits on the scene file, reads it when it settles, and builds it (SceneBuilder)
// while whoever renders keeps showing the last good frame.
#pragma once

#include "runtime/live/FileWatch.h"
#include "runtime/live/SceneBuilder.h"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace moire {

class SceneReloader {
  public:
    struct Options {
        CompileOptions compile;
        FileWatch::Options watch;
    };
    // Throws std::runtime_error (one line) when the scene's directory cannot be watched.
    SceneReloader(std::string path, Backend& backend, Options options);
    ~SceneReloader(); // stops the thread

    // Reads and builds the file as it is now, on the calling thread (the first frame; the
    // thread does the same after each change). Unchanged when the bytes are the last built.
    BuildResult loadNow();

    // Starts the thread. `onEvent` runs on it for every new state of the file, good or bad;
    // Unchanged states (an editor saving the same bytes) are skipped.
    void start(std::function<void(const BuildResult&)> onEvent);
    // Stops the thread, finishing the build in hand. Safe from any thread but the reloader's.
    void stop();

    SceneBuilder& builder() { return builder_; }

  private:
    void run();

    std::string path_;
    SceneBuilder builder_;
    FileWatch watch_;
    std::function<void(const BuildResult&)> onEvent_;
    std::thread thread_;
    std::atomic<bool> stopping_{false};
};

} // namespace moire
