// The viewer's clock: scene time t, running with the wall clock or stopped. Kept apart from
// the window so that its arithmetic can be tested without one.
//
// While the clock runs, the window asks for frames at most 60 times a second, and only ten
// times a second when the picture does not move (only the status line's t changes), so the
// time on screen trails the running clock by up to a tenth of a second. Pausing stops the
// clock at the time of the last frame asked for, which is the one on screen (or arriving):
// the picture does not jump, and a step from the pause (`.`, one frame at 30 fps) moves the
// time on screen by exactly one step.
#pragma once

#include <chrono>
#include <optional>

namespace moire::view {

class ViewClock {
  public:
    using Clock = std::chrono::steady_clock;

    ViewClock(double t, bool playing, Clock::time_point now)
        : playing_(playing), base_(t), start_(now) {}

    bool playing() const { return playing_; }
    // t at wall-clock time `now`.
    double at(Clock::time_point now) const {
        if (!playing_) return base_;
        return base_ + std::chrono::duration<double>(now - start_).count();
    }
    // The clock restarts from where it is (the window opening after a slow compile).
    void restart(Clock::time_point now) { start_ = now; }
    // Jumps to `t`, running on from there if it runs.
    void set(double t, Clock::time_point now) {
        base_ = t;
        start_ = now;
        lastAsked_.reset(); // the frames asked for so far are of the old time
    }
    // Records the time of a frame asked for (the one that will be on screen next).
    void asked(double t) { lastAsked_ = t; }
    // Stops at the time of the last frame asked for, or at `now`'s time before any.
    void pause(Clock::time_point now) {
        if (!playing_) return;
        base_ = lastAsked_ ? *lastAsked_ : at(now);
        playing_ = false;
    }
    void play(Clock::time_point now) {
        if (playing_) return;
        start_ = now;
        playing_ = true;
    }
    // `.` and `,`: stops the clock if it runs, then moves it by `dt`.
    void step(double dt, Clock::time_point now) {
        pause(now);
        base_ += dt;
    }

  private:
    bool playing_;
    double base_;             // t when stopped, or at start_ while running
    Clock::time_point start_; // when base_ was t, while running
    std::optional<double> lastAsked_;
};

} // namespace moire::view
