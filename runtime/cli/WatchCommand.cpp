// `moire watch`: headless live coding. The file's directory is watched; every good save
// re-renders the image (replaced atomically, so an editor's image preview never reads half a
// file) and every bad save prints its diagnostics while the last good image stays.
#include "runtime/cli/Commands.h"
#include "runtime/cli/Shared.h"
#include "runtime/live/WatchSession.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/Render.h"

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <mutex>
#include <pthread.h>

namespace moire::cli {

namespace {

// One line per state of the file, so an editor integration can follow along.
void printReport(const WatchReport& r, const WatchArgs& args, const Backend& backend,
                 const std::string& output) {
    if (!r.good()) {
        fmt::print(stderr, "{}", r.diagnostics);
        // "kept" only what is there: before the first good render there is no image.
        std::error_code ec;
        if (!args.verbosity.quiet && std::filesystem::is_regular_file(output, ec))
            fmt::print(stderr, "moire: watch: kept {} (the last good render)\n", output);
        else if (!args.verbosity.quiet)
            fmt::print(stderr, "moire: watch: {} not written (no good render yet)\n", output);
    } else if (!args.verbosity.quiet) {
        fmt::print(stderr, "{}", r.notes);
        const BuildResult& b = r.result;
        std::string how = b.kind == BuildResult::Kind::Numbers
                              ? "numbers changed, kernel reused"
                              : fmt::format("kernel compiled in {:.0f} ms", b.kernelMs);
        if (args.verbosity.verbose)
            fmt::print(stderr, "moire: watch: read and checked the scene in {:.1f} ms\n",
                       b.frontEndMs);
        fmt::print(stderr, "moire: watch: wrote {} ({}x{}, {}, {}, rendered in {:.0f} ms)\n",
                   output, r.width, r.height, describe(backend), how, r.renderMs);
    }
    std::fflush(stderr);
}

int exitStatusOf(const WatchReport& r) {
    switch (r.failure) {
    case WatchReport::Failure::None:
        return kExitOk;
    case WatchReport::Failure::Scene:
        return kExitScene;
    case WatchReport::Failure::File:
        return kExitIo;
    case WatchReport::Failure::Machine:
        return kExitMachine;
    }
    return kExitInternal;
}

} // namespace

int watch(const WatchArgs& args) {
    if (args.scene == kStdinPath) {
        fmt::print(stderr, "moire: error: watch follows a scene file as it is saved; standard "
                           "input ('-') cannot be watched (use 'moire render -')\n");
        return kExitUsage;
    }
    if (!checkTime(args.time, "--time")) return kExitUsage;
    ImageOptions image;
    if (!checkImageOptions({args.scene, args.output, args.size, args.depth, args.backend,
                            args.device, kMaxFrameSide},
                           image))
        return kExitUsage;
    CompileOptions filter;
    if (!checkFilterOption(args.filter, filter)) return kExitUsage;
    const std::string& output = image.output;
    std::unique_ptr<Backend> backend = openBackend(args.backend, args.device);
    if (!backend) return kExitMachine;
    // The image's directory is created when missing, as render and clip do; temporaries
    // that a killed watch left there go.
    try {
        prepareOutputDirectory(output);
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    removeStaleTemporaries(output);

    WatchOptions options;
    options.scene = args.scene;
    options.output = output;
    options.request.time = args.time;
    options.request.width = image.width;
    options.request.height = image.height;
    options.request.maxSide = kMaxFrameSide;
    options.write.depth = image.depth;
    // Rewritten on every save: the fast level.
    options.write.compression = kPreviewCompression;
    options.write.threads = args.threads;
    options.exec.threads = args.threads;
    options.watch.debounce = std::chrono::milliseconds(args.debounceMs);
    options.defines = args.defines;
    options.filter = filter.filter;

    // SIGINT and SIGTERM are taken by sigwait below, on this thread only: block them before
    // the watch thread starts, so that it inherits the mask and a signal never lands on it in
    // the middle of writing an image.
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGINT);
    sigaddset(&stopSignals, SIGTERM);
    if (!args.once) pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);

    std::unique_ptr<WatchSession> session;
    try {
        session = std::make_unique<WatchSession>(*backend, options);
    } catch (const std::runtime_error& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    std::mutex printing;
    WatchReport first = session->processNow();
    printReport(first, args, *backend, output);
    if (args.once) return exitStatusOf(first);

    if (!args.verbosity.quiet) {
        fmt::print(stderr, "moire: watch: watching {} (Ctrl-C stops)\n", args.scene);
        std::fflush(stderr);
    }
    session->start([&](const WatchReport& r) {
        std::lock_guard<std::mutex> lock(printing);
        printReport(r, args, *backend, output);
    });
    int sig = 0;
    sigwait(&stopSignals, &sig);
    session->stop(); // finishes the state in hand: the image on disk is always whole
    pthread_sigmask(SIG_UNBLOCK, &stopSignals, nullptr);
    return kExitOk;
}

} // namespace moire::cli
