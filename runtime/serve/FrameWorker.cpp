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
// Rows a CPU worker renders and turns into bytes at a time.
constexpr int kBandRows = 16;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
} // namespace

std::vector<unsigned char> encodeFramePng(int width, int height, const std::vector<uint8_t>& rgba) {
    Image image;
    image.width = width;
    image.height = height;
    image.channels = 4;
    image.pixels.resize(rgba.size());
    // b / 255 goes back to b through toByte: the PNG holds the frame's bytes exactly.
    for (size_t i = 0; i < rgba.size(); ++i) image.pixels[i] = rgba[i] / 255.0f;
    WriteOptions write;
    write.compression = kPreviewCompression;
    return encodeImage("frame.png", "png", image, write);
}

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
        request.maxSide = kMaxFrameSide;
        request.literals = &job.literals;
        FrameValues values;
        if (!evaluateFrame(*job.build->program, request, values, out.error)) return out;
        out.width = values.width;
        out.height = values.height;
        out.parameters = values.parameters;
        if (last_.build && last_.build->kernel == job.build->kernel &&
            last_.width == values.width && last_.height == values.height &&
            last_.uniforms == values.uniforms) {
            out.rgba = last_.rgba;
            out.renderMs = last_.renderMs;
            out.reused = true;
            return out;
        }
        FrameFootprint footprint;
        footprint.width = values.width;
        footprint.height = values.height;
        footprint.channels = job.build->kernel->numOutputs();
        footprint.format = "png"; // at most: a PNG is made when asked for
        footprint.gpu = job.build->kernel->wholeFrame();
        if (std::string problem = memoryProblem(footprint); !problem.empty()) {
            out.error = fmt::format("moire: error: {}", problem);
            return out;
        }
        const KernelFrame kf{values.uniforms.data(), values.width, values.height};
        ExecOptions exec;
        exec.threads = threads_;
        const CompiledKernel& kernel = *job.build->kernel;
        const size_t width = static_cast<size_t>(values.width);
        auto rgba = std::make_shared<std::vector<uint8_t>>(width * values.height * 4);
        auto toBytes = [&](const float* px, size_t count, int channels, uint8_t* to) {
            for (size_t i = 0; i < count; ++i)
                for (int c = 0; c < 4; ++c) to[i * 4 + c] = toByte(px[i * channels + c]);
        };
        if (kernel.wholeFrame()) {
            Image image = runKernel(kernel, kf, exec);
            toBytes(image.pixels.data(), width * image.height, image.channels, rgba->data());
        } else {
            // On the CPU each band's rows become bytes on the thread that rendered them,
            // while they are still in its cache.
            const int channels = kernel.numOutputs();
            runKernelInBands(
                kernel, kf, exec, kBandRows,
                [&](int band, int first, int count, const float* rows, size_t stride) {
                    for (int r = 0; r < count; ++r) {
                        const size_t y = static_cast<size_t>(band) * kBandRows + first + r;
                        toBytes(rows + r * stride, width, channels, rgba->data() + y * width * 4);
                    }
                });
        }
        out.renderMs = msSince(t0);
        out.rgba = rgba;
        last_ = Last{job.build, values.uniforms, values.width, values.height, rgba, out.renderMs};
    } catch (const std::bad_alloc&) {
        out.error =
            fmt::format("moire: error: out of memory drawing a {}x{} frame", job.width, job.height);
        out.rgba.reset();
    } catch (const std::exception& e) { // a lost device, a bug in the backend
        out.error = fmt::format("moire: error: {}", e.what());
        out.rgba.reset();
    }
    return out;
}

} // namespace moire::serve
