#include "runtime/serve/FrameWorker.h"

#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/MemoryBudget.h"
#include "runtime/TileExecutor.h"

#include <chrono>
#include <fmt/format.h>
#include <new>

namespace moire::serve {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
} // namespace

FrameWorker::FrameWorker(int threads, std::function<void(EncodedFrame)> onFrame)
    : threads_(threads), onFrame_(std::move(onFrame)) {
    thread_ = std::thread([this] { run(); });
}

FrameWorker::~FrameWorker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void FrameWorker::submit(FrameJob job) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_ = std::move(job);
    }
    wake_.notify_all();
}

bool FrameWorker::idle() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return !inHand_ && !pending_;
}

void FrameWorker::drain() {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return stop_ || (!inHand_ && !pending_); });
}

void FrameWorker::run() {
    for (;;) {
        FrameJob job;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || pending_; });
            if (stop_) break;
            job = std::move(*pending_);
            pending_.reset();
            inHand_ = true;
        }
        EncodedFrame frame = render(job);
        if (onFrame_) onFrame_(std::move(frame));
        {
            std::lock_guard<std::mutex> lock(mutex_);
            inHand_ = false;
        }
        idle_.notify_all();
    }
    idle_.notify_all();
}

EncodedFrame FrameWorker::render(const FrameJob& job) {
    EncodedFrame out;
    out.version = job.version;
    out.time = job.time;
    if (!job.build) {
        out.error = "moire: error: no good build of the scene yet";
        return out;
    }
    try {
        const auto t0 = Clock::now();
        FrameRequest request;
        request.time = job.time;
        request.width = job.width;
        request.height = job.height;
        request.literals = &job.literals;
        FrameValues values;
        if (!evaluateFrame(*job.build->program, request, values, out.error)) return out;
        out.width = values.width;
        out.height = values.height;
        if (last_.build && last_.build->kernel == job.build->kernel &&
            last_.width == values.width && last_.height == values.height &&
            last_.uniforms == values.uniforms) {
            out.png = last_.png;
            out.renderMs = last_.renderMs;
            out.encodeMs = last_.encodeMs;
            out.reused = true;
            return out;
        }
        FrameFootprint footprint;
        footprint.width = values.width;
        footprint.height = values.height;
        footprint.channels = job.build->kernel->numOutputs();
        footprint.format = "png";
        footprint.gpu = job.build->kernel->wholeFrame();
        if (std::string problem = memoryProblem(footprint); !problem.empty()) {
            out.error = fmt::format("moire: error: {}", problem);
            return out;
        }
        KernelFrame kf;
        kf.uniforms = values.uniforms.data();
        kf.imageW = values.width;
        kf.imageH = values.height;
        ExecOptions exec;
        exec.threads = threads_;
        Image image = runKernel(*job.build->kernel, kf, exec);
        out.renderMs = msSince(t0);
        const auto t1 = Clock::now();
        WriteOptions write;
        // Shown once and soon replaced: the fast level, as `moire watch` writes.
        write.compression = kPreviewCompression;
        write.threads = threads_;
        auto png = std::make_shared<const std::vector<unsigned char>>(
            encodeImage("frame.png", "png", image, write));
        out.encodeMs = msSince(t1);
        out.png = png;
        last_ = Last{job.build, values.uniforms, values.width, values.height,
                     png,       out.renderMs,    out.encodeMs};
    } catch (const std::bad_alloc&) {
        out.error =
            fmt::format("moire: error: out of memory drawing a {}x{} frame", job.width, job.height);
        out.png.reset();
    } catch (const std::exception& e) { // a lost device, a bug in the backend
        out.error = fmt::format("moire: error: {}", e.what());
        out.png.reset();
    }
    return out;
}

} // namespace moire::serve
