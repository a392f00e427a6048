// `moire serve`: binds the page's server, prints its address (the first line on standard
// output, so that an editor can read it), and serves until Ctrl-C.
#include "runtime/cli/ServeCommand.h"

#include "runtime/cli/Shared.h"
#include "runtime/FrameEval.h"
#include "runtime/serve/Server.h"
#include "runtime/serve/Session.h"
#include "runtime/serve/Token.h"

#include <csignal>
#include <cstdio>
#include <fmt/format.h>
#include <pthread.h>

namespace moire::cli {

namespace {

bool isLoopback(const std::string& host) {
    return host == "127.0.0.1" || host == "localhost" || host == "::1";
}

} // namespace

int serve(const ServeArgs& args) {
    if (args.scene == kStdinPath) {
        fmt::print(stderr, "moire: error: serve follows a scene file as it is saved; standard "
                           "input ('-') cannot be watched\n");
        return kExitUsage;
    }
    if (!checkTime(args.time, "--time")) return kExitUsage;
    int w = 0, h = 0;
    if (!args.size.empty() && !parseSize(args.size, w, h, kMaxFrameSide)) {
        fmt::print(stderr, "moire: error: --size must be WIDTHxHEIGHT (1 to {}), not '{}'\n",
                   kMaxFrameSide, args.size);
        return kExitUsage;
    }
    if (args.port < 0 || args.port > 65535) {
        fmt::print(stderr, "moire: error: --port must be 0 (any free port) to 65535, not {}\n",
                   args.port);
        return kExitUsage;
    }
    if (!checkBackendArgs(args.backend, args.device)) return kExitUsage;
    serve::SessionOptions options;
    if (!checkFilterOption(args.filter, options.compile)) return kExitUsage;
    // SIGINT and SIGTERM are taken by sigwait below: blocked before any thread starts (the
    // backend's among them), so that every thread inherits the mask and none is stopped
    // halfway through a frame.
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGINT);
    sigaddset(&stopSignals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);
    std::unique_ptr<Backend> backend = openBackend(args.backend, args.device);
    if (!backend) return kExitMachine;
    if (args.hostGiven && !isLoopback(args.host))
        fmt::print(stderr,
                   "moire: warning: serving on {}: anyone who can reach this address and learns "
                   "the URL's token can see the scene and change its view\n",
                   args.host);

    options.scene = args.scene;
    options.compile.defines = args.defines;
    options.width = w;
    options.height = h;
    options.time = args.time;
    options.paused = args.paused;
    options.threads = args.threads;
    options.watch.debounce = std::chrono::milliseconds(args.debounceMs);
    options.backend = describe(*backend);
    // Each save, one line (or its diagnostics), as `moire watch` prints them.
    options.onReload = [&args](const BuildResult& b) {
        if (!b.good())
            fmt::print(stderr, "{}", b.diagnostics);
        else if (!args.verbosity.quiet)
            fmt::print(stderr, "moire: serve: reloaded {} ({})\n", args.scene,
                       b.kind == BuildResult::Kind::Numbers
                           ? "numbers changed, kernel reused"
                           : fmt::format("kernel compiled in {:.0f} ms", b.kernelMs));
        std::fflush(stderr);
    };

    std::unique_ptr<serve::Session> session;
    try {
        session = std::make_unique<serve::Session>(*backend, options);
    } catch (const std::runtime_error& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    serve::Server server(*session, serve::makeToken());
    int port = 0;
    try {
        port = server.bind(args.host, args.port);
    } catch (const std::runtime_error& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    BuildResult first = session->start();
    if (!first.good()) {
        fmt::print(stderr, "{}", first.diagnostics);
        // A scene with errors is served (the page shows them until a save fixes them), but a
        // wrong -D no save can fix: that is the command line's, as for render.
        if (first.diagnostics.rfind("<command line>:", 0) == 0 ||
            first.diagnostics.find("\n<command line>:") != std::string::npos) {
            session->stop();
            return kExitUsage;
        }
    }
    fmt::print("{}\n", server.url(args.host, port));
    std::fflush(stdout);
    server.start();
    if (!args.verbosity.quiet) {
        fmt::print(stderr, "moire: serve: {} on {} with {} (Ctrl-C stops)\n", args.scene,
                   server.url(args.host, port), describe(*backend));
        std::fflush(stderr);
    }
    int sig = 0;
    sigwait(&stopSignals, &sig);
    server.stop();
    session->stop();
    // The signals stay blocked: a second one on its way (timeout(1) signals the process and
    // then its group) would otherwise end the process, status 143, after a clean stop.
    return kExitOk;
}

} // namespace moire::cli
