// Which layer a click lands on, answered off the window's thread. A layer's distance at a
// pixel is not in the picture's kernel: it comes from a second compile of the scene's text
// with the layers' fields as outputs (CompileOptions::layerFields), run by the interpreter at
// the clicked pixel alone, with the view's adjustments as the picture has them. That compile
// takes as long as the scene's front end (milliseconds, more for a large scene), so it runs on
// the picker's own thread, once per build, and the window goes on drawing meanwhile.
#pragma once

#include "runtime/live/SceneBuilder.h"
#include "runtime/view/FrameRenderer.h"
#include "runtime/view/ViewCamera.h"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace moire {

class Interpreter;

namespace view {

struct PickRequest {
    RenderJob picture;      // the picture the click was on (its build, view, time and size)
    Vec2 at;                // in pixels from its top-left corner
    double tolerance = 4.0; // in pixels from a stroke's centre line
    uint64_t id = 0;        // given back with the answer
};

struct PickResult {
    uint64_t id = 0;
    std::shared_ptr<const LiveProgram> build;
    bool ok = false; // false: the pick could not be made (the selection should stay)
    int layer = -1;  // the layer picked, -1 none
};

// The layer whose stroke passes nearest `at` (within `tolerance` pixels; the topmost on a
// tie), or -1; nullopt when it cannot be told. `probe` is the scene compiled with layer
// fields and interactive slots, `kernel` its pixel kernel in the interpreter.
std::optional<int> pickLayer(const SceneProgram& probe, const Interpreter& kernel,
                             const PickRequest& request);

class LayerPicker {
  public:
    // `notify` is called on the picker's thread after each answer (the viewer posts an
    // empty event to wake the window's loop).
    explicit LayerPicker(std::function<void()> notify);
    ~LayerPicker();
    LayerPicker(const LayerPicker&) = delete;
    LayerPicker& operator=(const LayerPicker&) = delete;

    // Asks for the layer under a click; replaces a request not yet started.
    void request(PickRequest request);
    // The oldest answer not yet taken, if any.
    std::optional<PickResult> take();

  private:
    void run();
    PickResult answer(const PickRequest& request);

    std::function<void()> notify_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<PickRequest> pending_;
    std::vector<PickResult> done_;
    bool stop_ = false;
    // The picker's thread only: the probe of the last build asked about.
    std::shared_ptr<const SceneProgram> probeOf_;
    std::unique_ptr<SceneProgram> probe_;
    std::unique_ptr<Interpreter> probeKernel_;
    std::thread thread_;
};

} // namespace view
} // namespace moire
