// A window of a scene drawn under the mean filter against the same window of its exact field,
// which the mean-filter tests share (tests/filter_test.cpp, tests/crowded_strokes_test.cpp):
// the window box-downsampled from the frame drawn k times larger, the exact field's options,
// and one channel of ink compared.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/Image.h"

namespace moire::test {

// A window (x0, y0, width, height) of the frame drawn k times larger (each pixel k x k
// pixels), box-downsampled back: the kernel's outputs [c0, c0 + channels) of its straight RGBA,
// at `time`.
Image downsampled(const SceneProgram& program, Backend& backend, int x0, int y0, int width,
                  int height, int k, int c0, int channels, double time = 0.0);

// The exact field: each stroke as written (no floor), point-sampled; `options` as drawn.
CompileOptions exactField(CompileOptions options);

// One channel of ink drawn (`got`, 1 - red on white) against the exact field's (`want`): the
// RMSE a pixel, each one's mean ink and the worst pixel's difference.
struct InkAgainst {
    double rmse, ink, exact, worst;
};
InkAgainst inkAgainst(const Image& got, const Image& want);

} // namespace moire::test
