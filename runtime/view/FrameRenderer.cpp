#include "runtime/view/FrameRenderer.h"

#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <new>
#include <utility>

namespace moire::view {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// <dir>/<stem>-still-NNN.png, the first NNN from 001 that names no file.
std::string stillPath(const std::string& scenePath) {
    fs::path dir = scenePath.empty() ? fs::path(".") : fs::path(scenePath).parent_path();
    std::string stem = scenePath.empty() ? "default" : fs::path(scenePath).stem().string();
    for (int n = 1;; ++n) {
        fs::path p = dir / fmt::format("{}-still-{:03}.png", stem, n);
        std::error_code ec;
        if (!fs::exists(p, ec) && !ec) return p.lexically_normal().string();
        if (n > 99999) return {};
    }
}

} // namespace

bool evaluateViewFrame(const SceneProgram& program, const ViewAdjust& view, double time, int width,
                       int height, FrameValues& out, std::string& diags, const ParamSet* params) {
    std::vector<double> literals = program.literals;
    if (params) applyParams(program.parameters, *params, literals);
    view.write(literals, program.viewSlot, static_cast<int>(program.checked.layers.size()));
    FrameRequest req;
    req.time = time;
    req.width = width;
    req.height = height;
    req.maxSide = kMaxFrameSide;
    req.literals = &literals;
    return evaluateFrame(program, req, out, diags);
}

void toRgba8(const float* rgba, int channels, size_t pixels, uint8_t* out) {
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 4; ++c) out[i * 4 + c] = toByte(rgba[i * channels + c]);
}

FrameRenderer::FrameRenderer(int threads, std::function<void()> notify)
    : threads_(threads), notify_(std::move(notify)) {
    thread_ = std::thread([this] { run(); });
}

FrameRenderer::~FrameRenderer() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        newest_.store(UINT64_MAX); // abandons the frame in hand
    }
    wake_.notify_all();
    thread_.join();
}

void FrameRenderer::submit(RenderJob job) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        newest_.store(std::max(newest_.load(), job.version));
        pending_ = std::move(job);
    }
    wake_.notify_all();
}

void FrameRenderer::saveStill(RenderJob job, std::string scenePath) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        still_ = StillJob{std::move(job), std::move(scenePath)};
    }
    wake_.notify_all();
}

std::optional<RenderedFrame> FrameRenderer::takeFrame() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<RenderedFrame> f = std::move(done_);
    done_.reset();
    return f;
}

std::vector<std::string> FrameRenderer::takeMessages() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(messages_, {});
}

bool FrameRenderer::busy() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return inHand_ || pending_.has_value();
}

void FrameRenderer::run() {
    for (;;) {
        std::optional<RenderJob> job;
        std::optional<StillJob> still;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || pending_ || still_; });
            if (stop_) return;
            if (still_) {
                still = std::move(still_);
                still_.reset();
            } else {
                job = std::move(pending_);
                pending_.reset();
            }
            inHand_ = true;
        }
        if (still) renderStill(*still);
        if (job) renderJob(*job);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            inHand_ = false;
        }
        if (notify_) notify_();
    }
}

int FrameRenderer::previewDivisor(const RenderJob& job) const {
    const double estimate = msPerPixel_ * job.width * job.height;
    if (!job.interactive || estimate <= 50.0) return 1;
    // Coarse enough that the preview keeps up with the hand (about 30 ms), at most 1/8.
    int d = 2;
    while (d < 8 && estimate / (d * d) > 30.0) d *= 2;
    return d;
}

void FrameRenderer::renderJob(const RenderJob& job) {
    if (!job.build || job.width <= 0 || job.height <= 0) return;
    auto publish = [&](RenderedFrame&& f) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_ = std::move(f);
        }
        if (notify_) notify_();
    };
    try {
        if (int d = previewDivisor(job); d > 1) {
            RenderedFrame preview;
            render(job, d, false, preview, nullptr);
            publish(std::move(preview));
            // A newer job already waiting makes this one's full frame moot.
            if (newest_.load() > job.version) return;
        }
        RenderedFrame full;
        if (!render(job, 1, true, full, nullptr)) return;
        publish(std::move(full));
    } catch (const std::exception& e) {
        RenderedFrame failed;
        failed.version = job.version;
        failed.time = job.time;
        const bool memory = dynamic_cast<const std::bad_alloc*>(&e) != nullptr;
        failed.error = fmt::format(
            "moire: error: {}",
            memory ? fmt::format("out of memory drawing a {}x{} frame", job.width, job.height)
                   : std::string(e.what()));
        publish(std::move(failed));
    }
}

void FrameRenderer::renderStill(const StillJob& still) {
    std::string message;
    try {
        RenderedFrame frame;
        Image image;
        render(still.job, 1, false, frame, &image);
        if (!frame.error.empty()) {
            message = frame.error;
        } else {
            std::string path = stillPath(still.scenePath);
            if (path.empty()) throw IoError("no free still name beside the scene");
            writeImage(path, image);
            message = fmt::format("moire: saved {} ({}x{})", path, image.width, image.height);
        }
    } catch (const std::exception& e) {
        message = std::string("moire: error: cannot save a still: ") + e.what();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.push_back(message);
}

bool FrameRenderer::render(const RenderJob& job, int divisor, bool cancellable, RenderedFrame& out,
                           Image* full) {
    const auto t0 = Clock::now();
    out.version = job.version;
    out.time = job.time;
    out.fullWidth = job.width;
    out.fullHeight = job.height;
    out.divisor = divisor;
    const SceneProgram& program = *job.build->program;
    FrameValues frame;
    std::string diags;
    if (!evaluateViewFrame(program, job.view, job.time, job.width, job.height, frame, diags,
                           &job.params)) {
        out.error = diags;
        return true;
    }
    if (divisor > 1) {
        // The preview's own camera, whose pixels are blocks of the full frame's.
        Preview p = previewOf(SceneCamera::from(frame), job.view, job.width, job.height, divisor);
        if (!evaluateViewFrame(program, p.view, job.time, p.width, p.height, frame, diags,
                               &job.params)) {
            out.error = diags;
            return true;
        }
    }
    const CompiledKernel& kernel = *job.build->kernel;
    const bool same = divisor == 1 && !full && last_.kernel == &kernel &&
                      last_.width == frame.width && last_.height == frame.height &&
                      last_.uniforms == frame.uniforms;
    if (same) {
        out.width = frame.width;
        out.height = frame.height;
        out.rgba = last_.rgba;
        out.ms = last_.ms;
        out.reused = true;
        return true;
    }
    KernelFrame kf;
    kf.uniforms = frame.uniforms.data();
    kf.imageW = frame.width;
    kf.imageH = frame.height;
    ExecOptions exec;
    exec.threads = threads_;
    if (cancellable) exec.cancelled = [&] { return newest_.load() > job.version; };
    Image img = runKernel(kernel, kf, exec);
    if (img.width == 0) return false; // a newer job came in

    out.width = img.width;
    out.height = img.height;
    out.rgba.resize(static_cast<size_t>(img.width) * img.height * 4);
    toRgba8(img.pixels.data(), img.channels, static_cast<size_t>(img.width) * img.height,
            out.rgba.data());
    out.ms = msSince(t0);
    if (divisor == 1) {
        msPerPixel_ = out.ms / (static_cast<double>(img.width) * img.height);
        last_ = Last{&kernel, job.build, frame.uniforms, img.width, img.height, out.rgba, out.ms};
    }
    if (full) *full = std::move(img);
    return true;
}

} // namespace moire::view
