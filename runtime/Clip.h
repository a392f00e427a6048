// A clip's schedule, as arithmetic with no rendering in it (spec §8.5): frame n is the frame
// at exactly t0 + n / fps, and a clip given no length runs for the least common multiple of
// the cycles of the timings the scene uses, so that its last frame leads back into its first.
//
// The cycles are decimals written in a scene (1.5, 0.3333, 10 / 7), so the multiple is taken
// over fractions: each period and delay is read as the nearest fraction whose denominator is
// at most kMaxDenominator (0.3333 and 1 / 3 both read as a third), and whatever that reading
// costs the join is measured afterwards against the cycles as written and reported.
#pragma once

#include "runtime/FrameEval.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace moire {
struct SceneProgram;
}

namespace moire::clip {

// A fraction num / den in lowest terms with den > 0.
struct Rational {
    int64_t num = 0, den = 1;
    double value() const { return static_cast<double>(num) / static_cast<double>(den); }
    bool operator==(const Rational&) const = default;
};

constexpr int64_t kMaxDenominator = 1000;
// The longest clip a length chosen from the timings may have: cycles such as 7, 11 and 13
// seconds only all close after 1001 s, which is no loop anyone wants rendered unasked.
constexpr double kMaxLoopSeconds = 600.0;

// The fraction nearest to `v` among those with a denominator at most `maxDen`, from the
// convergents and semiconvergents of v's continued fraction. Requires |v| < 2^53.
Rational approximate(double v, int64_t maxDen = kMaxDenominator);
// Exact sum and least common multiple (of positive fractions: the smallest value that is a
// whole multiple of both); nullopt when a numerator or denominator would overflow.
std::optional<Rational> add(Rational a, Rational b);
std::optional<Rational> lcm(Rational a, Rational b);

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

// The frames of a clip, first to last inclusive, numbered as in the whole clip.
struct FrameRange {
    int64_t first = 0, last = 0;
    int64_t count() const { return last - first + 1; }
};
// --frames: "N" (frames 0 to N - 1) or "A..B" (A to B inclusive). nullopt with `error` set
// when it is neither.
std::optional<FrameRange> parseFrames(const std::string& text, std::string& error);
// --to: the number of frames from t0 that start before t1 (t1 itself is where the next clip
// would begin). A product within a millionth of a whole number counts as that number, so
// that --to 2 at 30 fps gives 60 frames even when (t1 - t0) * fps comes out as 59.9999...
int64_t framesBefore(double t0, double t1, double fps);

// An output name with an optional printf-style frame number in its file name: %d, %4d,
// %04d (%% is a literal percent sign).
struct NamePattern {
    std::string before, after;
    bool numbered = false;
    int width = 0;
    bool zeroPad = false;
    std::string name(int64_t frame) const;
};
std::optional<NamePattern> parseNamePattern(const std::string& path, std::string& error);

// Seconds for a person: "7.5 s", "2 min 5 s".
std::string describeSeconds(double s);

} // namespace moire::clip
