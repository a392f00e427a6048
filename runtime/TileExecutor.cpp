#include "runtime/TileExecutor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>

namespace moire {

namespace {

// A GPU kernel takes the frame whole, from this thread: it splits it to its device's limits
// and keeps its own pipeline of chunks busy. Without a progress or cancel callback that is one
// call; with one, sixteen horizontal bands, so the progress line moves and a cancel is heard
// (a band boundary costs one round trip to the device, nothing next to the band). False when
// cancelled.
bool runWholeFrame(const CompiledKernel& kernel, const KernelFrame& frame,
                   const ExecOptions& options, Image& img) {
    const size_t rowStride = static_cast<size_t>(frame.imageW) * img.channels;
    const int bands = options.progress || options.cancelled ? std::min(frame.imageH, 16) : 1;
    for (int b = 0; b < bands; ++b) {
        if (options.cancelled && options.cancelled()) return false;
        const int y0 = static_cast<int>(static_cast<int64_t>(frame.imageH) * b / bands);
        const int y1 = static_cast<int>(static_cast<int64_t>(frame.imageH) * (b + 1) / bands);
        if (y1 > y0)
            kernel.runTile(frame, TileRect{0, y0, frame.imageW, y1}, img.row(y0), rowStride);
        if (options.progress) options.progress(static_cast<double>(y1) / frame.imageH);
    }
    return true;
}

} // namespace

Image runKernel(const CompiledKernel& kernel, const KernelFrame& frame,
                const ExecOptions& options) {
    const int n = kernel.numOutputs();
    // Every pixel is written by the kernel (Backend.h).
    Image img = Image::forOverwrite(frame.imageW, frame.imageH, n);
    if (kernel.wholeFrame()) return runWholeFrame(kernel, frame, options, img) ? img : Image();
    const int ts = std::max(8, options.tileSize);
    const int tilesX = (frame.imageW + ts - 1) / ts;
    const int tilesY = (frame.imageH + ts - 1) / ts;
    const int total = tilesX * tilesY;
    int threads = options.threads > 0 ? options.threads
                                      : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::max(1, std::min(threads, total));

    std::atomic<int> next{0};
    std::atomic<int> done{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    std::atomic<bool> failed{false}, cancelled{false};
    const size_t rowStride = static_cast<size_t>(frame.imageW) * n;

    auto worker = [&] {
        try {
            for (int t; (t = next.fetch_add(1)) < total;) {
                if (options.cancelled && options.cancelled()) {
                    cancelled.store(true);
                    next.store(total);
                    return;
                }
                TileRect r;
                r.x0 = (t % tilesX) * ts;
                r.y0 = (t / tilesX) * ts;
                r.x1 = std::min(r.x0 + ts, frame.imageW);
                r.y1 = std::min(r.y0 + ts, frame.imageH);
                float* out = img.row(r.y0) + static_cast<size_t>(r.x0) * n;
                kernel.runTile(frame, r, out, rowStride);
                done.fetch_add(1);
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(failureMutex);
            if (!failure) failure = std::current_exception();
            failed.store(true);
            next.store(total);
        }
    };

    std::vector<std::thread> pool;
    if (options.progress && threads > 1) {
        // The calling thread only reports progress; `threads` workers take the tiles.
        for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
        while (done.load() < total && !failed.load() && !cancelled.load()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            options.progress(static_cast<double>(done.load()) / total);
        }
    } else {
        for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
        worker();
    }
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    if (cancelled.load()) return Image();
    if (options.progress) options.progress(1.0);
    return img;
}

} // namespace moire
