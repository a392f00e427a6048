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

struct ReloadEvent {
    BuildResult result; // never Unchanged
    // When the file began to change (the first event of the settled batch), for
    // edit-to-pixels latency; the time of the read for the first load.
    std::chrono::steady_clock::time_point changedAt;
    int generation = 0; // counts events, from 1
};

class SceneReloader {
  public:
    struct Options {
        CompileOptions compile;
        FileWatch::Options watch;
    };
    // Throws std::runtime_error (one line) when the scene's directory cannot be watched.
    SceneReloader(std::string path, Backend& backend, Options options);
    ~SceneReloader(); // stops the thread

    // Reads and builds the file once on the calling thread (the first frame). Not Unchanged
    // unless called twice on the same bytes.
    ReloadEvent loadNow();

    // Starts the thread. `onEvent` runs on it for every new state of the file, good or bad;
    // Unchanged states (an editor saving the same bytes) are skipped.
    void start(std::function<void(const ReloadEvent&)> onEvent);
    // Stops the thread, finishing the build in hand. Safe from any thread but the reloader's.
    void stop();

    const std::string& path() const { return path_; }
    SceneBuilder& builder() { return builder_; }

  private:
    ReloadEvent readAndBuild(std::chrono::steady_clock::time_point changedAt);
    void run();

    std::string path_;
    SceneBuilder builder_;
    FileWatch watch_;
    std::function<void(const ReloadEvent&)> onEvent_;
    std::thread thread_;
    std::atomic<bool> stopping_{false};
    int generation_ = 0;
};

} // namespace moire
