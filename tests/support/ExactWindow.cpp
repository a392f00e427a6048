#include "tests/support/ExactWindow.h"

#include "runtime/FrameEval.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <string>
#include <vector>

namespace moire::test {

Image downsampled(const SceneProgram& program, Backend& backend, int x0, int y0, int width,
                  int height, int k, int c0, int channels, double time) {
    FrameRequest req;
    req.time = time;
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(program, req, fv, diags));
    req.width = fv.width * k;
    req.height = fv.height * k;
    REQUIRE(evaluateFrame(program, req, fv, diags));
    auto kernel = backend.compile(program.kernel);
    const int n = kernel->numOutputs();
    std::vector<float> big(size_t(width) * k * height * k * n);
    KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    kernel->runTile(frame, TileRect{x0 * k, y0 * k, (x0 + width) * k, (y0 + height) * k},
                    big.data(), size_t(width) * k * n);
    Image out(width, height, channels);
    for (int y = 0; y < height * k; ++y)
        for (int x = 0; x < width * k; ++x)
            for (int c = 0; c < channels; ++c)
                out.pixels[(size_t(y / k) * width + x / k) * channels + c] +=
                    big[(size_t(y) * width * k + x) * n + c0 + c] / float(k * k);
    return out;
}

CompileOptions exactField(CompileOptions options) {
    options.filter = sema::FilterMode::Point;
    options.strokeFloor = false;
    return options;
}

InkAgainst inkAgainst(const Image& got, const Image& want) {
    double sq = 0.0, gotInk = 0.0, wantInk = 0.0, worst = 0.0;
    for (size_t i = 0; i < got.pixels.size(); ++i) {
        const double e = got.pixels[i] - want.pixels[i];
        sq += e * e;
        gotInk += 1 - got.pixels[i];
        wantInk += 1 - want.pixels[i];
        worst = std::max(worst, std::abs(e));
    }
    const double n = static_cast<double>(got.pixels.size());
    return {std::sqrt(sq / n), gotInk / n, wantInk / n, worst};
}

} // namespace moire::test
