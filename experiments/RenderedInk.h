// What the filter experiments share: the ink a scene draws (the scene compiled and rendered on
// a backend, each pixel's ink taken as 1 - red, black strokes on white paper, row by row), the
// box-filtered reference of an exact field it is judged against, and the zooms they sweep.
// A scene that does not compile or evaluate ends the program (status 2) with its diagnostics.
#pragma once

#include "runtime/output/Render.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace moire::exp {

// Samples a pixel of the reference, on a rank-1 lattice: sample j at ((j + 1/2) / 256,
// frac(j / phi + 1/2)), so that both the columns and the rows hold 256 distinct positions (a
// 16 x 16 grid would give upright lines only 16, and alias with them).
constexpr int kReferenceSamples = 256;

// Sample j's place in its pixel, each coordinate in [0, 1).
inline std::array<double, 2> referenceSample(int j) {
    double v = j * 0.6180339887498949 + 0.5;
    return {(j + 0.5) / kReferenceSamples, v - std::floor(v)};
}

// Each pixel's kReferenceSamples-sample mean of `inked(x, y)`, the exact field at a world
// point. The camera puts the world origin at the frame's middle, a pixel 1 / zoom world units,
// y up.
template <class Inked>
std::vector<double> boxReference(int width, int height, double zoom, Inked inked) {
    std::vector<double> out(size_t(width) * height);
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            int count = 0;
            for (int j = 0; j < kReferenceSamples; ++j) {
                const auto [u, v] = referenceSample(j);
                count += inked((px + u - 0.5 * width) / zoom, (0.5 * height - (py + v)) / zoom);
            }
            out[size_t(py) * width + px] = double(count) / kReferenceSamples;
        }
    return out;
}

// Two decades of zoom, 0.1 to 10 in steps of 10^(1/8); --quick: three of them.
inline std::vector<double> zoomSweep(bool quick) {
    if (quick) return {0.1, 0.5, 5.0};
    std::vector<double> zooms;
    for (int k = -8; k <= 8; ++k) zooms.push_back(std::pow(10.0, k / 8.0));
    return zooms;
}

inline double meanAbsError(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
    return sum / double(a.size());
}

inline std::vector<double> renderedInk(Backend& backend, const std::string& name,
                                       const std::string& text) {
    CompileResult compiled = compileScene(name, text);
    if (!compiled.program) {
        std::fprintf(stderr, "%s", compiled.diagnostics.c_str());
        std::exit(2);
    }
    FrameValues fv;
    std::string diags;
    if (!evaluateFrame(*compiled.program, FrameRequest{}, fv, diags)) {
        std::fprintf(stderr, "%s", diags.c_str());
        std::exit(2);
    }
    Image img = renderFrame(*compiled.program, backend, fv);
    std::vector<double> out(size_t(img.width) * img.height);
    for (int py = 0; py < img.height; ++py)
        for (int px = 0; px < img.width; ++px)
            out[size_t(py) * img.width + px] = 1.0 - img.at(px, py, 0);
    return out;
}

} // namespace moire::exp
