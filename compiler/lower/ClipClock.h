// A clip's schedule, as arithmetic with no rendering in it (spec §8.5): frame n is the frame
// at exactly t0 + n / fps, and a clip given no length runs for the least common multiple of
// the cycles of the timings the scene uses, so that its last frame leads back into its first.
//
// The cycles are decimals written in a scene (1.5, 0.3333, 10 / 7), so the multiple is taken
// over fractions: each period and delay is read as the nearest fraction whose denominator is
// at most kMaxDenominator (0.3333 and 1 / 3 both read as a third), and whatever that reading
// costs the join is measured afterwards against the cycles as written and reported.
//
// These are questions about the compiled program's clock (which timings it uses, whether it
// reads t itself), answered here so that every command asks them the same way.
#pragma once

#include "compiler/lower/Rational.h"

#include <cstdint>
#include <string>
#include <vector>

namespace moire {

struct SceneProgram;

// A timing the scene uses, as the frame program computes it (OutputLayout's timing settings:
// period, delay, mode).
struct TimingValues {
    enum Mode { Once = 0, Loop = 1, PingPong = 2 };
    std::string name;
    double period = 0.0, delay = 0.0;
    Mode mode = Loop;
    // The time after which it repeats: delay + period (loop) or delay + 2 period (pingpong);
    // for `once`, the time it comes to rest.
    double cycle() const { return delay + (mode == PingPong ? 2.0 : 1.0) * period; }
};

} // namespace moire

namespace moire::clip {

constexpr int64_t kMaxDenominator = 1000;
// The longest clip a length chosen from the timings may have: cycles such as 7, 11 and 13
// seconds only all close after 1001 s, which is no loop anyone wants rendered unasked.
constexpr double kMaxLoopSeconds = 600.0;

// The clock time of frame n: computed afresh from n, never accumulated from frame n - 1.
inline double frameTime(double t0, int64_t n, double fps) {
    return t0 + static_cast<double>(n) / fps;
}

// How a scene moves, as far as its length is concerned.
struct Motion {
    std::vector<TimingValues> timings; // every timing the scene uses
    bool readsClock = false;           // some expression uses the clock t itself
    bool moves = false;                // the frame depends on the clock at all
};
// Whether any expression of the scene reads the clock `t` directly (not through a timing).
bool readsClock(const SceneProgram& program);
// Whether the frame depends on the clock at all (the frame or pixel program reads it).
bool movesWithClock(const SceneProgram& program);

// The length of a clip that was given neither --to nor --frames.
//   Loop and pingpong timings: the least common multiple of their cycles (seamless).
//   Once timings still moving after t0: the clip runs on until every one has come to rest
//     (a whole number of loops when there are loopers too) and cannot join seamlessly.
//   No motion at all: one frame.
//   The clock read directly, with no timing to bound it: no length (`error` says so).
struct Length {
    int64_t frames = 1;
    Rational loop;                  // the loopers' common cycle in seconds (0 when there are none)
    bool seamless = false;          // frame `frames` shows the same picture as frame 0
    bool still = false;             // nothing moves: one frame
    std::vector<std::string> notes; // one line each, for the user
    std::string error;              // non-empty: no length can be chosen
};
Length defaultLength(const Motion& motion, double t0, double fps);

// --to: the number of frames from t0 that start before t1 (t1 itself is where the next clip
// would begin). A product within a millionth of a whole number counts as that number, so
// that --to 2 at 30 fps gives 60 frames even when (t1 - t0) * fps comes out as 59.9999...
int64_t framesBefore(double t0, double t1, double fps);

// Seconds for a person: "7.5 s", "2 min 5 s".
std::string describeSeconds(double s);

} // namespace moire::clip
