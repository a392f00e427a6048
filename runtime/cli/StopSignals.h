// SIGINT and SIGTERM while a command writes files (render, clip): the first asks the command
// to stop at the next safe point (between tiles of a render, after the frame in hand of a
// clip) so that it removes what it had started and exits with 128 + the signal; a second
// one stops the process at once (what it leaves, the next run removes: OutputFile.h).
// SIGPIPE is ignored meanwhile, so that ffmpeg dying shows up as a write error.
#pragma once

#include <csignal>

namespace moire::cli {

class StopSignals {
  public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

    // The signal received, or 0.
    static int received();

  private:
    struct sigaction old_[3];
};

} // namespace moire::cli
