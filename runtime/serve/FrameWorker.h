// The render thread of `moire serve`: renders the newest job it was given, as the 8-bit RGBA
// bytes the page draws (the very bytes `moire render` writes to a PNG: toByte). Encoding a
// PNG of 1280x720 took as long as rendering it, so the page takes the bytes as they are and a
// PNG is made only when one is asked for (Session::framePng).
//
// Only the newest job matters, but a frame in hand is finished rather than abandoned: while a
// slider is dragged, jobs come faster than frames, and abandoning the frame in hand for each
// new one would show nothing until the hand stops. So a job waits at most one frame, and a
// thousand jobs a second make one frame after another, each of the newest values.
#pragma once

#include "runtime/live/SceneBuilder.h"

#include <array>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace moire::serve {

struct FrameJob {
    std::shared_ptr<const LiveProgram> build;
    // The whole literal table: the program's, with the page's parameter values and the view's
    // pan and zoom written in (FrameRequest::literals).
    std::vector<double> literals;
    double time = 0.0;
    int width = 0, height = 0;
    uint64_t version = 0; // increases with every change of what is to be drawn
};

struct EncodedFrame {
    uint64_t version = 0; // the job's
    double time = 0.0;
    int width = 0, height = 0;
    // Straight sRGB RGBA, rows top to bottom; null when `error` is set.
    std::shared_ptr<const std::vector<uint8_t>> rgba;
    bool reused = false; // the uniforms were the last frame's: its picture, not rendered again
    std::vector<std::array<double, 4>> parameters; // each parameter's value in this frame
    double renderMs = 0.0;
    std::string error; // the frame could not be evaluated or rendered: why
};

// A frame's bytes as a PNG file (the fast zlib level: a page's picture, not a print).
std::vector<unsigned char> encodeFramePng(int width, int height, const std::vector<uint8_t>& rgba);

class FrameWorker {
  public:
    // `onFrame` runs on the render thread after each job. `threads` 0: one per core.
    FrameWorker(int threads, std::function<void(EncodedFrame)> onFrame);
    ~FrameWorker();
    FrameWorker(const FrameWorker&) = delete;
    FrameWorker& operator=(const FrameWorker&) = delete;

    // Replaces the pending job, if any.
    void submit(FrameJob job);
    // No job pending or in hand.
    bool idle() const;
    // Blocks until idle (tests, benchmarks).
    void drain();

  private:
    void run();
    EncodedFrame render(const FrameJob& job);

    int threads_;
    std::function<void(EncodedFrame)> onFrame_;
    mutable std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::optional<FrameJob> pending_;
    bool inHand_ = false;
    bool stop_ = false;
    // The last frame and what it was made from (render thread only): a still scene while the
    // clock runs gives the same uniforms, and so the same picture, frame after frame.
    struct Last {
        std::shared_ptr<const LiveProgram> build;
        std::vector<double> uniforms;
        int width = 0, height = 0;
        std::shared_ptr<const std::vector<uint8_t>> rgba;
        double renderMs = 0.0;
    } last_;
    std::thread thread_;
};

} // namespace moire::serve
