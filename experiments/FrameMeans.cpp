#include "experiments/FrameMeans.h"

#include "runtime/FrameEval.h"
#include "runtime/TileExecutor.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace moire::exp {

namespace {
[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "error: %s\n", what.c_str());
    std::exit(2);
}
} // namespace

std::vector<double> frameMeans(const SceneProgram& program, const CompiledKernel& kernel, int width,
                               int height, int k, int c0, int channels, double time) {
    FrameRequest request;
    request.time = time;
    request.width = width * k;
    request.height = height * k;
    FrameValues frame;
    std::string diagnostics;
    if (!evaluateFrame(program, request, frame, diagnostics)) fail(diagnostics);
    const KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
    const int n = kernel.numOutputs();
    std::vector<double> out(size_t(width) * height * channels, 0.0);
    runKernelInBands(kernel, kf, {}, k,
                     [&](int band, int first, int count, const float* rows, size_t stride) {
                         if (first != 0 || count != k) fail("a band came in parts");
                         double* row = out.data() + size_t(band) * width * channels;
                         for (int j = 0; j < k; ++j)
                             for (int x = 0; x < width * k; ++x)
                                 for (int c = 0; c < channels; ++c)
                                     row[size_t(x / k) * channels + c] +=
                                         rows[size_t(j) * stride + size_t(x) * n + c0 + c];
                         for (size_t i = 0; i < size_t(width) * channels; ++i) row[i] /= k * k;
                     });
    return out;
}

double rmse(const std::vector<double>& a, const std::vector<double>& b) {
    double sq = 0;
    for (size_t i = 0; i < a.size(); ++i) sq += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(sq / double(a.size()));
}

} // namespace moire::exp
