// The clip's clock without rendering: loop lengths against a brute-force search, frame
// times, and what a compiled scene says about its clock.
#include "compiler/lower/ClipClock.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numeric>
#include <random>

using namespace moire;

namespace {

TimingValues timing(const char* name, double period, double delay, TimingValues::Mode mode) {
    return TimingValues{name, period, delay, mode};
}

// The fewest frames at `fps` after which every cycle (num / den seconds, as the scene's
// author meant it) has closed a whole number of times, found by counting frames up.
int64_t framesUntilAllClose(const std::vector<Rational>& cycles, int64_t fps) {
    for (int64_t n = 1; n < 1'000'000; ++n) {
        bool all = true;
        for (Rational c : cycles) // n / fps seconds is a whole number of c = p / q seconds
            all = all && (n * c.den) % (fps * c.num) == 0;
        if (all) return n;
    }
    return -1;
}

clip::Length lengthOf(const std::vector<TimingValues>& timings, double fps, double t0 = 0.0) {
    clip::Motion m;
    m.timings = timings;
    m.moves = !timings.empty();
    return clip::defaultLength(m, t0, fps);
}

constexpr auto Loop = TimingValues::Loop;
constexpr auto PingPong = TimingValues::PingPong;
constexpr auto Once = TimingValues::Once;

} // namespace

TEST_CASE("the loop length is the least common multiple of the timings' cycles") {
    struct Case {
        std::vector<TimingValues> timings;
        std::vector<Rational> meant; // each timing's cycle as its author meant it
        int64_t fps;
        double seconds;
    };
    const Case cases[] = {
        {{timing("a", 1.5, 0, Loop), timing("b", 2.5, 0, Loop)}, {{3, 2}, {5, 2}}, 24, 7.5},
        {{timing("a", 0.3333, 0, Loop), timing("b", 0.5, 0, Loop)}, {{1, 3}, {1, 2}}, 24, 1.0},
        {{timing("a", 1.0 / 3.0, 0, Loop), timing("b", 0.25, 0, Loop)}, {{1, 3}, {1, 4}}, 36, 1.0},
        // Delays lengthen the cycle; pingpong goes there and back.
        {{timing("a", 2, 1, Loop), timing("b", 1.5, 0.5, PingPong)}, {{3, 1}, {7, 2}}, 10, 21.0},
        {{timing("a", 0.6667, 0, Loop), timing("b", 0.25, 0.5, PingPong)},
         {{2, 3}, {1, 1}},
         30,
         2.0},
        {{timing("a", 2.5, 0, PingPong)}, {{5, 1}}, 30, 5.0},
        {{timing("a", 1.2, 0.3, Loop), timing("b", 0.8, 0, Loop), timing("c", 0.9, 0, PingPong)},
         {{3, 2}, {4, 5}, {9, 5}},
         20,
         36.0},
    };
    for (const Case& c : cases) {
        CAPTURE(c.seconds);
        clip::Length len = lengthOf(c.timings, static_cast<double>(c.fps));
        REQUIRE(len.error.empty());
        CHECK(len.loop.value() == doctest::Approx(c.seconds).epsilon(1e-12));
        CHECK(len.frames == framesUntilAllClose(c.meant, c.fps));
        CHECK(len.seamless);
        CHECK_FALSE(len.still);
    }
}

TEST_CASE("a loop that is not a whole number of frames is rounded and says which fps would do") {
    clip::Length len = lengthOf({timing("a", 1.5, 0, Loop), timing("b", 2.5, 0, Loop)}, 25.0);
    CHECK(len.frames == 188); // 7.5 s x 25 = 187.5
    CHECK_FALSE(len.seamless);
    REQUIRE(len.notes.size() == 1);
    CHECK(len.notes[0].find("187.5 frames") != std::string::npos);
    CHECK(len.notes[0].find("at 24 or 26 fps it would") != std::string::npos);
}

