// A scene's frame as the mean of k x k samples a pixel: the frame rendered k times larger on a
// compiled kernel and box-downsampled, streamed in bands of k rows so that the large frame is
// never held whole. The experiments that hold the mean filter against its print or against the
// exact field (tone_resolution, filter_random) read their frames this way.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"

#include <vector>

namespace moire::exp {

// Channels [c0, c0 + channels) of the straight RGBA of a width x height frame of `program`,
// each pixel the mean of its k x k samples, row by row, at `time` seconds. Exits with status 2
// where the frame's values cannot be evaluated.
std::vector<double> frameMeans(const SceneProgram& program, const CompiledKernel& kernel, int width,
                               int height, int k, int c0, int channels, double time = 0.0);

// The root mean square of a - b.
double rmse(const std::vector<double>& a, const std::vector<double>& b);

} // namespace moire::exp
