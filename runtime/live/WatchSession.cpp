#include "runtime/live/WatchSession.h"

#include "compiler/backend/Backend.h"
#include "runtime/FloorNote.h"
#include "runtime/output/MemoryBudget.h"

#include <fmt/format.h>
#include <new>

namespace moire {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

SceneReloader::Options reloaderOptions(const WatchOptions& o) {
    SceneReloader::Options r;
    r.watch = o.watch;
    r.compile.defines = o.defines;
    r.compile.filter = o.filter;
    return r;
}
} // namespace

WatchSession::WatchSession(Backend& backend, WatchOptions options)
    : backend_(backend), options_(std::move(options)),
      reloader_(options_.scene, backend, reloaderOptions(options_)) {}

WatchSession::~WatchSession() {
    stop();
}

WatchReport WatchSession::processNow() {
    return handle(reloader_.loadNow());
}

void WatchSession::start(std::function<void(const WatchReport&)> onReport) {
    reloader_.start([this, onReport = std::move(onReport)](const BuildResult& ev) {
        WatchReport r = handle(ev);
        if (onReport) onReport(r);
    });
}

void WatchSession::stop() {
    reloader_.stop();
}

WatchReport WatchSession::handle(const BuildResult& b) {
    WatchReport r;
    r.result = b;
    using Failure = WatchReport::Failure;
    if (!b.good()) {
        r.diagnostics = b.diagnostics;
        r.failure = b.unreadable ? Failure::File : Failure::Scene;
        return r;
    }
    // A good build can still describe a frame that cannot be drawn (a zero zoom, a size out of
    // range): that is a bad state too, and the last image stays.
    FrameRequest req = options_.request;
    req.literals = nullptr;
    FrameValues frame;
    if (!evaluateFrame(*b.build->program, req, frame, r.diagnostics)) {
        r.failure = Failure::Scene;
        return r;
    }
    FrameFootprint footprint;
    footprint.width = frame.width;
    footprint.height = frame.height;
    footprint.channels = b.build->kernel->numOutputs();
    footprint.format = imageFormatOf(options_.output);
    footprint.gpu = b.build->kernel->wholeFrame();
    if (std::string problem = memoryProblem(footprint); !problem.empty()) {
        r.diagnostics = fmt::format("moire: error: {}\n", problem);
        r.failure = Failure::Machine;
        return r;
    }
    auto t0 = std::chrono::steady_clock::now();
    Image img;
    try {
        KernelFrame kf;
        kf.uniforms = frame.uniforms.data();
        kf.imageW = frame.width;
        kf.imageH = frame.height;
        img = runKernel(*b.build->kernel, kf, options_.exec);
        r.renderMs = msSince(t0);
        writeImage(options_.output, img, options_.write);
    } catch (const std::bad_alloc&) {
        r.diagnostics = fmt::format("moire: error: out of memory rendering a {}x{} image\n",
                                    frame.width, frame.height);
        r.failure = Failure::Machine;
        return r;
    } catch (const BackendError& e) { // a lost device
        r.diagnostics = fmt::format("moire: error: {}\n", e.what());
        r.failure = Failure::Machine;
        return r;
    } catch (const std::exception& e) { // a full disk, a vanished directory
        r.diagnostics = fmt::format("moire: error: {}\n", e.what());
        r.failure = Failure::File;
        return r;
    }
    r.wrote = true;
    r.notes = strokeFloorNotes(*b.build->program, options_.filter, frame.pixelSize);
    r.width = frame.width;
    r.height = frame.height;
    return r;
}

} // namespace moire
