// For the unit tests of the viewer's state (runtime/view/*_test.cpp): instants of the state's
// clock, and builds made as the viewer makes them.
#pragma once

#include "runtime/live/SceneBuilder.h"
#include "tests/support/Support.h"

#include <chrono>
#include <memory>
#include <string>

namespace moire::test {

// The instant `seconds` after the clock's epoch.
inline std::chrono::steady_clock::time_point at(double seconds) {
    using Clock = std::chrono::steady_clock;
    return Clock::time_point{} +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// A build of `text` as the viewer makes it (interactive slots); no kernel: the state never
// runs one.
inline std::shared_ptr<const LiveProgram> buildOf(const std::string& text) {
    auto live = std::make_shared<LiveProgram>();
    live->program = compileOk(text, {.mode = CompileOptions::Mode::Interactive});
    return live;
}

} // namespace moire::test
