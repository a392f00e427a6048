// The viewer's clock, with the wall clock given: pausing stops at the frame on screen, and a
// step from there moves the time on screen by exactly one step.
#include "runtime/view/ViewClock.h"

#include <doctest/doctest.h>

using moire::view::ViewClock;

namespace {

ViewClock::Clock::time_point at(double seconds) {
    return ViewClock::Clock::time_point{} + std::chrono::duration_cast<ViewClock::Clock::duration>(
                                                std::chrono::duration<double>(seconds));
}

} // namespace

TEST_CASE("view clock: runs with the wall clock, stops and steps") {
    ViewClock clock(2.0, true, at(100));
    CHECK(clock.at(at(100.5)) == doctest::Approx(2.5));
    clock.set(10.0, at(101));
    CHECK(clock.at(at(102)) == doctest::Approx(11.0));
    clock.pause(at(103)); // no frame asked for since the jump: the clock's own time
    CHECK(!clock.playing());
    CHECK(clock.at(at(200)) == doctest::Approx(12.0));
    clock.play(at(300));
    CHECK(clock.at(at(300.25)) == doctest::Approx(12.25));
    clock.step(-1.0 / 30.0, at(301)); // a step while playing pauses first
    CHECK(clock.at(at(400)) == doctest::Approx(13.0 - 1.0 / 30.0));
}

TEST_CASE("view clock: the first step after pausing moves the shown time by one step") {
    // A still scene while the clock plays: frames are asked for ten times a second, so the
    // time on screen trails the clock by up to 0.1 s.
    const double step = 1.0 / 30.0;
    ViewClock clock(0.0, true, at(0));
    double shown = 0.0;
    for (double wall = 0.0; wall < 0.45; wall += 0.1) {
        shown = clock.at(at(wall));
        clock.asked(shown);
    }
    REQUIRE(shown == doctest::Approx(0.4));
    // Space 90 ms after the last frame: the clock stops at the frame on screen...
    clock.pause(at(0.49));
    CHECK(clock.at(at(0.5)) == doctest::Approx(shown));
    // ...and `.` moves the time on screen by exactly 1/30 s (it moved 0.123 s when the pause
    // took the running clock's time).
    clock.step(step, at(0.6));
    CHECK(clock.at(at(0.7)) - shown == doctest::Approx(step).epsilon(1e-12));
}
