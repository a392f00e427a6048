#include "experiments/SceneRaster.h"

#include "compiler/backend/llvm/LlvmJit.h"
#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <cstdio>
#include <cstdlib>

namespace moire::exp {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& why) {
    std::fprintf(stderr, "moire: error: %s: %s\n", name.c_str(), why.c_str());
    std::exit(2);
}

} // namespace

SceneRaster::SceneRaster(const std::string& name, const std::string& text, bool floored) {
    // Point-sampled: the stroke floor's rule and explicit geometry are each judged against the
    // renderer's pixel at its centre (the mean filter, docs/filtering.md, is measured apart).
    CompileResult r = compileScene(
        name + ".moire", text,
        {.layerFields = true, .filter = sema::FilterMode::Point, .strokeFloor = floored});
    if (!r.program) {
        std::fprintf(stderr, "%s", r.diagnostics.c_str());
        std::exit(2);
    }
    program_ = std::move(r.program);
    if (program_->layout.numLayers != 2) fail(name, "the experiment needs exactly two layers");
    jit_ = std::make_unique<LlvmJitBackend>(LlvmJitBackend::Options{});
    kernel_ = jit_->compile(program_->kernel);
}

SceneRaster::~SceneRaster() = default;

double SceneRaster::pixelSize(int width, int height) const {
    FrameRequest request;
    request.width = width;
    request.height = height;
    FrameValues frame;
    std::string diagnostics;
    if (!evaluateFrame(*program_, request, frame, diagnostics)) fail("frame", diagnostics);
    return frame.pixelSize;
}

void SceneRaster::sample(int width, int height, int k, const Visit& visit) const {
    // The frame k times larger is the same frame (the scene's size fits it), each pixel
    // split into k x k; a band of k rows is one row of the image asked for.
    FrameRequest request;
    request.width = width * k;
    request.height = height * k;
    FrameValues frame;
    std::string diagnostics;
    if (!evaluateFrame(*program_, request, frame, diagnostics)) fail("frame", diagnostics);
    const KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
    const int n = kernel_->numOutputs();
    runKernelInBands(*kernel_, kf, {}, k,
                     [&](int band, int first, int count, const float* rows, size_t stride) {
                         if (first != 0 || count != k) fail("frame", "a band came in parts");
                         for (int x = 0; x < width; ++x)
                             visit(x, band, PixelSamples(rows, stride, n, k, x));
                     });
}

} // namespace moire::exp
