#include "runtime/view/LayerPicker.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"

#include <cmath>
#include <exception>
#include <utility>

namespace moire::view {

std::optional<int> pickLayer(const SceneProgram& probe, const Interpreter& kernel,
                             const PickRequest& request) {
    const RenderJob& p = request.picture;
    FrameValues fv;
    std::string diags;
    if (!evaluateViewFrame(probe, p.view, p.time, p.width, p.height, fv, diags, &p.params))
        return std::nullopt;
    const std::vector<double> out =
        kernel.atPixel(fv.uniforms, request.at.x, request.at.y, p.width, p.height);
    const double pixel = ViewCamera(SceneCamera::from(fv), p.view, p.width, p.height).pixelSize();
    const int n = static_cast<int>(probe.checked.layers.size());
    int best = -1;
    double bestDistance = request.tolerance;
    for (int i = n - 1; i >= 0; --i) {
        const double d = std::fabs(out[probe.layout.distanceSlot(i)]) / pixel;
        if (std::isfinite(d) && d < bestDistance) best = i, bestDistance = d;
    }
    return best;
}

LayerPicker::LayerPicker(std::function<void()> notify) : notify_(std::move(notify)) {
    thread_ = std::thread([this] { run(); });
}

LayerPicker::~LayerPicker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void LayerPicker::request(PickRequest request) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_ = std::move(request);
    }
    wake_.notify_all();
}

std::optional<PickResult> LayerPicker::take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (done_.empty()) return std::nullopt;
    PickResult r = std::move(done_.front());
    done_.erase(done_.begin());
    return r;
}

void LayerPicker::run() {
    for (;;) {
        PickRequest request;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || pending_; });
            if (stop_) return;
            request = std::move(*pending_);
            pending_.reset();
        }
        PickResult result = answer(request);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_.push_back(std::move(result));
        }
        if (notify_) notify_();
    }
}

PickResult LayerPicker::answer(const PickRequest& request) {
    PickResult result;
    result.id = request.id;
    result.build = request.picture.build;
    if (!result.build || request.picture.width <= 0 || request.picture.height <= 0) return result;
    // Nothing thrown here may end the thread: a pick that fails leaves the selection be.
    try {
        const std::shared_ptr<const SceneProgram>& program = result.build->program;
        if (probeOf_ != program) {
            probe_.reset();
            probeKernel_.reset();
            probeOf_ = program;
            const SourceFile& src = program->sources->file(program->userModule().file);
            CompileOptions o;
            o.layerFields = true;
            o.mode = CompileOptions::Mode::Interactive;
            CompileResult r = compileScene(src.path(), src.text(), o);
            if (!r.program) return result;
            probe_ = std::move(r.program);
            probeKernel_ = std::make_unique<Interpreter>(probe_->kernel);
        }
        if (!probe_) return result;
        if (std::optional<int> layer = pickLayer(*probe_, *probeKernel_, request)) {
            result.ok = true;
            result.layer = *layer;
        }
    } catch (const std::exception&) {
        result.ok = false;
    }
    return result;
}

} // namespace moire::view
