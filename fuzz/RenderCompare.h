// The render target's verdict on two renders of the same tiny image: the interpreter (double)
// against the JIT (single precision).
//
// Single precision legitimately moves an edge by a fraction of a pixel, which at 8 x 8 turns a
// few pixels from ink to paper; those must pass. A backend that draws another picture (a wrong
// op, a value that overflows float, a slipped uniform) changes most of the image; that must
// fail. And some scenes are ill-conditioned in single precision (a phase of 1e8 members, a
// camera at 1e7 with a tiny pixel): there any f32 render is noise, and no verdict is given.
// Whether a scene is such is measured on the interpreter itself: it renders again with its
// uniforms rounded to float, and once more nudged a few float ulps; if that alone changes the
// image, single precision cannot be held to it.
#pragma once

#include "compiler/backend/Backend.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace moire::fuzz {

// The pixels compared: two 8 x 8 windows of the frame at its own size, one at its centre
// (where most scenes put their pattern), one at its top-left corner (where the camera's maths
// is farthest from the centre). At the scene's own size a pattern is resolved; a whole frame
// shrunk to 8 x 8 would mostly show the `unresolved` colour and test nothing.
constexpr int kWindow = 8;
inline std::vector<float>
renderWindows(const CompiledKernel& k, const std::vector<double>& uniforms, int width, int height) {
    const size_t n = k.numOutputs();
    const int w = std::min(kWindow, width), h = std::min(kWindow, height);
    std::vector<float> out(2 * n * w * h);
    KernelFrame frame;
    frame.uniforms = uniforms.data();
    frame.imageW = width;
    frame.imageH = height;
    const int cx = (width - w) / 2, cy = (height - h) / 2;
    k.runTile(frame, TileRect{cx, cy, cx + w, cy + h}, out.data(), n * w);
    k.runTile(frame, TileRect{0, 0, w, h}, out.data() + n * w * h, n * w);
    return out;
}

// A sample is off when its colour differs by more than this (after clamping to [0, 1], as
// the image writers do), or when one of the two is NaN and the other is not.
constexpr double kOffBy = 0.1;
// More than this fraction of the samples off is another picture. An edge that float moves
// crosses a window's 8 pixels or so, under 5% of the samples (the examples stay there).
constexpr double kOffFraction = 0.15;
// The interpreter's own re-render with float-rounded uniforms must stay within this fraction
// for the scene to count as well-conditioned.
constexpr double kConditionedFraction = 0.05;

inline double offFraction(const std::vector<float>& a, const std::vector<float>& b, size_t channels,
                          size_t stride) {
    size_t off = 0, n = 0;
    for (size_t i = 0; i + stride <= a.size() && i + stride <= b.size(); i += stride)
        for (size_t c = 0; c < channels; ++c, ++n) {
            float x = a[i + c], y = b[i + c];
            if (std::isnan(x) || std::isnan(y)) {
                off += std::isnan(x) != std::isnan(y);
                continue;
            }
            off += std::abs(std::clamp(x, 0.0f, 1.0f) - std::clamp(y, 0.0f, 1.0f)) > kOffBy;
        }
    return n ? static_cast<double>(off) / n : 0.0;
}

// Uniforms as the JIT sees them (float), optionally nudged by `ulps` float ulps away from zero.
// Only the precision is float's: a finite value beyond float's range stays finite (the largest
// float) and a tiny one stays non-zero (the smallest), since a backend that overflows or
// flushes a value the interpreter holds draws another picture, which is a finding, not noise.
inline std::vector<double> floatUniforms(const std::vector<double>& u, int ulps) {
    constexpr float kMax = std::numeric_limits<float>::max();
    constexpr float kTiny = std::numeric_limits<float>::denorm_min();
    std::vector<double> out(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
        const double v = u[i];
        float f = static_cast<float>(std::clamp(v, -double(kMax), double(kMax)));
        if (std::isnan(v) || std::isinf(v)) f = static_cast<float>(v);
        if (v != 0.0 && f == 0.0f) f = v > 0 ? kTiny : -kTiny;
        for (int k = 0; k < ulps && std::abs(f) < kMax && f != 0.0f; ++k)
            f = std::nextafter(f, f > 0 ? INFINITY : -INFINITY);
        out[i] = f;
    }
    return out;
}

enum class Verdict { Agree, Differ, IllConditioned };

// `reference` and `jit` are the two renders; `rounded` and `nudged` the interpreter's renders
// with floatUniforms(u, 0) and floatUniforms(u, ulps). `channels` of every `stride` floats
// are compared (RGBA of the kernel's outputs). `overflows`: beyondFloat(u).
//
// A uniform beyond float's range is never excused: float cannot hold the value at all (a turn
// of 1e308deg, whose sine no precision draws), so the scene needs a limit or a clamp that every
// backend shares, and a JIT drawing another picture from it is a finding.
inline bool beyondFloat(const std::vector<double>& uniforms) {
    for (double v : uniforms)
        if (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max()) return true;
    return false;
}

inline Verdict judge(const std::vector<float>& reference, const std::vector<float>& jit,
                     const std::vector<float>& rounded, const std::vector<float>& nudged,
                     size_t channels, size_t stride, bool overflows = false) {
    if (offFraction(reference, jit, channels, stride) <= kOffFraction) return Verdict::Agree;
    if (overflows) return Verdict::Differ;
    if (offFraction(reference, rounded, channels, stride) > kConditionedFraction ||
        offFraction(reference, nudged, channels, stride) > kConditionedFraction)
        return Verdict::IllConditioned;
    return Verdict::Differ;
}

} // namespace moire::fuzz
