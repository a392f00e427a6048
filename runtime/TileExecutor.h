// The executor: runs a compiled kernel over an image, in square tiles on every core for a CPU
// kernel, or in a few whole-width bands from the calling thread for a GPU kernel
// (CompiledKernel::wholeFrame).
#pragma once

#include "compiler/backend/Backend.h"
#include "runtime/Image.h"

#include <functional>

namespace moire {

struct ExecOptions {
    int threads = 0;   // 0: one per hardware thread (CPU kernels)
    int tileSize = 64; // CPU kernels
    // Called from the calling thread with the fraction done: about ten times a second for a
    // CPU kernel, after each of sixteen bands for a GPU kernel; 1.0 at the end.
    std::function<void(double)> progress;
    // Asked between tiles (between bands for a GPU kernel), from any worker thread: once it
    // says true the frame is abandoned and runKernel returns an empty image (width 0). The
    // viewer drops a frame this way when a newer one is wanted.
    std::function<bool()> cancelled;
};

// Evaluates `kernel` at every pixel of a width x height image.
Image runKernel(const CompiledKernel& kernel, const KernelFrame& frame,
                const ExecOptions& options = {});

// Thread time spent in runKernelInBands, summed over its threads, in seconds.
struct BandTimes {
    double kernel = 0.0; // running the kernel's tiles
    double sink = 0.0;   // in the sink
};

// Called with `count` rows of band `band` from its row `first` (the frame's row
// band * bandRows + first; numOutputs() floats a pixel, `stride` floats from one row to the
// next), on the thread that renders the band: a band's rows come in order, and the call with
// its last rows ends it.
using BandSink =
    std::function<void(int band, int first, int count, const float* rows, size_t stride)>;

// Evaluates `kernel` in whole-width bands of `bandRows` rows, handing each to `sink` as soon
// as it is done, and no image of the whole frame is ever made. A CPU kernel: each worker takes
// the next band in order and renders it `stepRows` rows at a time (0: the whole band at once),
// tile by tile into a buffer of its own, so rows are encoded while they are still in the
// cache: memory holds one step a thread; a worker waits before a band more than `threads`
// bands below the first unfinished one, so a sink that keeps bands until those above them
// come holds a few. A GPU kernel (wholeFrame()): a few bands to a device call from the
// calling thread (a buffer of about 4 Mpx), handed over whole and in order. Bands are handed
// over once each, in any order. Progress and cancellation as for runKernel (progress in
// bands); returns false when cancelled. An exception from the kernel or the sink stops the
// other workers and is rethrown. `times`, when given, receives where the threads' time went.
bool runKernelInBands(const CompiledKernel& kernel, const KernelFrame& frame,
                      const ExecOptions& options, int bandRows, const BandSink& sink,
                      BandTimes* times = nullptr, int stepRows = 0);

} // namespace moire
