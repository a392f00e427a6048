#include "runtime/cli/StopSignals.h"

#include <unistd.h>

namespace moire::cli {

namespace {

volatile std::sig_atomic_t gSignal = 0;
constexpr int kStop[2] = {SIGINT, SIGTERM};

extern "C" void onStopSignal(int s) {
    if (gSignal != 0) _exit(128 + s); // the second: the user means it
    gSignal = s;
}

} // namespace

StopSignals::StopSignals() {
    gSignal = 0;
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART; // no EINTR inside the image encoders or the JIT
    for (int i = 0; i < 2; ++i) {
        sigaction(kStop[i], nullptr, &old_[i]);
        // A signal the parent chose to ignore (nohup, a background job) stays ignored.
        if (old_[i].sa_handler != SIG_IGN) sigaction(kStop[i], &sa, nullptr);
    }
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    sigaction(SIGPIPE, &ign, &old_[2]);
}

StopSignals::~StopSignals() {
    for (int i = 0; i < 2; ++i) sigaction(kStop[i], &old_[i], nullptr);
    sigaction(SIGPIPE, &old_[2], nullptr);
}

int StopSignals::received() {
    return gSignal;
}

} // namespace moire::cli