TEST_CASE("once timings: the clip runs until they are at rest, and says it will not join") {
    // Alone: frames up to and including the first one at rest (t >= 1.7 at 24 fps: 1.7083).
    clip::Length once = lengthOf({timing("intro", 1.2, 0.5, Once)}, 24.0);
    CHECK(once.frames == 42);
    CHECK(clip::frameTime(0, once.frames - 1, 24.0) >= 1.7);
    CHECK(clip::frameTime(0, once.frames - 2, 24.0) < 1.7);
    CHECK_FALSE(once.seamless);
    // With a looper: whole loops (1 s = 24 frames) until the intro has come to rest.
    clip::Length both = lengthOf({timing("intro", 1.2, 0.5, Once), timing("a", 1, 0, Loop)}, 24.0);
    CHECK(both.frames == 48);
    CHECK_FALSE(both.seamless);
    CHECK(both.notes.back().find("will not join seamlessly") != std::string::npos);
    // Starting after it has come to rest, the loop is seamless again.
    clip::Length after =
        lengthOf({timing("intro", 1.2, 0.5, Once), timing("a", 1, 0, Loop)}, 24.0, 2.0);
    CHECK(after.frames == 24);
    CHECK(after.seamless);
    // And with nothing else moving, the scene is still from then on.
    CHECK(lengthOf({timing("intro", 1.2, 0.5, Once)}, 24.0, 3.0).still);
}

TEST_CASE("no motion, the clock alone, and cycles that close only after the cap") {
    clip::Motion still;
    clip::Length s = clip::defaultLength(still, 0, 30);
    CHECK(s.still);
    CHECK(s.frames == 1);
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0] == "the scene does not move: writing one frame");

    clip::Motion clock;
    clock.moves = clock.readsClock = true;
    CHECK(clip::defaultLength(clock, 0, 30).error.find("give --to or --frames") !=
          std::string::npos);

    clip::Length capped = lengthOf(
        {timing("a", 7, 0, Loop), timing("b", 11, 0, Loop), timing("c", 13, 0, Loop)}, 10.0);
    CHECK(capped.frames == static_cast<int64_t>(clip::kMaxLoopSeconds * 10));
    CHECK_FALSE(capped.seamless);
    CHECK(capped.notes[0].find("16 min 41 s") != std::string::npos); // 1001 s
}

TEST_CASE("a cycle read as a nearby fraction reports what that costs the join") {
    clip::Length len = lengthOf({timing("a", 0.3333, 0, Loop), timing("b", 0.5, 0, Loop)}, 24.0);
    // 1 s is 3.0003 cycles of 0.3333 s: 0.03% of a cycle off.
    REQUIRE(len.notes.size() == 2);
    CHECK(len.notes[1].find("timing 'a'") != std::string::npos);
    CHECK(len.notes[1].find("0.03%") != std::string::npos);
    // Exactly a third (as written with a division) costs nothing and says nothing.
    CHECK(lengthOf({timing("a", 1.0 / 3.0, 0, Loop)}, 24.0).notes.size() == 1);
}

TEST_CASE("frame times and --to") {
    CHECK(clip::frameTime(0.0, 30, 30.0) == 1.0);
    CHECK(clip::frameTime(0.5, 48, 24.0) == 2.5);
    CHECK(clip::frameTime(0.0, 3, 30.0) == 0.1);
    CHECK(clip::framesBefore(0, 2, 30) == 60);
    CHECK(clip::framesBefore(0.1, 0.3, 30) == 6); // (0.3 - 0.1) * 30 = 5.999999999999999
    CHECK(clip::framesBefore(0, 1.01, 30) == 31);
    CHECK(clip::framesBefore(2, 1, 30) == 0);
}

TEST_CASE("whether a scene moves, and whether it reads the clock itself") {
    auto still = test::compileOk("layer { family = circles; spacing = 4 }\n");
    CHECK_FALSE(clip::movesWithClock(*still));
    CHECK_FALSE(clip::readsClock(*still));
    auto clock = test::compileOk("layer { family = circles; spacing = 4 + t }\n");
    CHECK(clip::movesWithClock(*clock));
    CHECK(clip::readsClock(*clock));
    auto timed = test::compileOk("timing d { period = 2 }\n"
                                 "layer { family = circles; spacing = ramp(d, 4, 5) }\n");
    CHECK(clip::movesWithClock(*timed));
    CHECK_FALSE(clip::readsClock(*timed));
}
