// The pieces of a brute-force envelope, shared by the tests that hold the envelope view to
// the pattern re-rendered at many index advances (tests/envelope_test.cpp,
// tests/sweeps_test.cpp): the per-pixel choice of sweeping the second layer backwards, and
// the RGB of many frames summed.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/Image.h"

#include <vector>

namespace moire::test {

// Per pixel, the share of the sweep that runs the second layer backwards: where the first two
// layers' index gradients point against each other (g1 . g2 < 0) their sum beat is the slower
// (Eq. 11), and the hand-over between the two sweeps is a fade over
// q = 2 g1.g2 / (|g1|^2 + |g2|^2) in [-0.1, 0.1] (smoothstep; the envelope's kSumFade, written
// out again here as the oracle's own). Read from `program` compiled with its layer fields and
// drawn with `literals` at time `t`.
std::vector<double> sumSweepShares(const SceneProgram& program, CompiledKernel& kernel,
                                   const std::vector<double>& literals, double t = 0.0);

// Adds the RGB of the frame drawn with `literals` at time `t` to `sum` (pixels x 3, sized on
// first use).
void addFrameRGB(const SceneProgram& program, CompiledKernel& kernel,
                 const std::vector<double>& literals, std::vector<double>& sum, double t = 0.0);

// The per-pixel mean: sums[0] and sums[1] (each over `count` taps) mixed by the pixel's share
// of the backwards sweep (`shares`; empty: none anywhere).
std::vector<double> fadedMean(const std::vector<double> (&sums)[2],
                              const std::vector<double>& shares, double count);

// The largest difference, in colour steps, between the envelope (gain 1) of `scene` at zoom 1
// and at zoom 4, at 60 world points spread over a width x height window about the origin (a
// fixed low-discrepancy walk), probed on `backend`.
double zoomDifference(const std::string& scene, double width, double height,
                      const std::string& backend);

// The share of the RGB samples of `got` within one colour step (1/255) of `want` (pixels x
// 3); reports the largest difference, in colour steps.
double shareWithinOneStep(const Image& got, const std::vector<double>& want);

} // namespace moire::test
