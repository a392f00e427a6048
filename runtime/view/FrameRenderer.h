// The viewer's render thread. The window's thread hands it jobs (a build, the view's
// adjustments, a time, a size) and shows whatever it finishes; it never waits on a frame, so
// the window stays responsive while a slow frame renders (a 1280x720 frame of the default
// scene is more than half a second on a two-core JIT).
//
// Only the newest job matters: a job submitted while another is pending replaces it, and a
// full frame in progress is abandoned, tile by tile, when a newer job arrives. While the user
// is in a gesture (job.interactive) and full frames are slow, a coarse preview is rendered
// first (each of its pixels exactly a block of the full frame's), then the full frame.
#pragma once

#include "runtime/Image.h"
#include "runtime/live/SceneBuilder.h"
#include "runtime/view/ParamValues.h"
#include "runtime/view/ViewCamera.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace moire::view {

struct RenderJob {
    std::shared_ptr<const LiveProgram> build;
    ViewAdjust view;
    double time = 0.0;
    int width = 0, height = 0; // the window's framebuffer
    bool interactive = false;  // part of a gesture: a quick preview first if frames are slow
    uint64_t version = 0;      // increases with every change of what is to be drawn
    ParamSet params;           // the panel's values for the build's parameters
};

struct RenderedFrame {
    std::vector<uint8_t> rgba;         // 8-bit sRGB, rows top to bottom
    int width = 0, height = 0;         // of the pixels
    int fullWidth = 0, fullHeight = 0; // of the frame they show
    int divisor = 1;                   // > 1: a preview, each pixel a divisor^2 block
    double ms = 0.0;                   // from the job to the pixels
    double time = 0.0;
    uint64_t version = 0;
    bool reused = false; // the uniforms were the last full frame's: its pixels, not rendered
    std::string error;   // no pixels: the frame could not be evaluated or rendered
};

// The frame values of `program` at `time` for a width x height image, with the view's
// adjustments in its literal slots (SceneProgram::viewSlot) and the panel's values in its
// parameters' (when given): what the picture on screen is drawn from. False, with the
// diagnostics, when the frame cannot be evaluated.
bool evaluateViewFrame(const SceneProgram& program, const ViewAdjust& view, double time, int width,
                       int height, FrameValues& out, std::string& diags,
                       const ParamSet* params = nullptr);

// Float RGBA (sRGB-encoded, straight alpha) to 8 bits the way the PNG writer rounds, so the
// window shows the bytes `moire render` writes.
void toRgba8(const float* rgba, int channels, size_t pixels, uint8_t* out);

class FrameRenderer {
  public:
    // `notify` is called on the render thread after each frame or message (the viewer posts
    // an empty event to wake the window's loop). `threads` 0: one per core.
    FrameRenderer(int threads, std::function<void()> notify);
    ~FrameRenderer();
    FrameRenderer(const FrameRenderer&) = delete;
    FrameRenderer& operator=(const FrameRenderer&) = delete;

    void submit(RenderJob job);
    // Renders `job` at full size and writes it as a PNG named <stem>-still-NNN.png beside
    // `scenePath` (the current directory and "default" when it is empty), never over an
    // existing file. The outcome comes back as a message.
    void saveStill(RenderJob job, std::string scenePath);

    // The newest finished frame since the last call, if any.
    std::optional<RenderedFrame> takeFrame();
    // Lines for the terminal (a still's path, a failure), oldest first.
    std::vector<std::string> takeMessages();
    // A job pending or in hand.
    bool busy() const;

  private:
    struct StillJob {
        RenderJob job;
        std::string scenePath;
    };
    void run();
    void renderJob(const RenderJob& job);
    void renderStill(const StillJob& still);
    // Renders `job` at 1/divisor resolution (1: full); false when a newer job made it moot.
    bool render(const RenderJob& job, int divisor, bool cancellable, RenderedFrame& out,
                Image* full);
    int previewDivisor(const RenderJob& job) const;

    int threads_;
    std::function<void()> notify_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<RenderJob> pending_;
    std::optional<StillJob> still_;
    std::optional<RenderedFrame> done_;
    std::vector<std::string> messages_;
    bool inHand_ = false;
    bool stop_ = false;
    std::atomic<uint64_t> newest_{0};
    double msPerPixel_ = 0.0; // of the last full frame (render thread only)
    // The last full frame and what it was computed from. The kernel sees the clock only
    // through the uniforms, so a job whose uniforms, kernel and size are the same (a still
    // scene while the clock runs) is the same picture and is not rendered again.
    struct Last {
        const CompiledKernel* kernel = nullptr;
        std::shared_ptr<const LiveProgram> build; // keeps `kernel` alive
        std::vector<double> uniforms;
        int width = 0, height = 0;
        std::vector<uint8_t> rgba;
        double ms = 0.0;
    } last_;
    std::thread thread_;
};

} // namespace moire::view
