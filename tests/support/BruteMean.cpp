#include "tests/support/BruteMean.h"

#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>

namespace moire::test {

std::vector<double> sumSweepShares(const SceneProgram& program, CompiledKernel& kernel,
                                   const std::vector<double>& literals, double t) {
    Image f = runWithLiterals(program, kernel, literals, 0, 0, t);
    const auto& L = program.layout;
    std::vector<double> out(static_cast<size_t>(f.width) * f.height);
    for (size_t px = 0; px < out.size(); ++px) {
        const float* o = &f.pixels[px * f.channels];
        const double x1 = o[L.gradXSlot(0)], y1 = o[L.gradYSlot(0)];
        const double x2 = o[L.gradXSlot(1)], y2 = o[L.gradYSlot(1)];
        const double q =
            2 * (x1 * x2 + y1 * y2) / std::max(x1 * x1 + y1 * y1 + x2 * x2 + y2 * y2, 1e-30);
        const double u = std::clamp((q - 0.1) / (-0.1 - 0.1), 0.0, 1.0);
        out[px] = std::isfinite(q) ? u * u * (3 - 2 * u) : 0.0;
    }
    return out;
}

void addFrameRGB(const SceneProgram& program, CompiledKernel& kernel,
                 const std::vector<double>& literals, std::vector<double>& sum, double t) {
    Image img = runWithLiterals(program, kernel, literals, 0, 0, t);
    const size_t pixels = static_cast<size_t>(img.width) * img.height;
    sum.resize(pixels * 3, 0.0);
    for (size_t px = 0; px < pixels; ++px)
        for (size_t c = 0; c < 3; ++c) sum[px * 3 + c] += img.pixels[px * img.channels + c];
}

std::vector<double> fadedMean(const std::vector<double> (&sums)[2],
                              const std::vector<double>& shares, double count) {
    std::vector<double> mean(sums[0].size());
    for (size_t k = 0; k < mean.size(); ++k) {
        const double share = shares.empty() ? 0.0 : shares[k / 3];
        mean[k] = ((1 - share) * sums[0][k] + (share > 0 ? share * sums[1][k] : 0.0)) / count;
    }
    return mean;
}

double zoomDifference(const std::string& scene, double width, double height,
                      const std::string& backend) {
    auto at = [&](double zoom) {
        auto p = compileOk(scene + fmt::format("camera {{ zoom = {} }}\n", zoom),
                           {.mode = CompileOptions::Mode::Probe,
                            .view = sema::ViewMode::Envelope,
                            .envelopeGain = 1.0});
        auto b = makeBackendOrSkip(backend);
        REQUIRE(b);
        auto kernel = b->compile(p->kernel);
        std::vector<double> out, lits = p->literals;
        for (int k = 0; k < 60; ++k) {
            lits[p->probeSlot] = -width / 2 + std::fmod(k * 0.6180339887 * width, width);
            lits[p->probeSlot + 1] = -height / 2 + std::fmod(k * 0.7548776662 * height, height);
            Image img = runWithLiterals(*p, *kernel, lits, 1, 1);
            for (int c = 0; c < 3; ++c) out.push_back(img.pixels[c]);
        }
        return out;
    };
    const std::vector<double> one = at(1.0), four = at(4.0);
    double worst = 0;
    for (size_t k = 0; k < one.size(); ++k) worst = std::max(worst, std::abs(one[k] - four[k]));
    return worst * 255.0;
}

double shareWithinOneStep(const Image& got, const std::vector<double>& want) {
    size_t ok = 0;
    double worst = 0;
    for (size_t k = 0; k < want.size(); ++k) {
        const double d = std::abs(got.pixels[k / 3 * got.channels + k % 3] - want[k]);
        worst = std::max(worst, d);
        ok += d <= 1.0 / 255.0;
    }
    MESSAGE("largest difference ", worst * 255.0, " colour steps");
    return static_cast<double>(ok) / static_cast<double>(want.size());
}

} // namespace moire::test
