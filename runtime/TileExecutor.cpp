#include "runtime/TileExecutor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

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

// Both CPU paths: `total` items taken in order by `threads` workers, each as
// item(index, worker) with worker in [0, threads). With a progress callback and more than one
// worker, the calling thread only reports progress (about ten times a second), woken as soon
// as the workers end (a plain sleep between reports added up to 100 ms to every frame);
// otherwise it is one of the workers. A cancel is heard between items (and inside one, where the
// item returns false); the first exception stops the others and is rethrown. False when cancelled.
bool runItems(int total, int threads, const ExecOptions& options,
              const std::function<bool(int, int)>& item) {
    std::atomic<int> next{0}, done{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    std::atomic<bool> failed{false}, cancelled{false};
    // The reporting thread's wake-up: workers that have left the loop, counted under the lock.
    std::mutex endMutex;
    std::condition_variable ended;
    int workersEnded = 0;
    auto worker = [&](int w) {
        struct Leave {
            std::mutex& m;
            std::condition_variable& cv;
            int& count;
            ~Leave() {
                {
                    std::lock_guard<std::mutex> lock(m);
                    ++count;
                }
                cv.notify_one();
            }
        } leave{endMutex, ended, workersEnded};
        try {
            for (int i; (i = next.fetch_add(1)) < total;) {
                if ((options.cancelled && options.cancelled()) || !item(i, w)) {
                    cancelled.store(true);
                    next.store(total);
                    return;
                }
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
        for (int i = 0; i < threads; ++i) pool.emplace_back(worker, i);
        std::unique_lock<std::mutex> lock(endMutex);
        while (!ended.wait_for(lock, std::chrono::milliseconds(100),
                               [&] { return workersEnded == threads; }))
            options.progress(static_cast<double>(done.load()) / total);
    } else {
        for (int i = 1; i < threads; ++i) pool.emplace_back(worker, i);
        worker(0);
    }
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    if (cancelled.load()) return false;
    if (options.progress) options.progress(1.0);
    return true;
}

int threadsFor(const ExecOptions& options, int items) {
    const int threads = options.threads > 0 ? options.threads
                                            : static_cast<int>(std::thread::hardware_concurrency());
    return std::max(1, std::min(threads, items));
}

} // namespace

namespace {

// A GPU kernel's bands (runKernelInBands): whole bands from the calling thread, several to a
// call of the device (each call costs a round trip) but no more than kGpuCallPixels pixels, so
// the buffer stays a few tens of megabytes however wide the frame.
constexpr int64_t kGpuCallPixels = int64_t{1} << 22;

bool runWholeFrameInBands(const CompiledKernel& kernel, const KernelFrame& frame,
                          const ExecOptions& options, int bandRows, const BandSink& sink,
                          BandTimes* times) {
    using Clock = std::chrono::steady_clock;
    const int n = kernel.numOutputs();
    const size_t stride = static_cast<size_t>(frame.imageW) * n;
    const int total = (frame.imageH + bandRows - 1) / bandRows;
    const int perCall = static_cast<int>(std::clamp<int64_t>(
        kGpuCallPixels / (int64_t{frame.imageW} * bandRows), 1, std::max(1, total)));
    std::vector<float> rows(static_cast<size_t>(perCall) * bandRows * stride);
    double kernelSeconds = 0, sinkSeconds = 0;
    for (int b0 = 0; b0 < total; b0 += perCall) {
        if (options.cancelled && options.cancelled()) return false;
        const int b1 = std::min(total, b0 + perCall);
        const int y0 = b0 * bandRows, y1 = std::min(frame.imageH, b1 * bandRows);
        const auto t0 = Clock::now();
        kernel.runTile(frame, TileRect{0, y0, frame.imageW, y1}, rows.data(), stride);
        const auto t1 = Clock::now();
        for (int b = b0; b < b1; ++b) {
            const int top = b * bandRows;
            sink(b, 0, std::min(frame.imageH, top + bandRows) - top,
                 rows.data() + static_cast<size_t>(top - y0) * stride, stride);
        }
        kernelSeconds += std::chrono::duration<double>(t1 - t0).count();
        sinkSeconds += std::chrono::duration<double>(Clock::now() - t1).count();
        if (options.progress) options.progress(static_cast<double>(y1) / frame.imageH);
    }
    if (times) {
        times->kernel += kernelSeconds;
        times->sink += sinkSeconds;
    }
    return true;
}

} // namespace

bool runKernelInBands(const CompiledKernel& kernel, const KernelFrame& frame,
                      const ExecOptions& options, int bandRows, const BandSink& sink,
                      BandTimes* times, int stepRows) {
    const int n = kernel.numOutputs();
    bandRows = std::max(1, bandRows);
    if (kernel.wholeFrame())
        return runWholeFrameInBands(kernel, frame, options, bandRows, sink, times);
    stepRows = stepRows > 0 ? std::min(stepRows, bandRows) : bandRows;
    const int total = (frame.imageH + bandRows - 1) / bandRows;
    const int ts = std::max(8, options.tileSize);
    const int threads = threadsFor(options, total);
    const size_t stride = static_cast<size_t>(frame.imageW) * n;
    std::vector<std::vector<float>> buffers(static_cast<size_t>(threads));
    std::mutex timesMutex;
    using Clock = std::chrono::steady_clock;
    // How far ahead a worker may go: band b starts only once every band above b - threads
    // has been handed over whole, so that a sink that keeps bands until those above them
    // come (ImageStream) holds at most 2 x threads of them, whatever a slow band does. The
    // band a waiting worker needs is in another worker's hands and that worker never waits
    // (every band above its own has started, and bands start in order), so they cannot
    // deadlock; a worker that stops (cancelled, failed) releases the others.
    std::mutex aheadMutex;
    std::condition_variable aheadMoved;
    std::vector<char> finished(static_cast<size_t>(total), 0);
    int finishedAbove = 0; // bands [0, finishedAbove) handed over whole
    bool stopped = false;
    auto stop = [&] {
        {
            std::lock_guard<std::mutex> lock(aheadMutex);
            stopped = true;
        }
        aheadMoved.notify_all();
    };
    // A cancel heard between bands (by runItems) releases the waiting workers too.
    ExecOptions itemOptions = options;
    if (options.cancelled)
        itemOptions.cancelled = [&] {
            if (!options.cancelled()) return false;
            stop();
            return true;
        };
    return runItems(total, threads, itemOptions, [&](int b, int w) {
        {
            std::unique_lock<std::mutex> lock(aheadMutex);
            aheadMoved.wait(lock, [&] { return stopped || finishedAbove >= b - threads; });
            if (stopped) return false;
        }
        std::vector<float>& rows = buffers[static_cast<size_t>(w)];
        rows.resize(static_cast<size_t>(stepRows) * stride);
        const int top = b * bandRows, bottom = std::min(frame.imageH, top + bandRows);
        double kernelSeconds = 0, sinkSeconds = 0;
        try {
            for (int y0 = top; y0 < bottom; y0 += stepRows) {
                const int y1 = std::min(bottom, y0 + stepRows);
                const auto t0 = Clock::now();
                for (int x0 = 0; x0 < frame.imageW; x0 += ts) {
                    if ((x0 > 0 || y0 > top) && options.cancelled && options.cancelled()) {
                        stop();
                        return false;
                    }
                    kernel.runTile(frame, TileRect{x0, y0, std::min(x0 + ts, frame.imageW), y1},
                                   rows.data() + static_cast<size_t>(x0) * n, stride);
                }
                const auto t1 = Clock::now();
                sink(b, y0 - top, y1 - y0, rows.data(), stride);
                kernelSeconds += std::chrono::duration<double>(t1 - t0).count();
                sinkSeconds += std::chrono::duration<double>(Clock::now() - t1).count();
            }
        } catch (...) {
            stop();
            throw;
        }
        {
            std::lock_guard<std::mutex> lock(aheadMutex);
            finished[static_cast<size_t>(b)] = 1;
            while (finishedAbove < total && finished[static_cast<size_t>(finishedAbove)])
                ++finishedAbove;
        }
        aheadMoved.notify_all();
        if (times) {
            std::lock_guard<std::mutex> lock(timesMutex);
            times->kernel += kernelSeconds;
            times->sink += sinkSeconds;
        }
        return true;
    });
}

Image runKernel(const CompiledKernel& kernel, const KernelFrame& frame,
                const ExecOptions& options) {
    const int n = kernel.numOutputs();
    // Every pixel is written by the kernel (Backend.h).
    Image img = Image::forOverwrite(frame.imageW, frame.imageH, n);
    // (`return ok ? img : Image()` would copy the frame: a conditional of an lvalue and a
    // prvalue is a prvalue, so no move.)
    if (kernel.wholeFrame()) {
        if (!runWholeFrame(kernel, frame, options, img)) return Image();
        return img;
    }
    const int ts = std::max(8, options.tileSize);
    const int tilesX = (frame.imageW + ts - 1) / ts;
    const int tilesY = (frame.imageH + ts - 1) / ts;
    const int total = tilesX * tilesY;
    const size_t rowStride = static_cast<size_t>(frame.imageW) * n;
    const bool finished = runItems(total, threadsFor(options, total), options, [&](int t, int) {
        TileRect r;
        r.x0 = (t % tilesX) * ts;
        r.y0 = (t / tilesX) * ts;
        r.x1 = std::min(r.x0 + ts, frame.imageW);
        r.y1 = std::min(r.y0 + ts, frame.imageH);
        kernel.runTile(frame, r, img.row(r.y0) + static_cast<size_t>(r.x0) * n, rowStride);
        return true;
    });
    if (!finished) return Image();
    return img;
}

} // namespace moire
