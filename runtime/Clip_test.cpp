// The clip's schedule without rendering: fractions, loop lengths against a brute-force search,
// frame ranges, output names, and what a compiled scene says about its clock.
#include "runtime/Clip.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numeric>
#include <random>

using namespace moire;
using clip::Rational;

namespace {

// The nearest fraction with a denominator up to maxDen by trying every denominator; ties go
// to the smaller denominator. Independent of the continued fraction in approximate().
Rational nearestByScan(double v, int64_t maxDen) {
    Rational best{0, 1};
    long double bestErr = INFINITY;
    for (int64_t q = 1; q <= maxDen; ++q) {
        int64_t p = std::llround(v * static_cast<double>(q));
        long double err = std::fabs(static_cast<long double>(v) - static_cast<long double>(p) / q);
        if (err < bestErr) {
            bestErr = err;
            int64_t g = std::gcd(p, q);
            best = {p / g, q / g};
        }
    }
    return best;
}

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

TEST_CASE("decimals are read as the nearest fraction with a denominator up to 1000") {
    CHECK(clip::approximate(1.5) == Rational{3, 2});
    CHECK(clip::approximate(2.5) == Rational{5, 2});
    CHECK(clip::approximate(0.1) == Rational{1, 10});
    CHECK(clip::approximate(0.3333) == Rational{1, 3});
    CHECK(clip::approximate(1.0 / 3.0) == Rational{1, 3});
    CHECK(clip::approximate(0.6667) == Rational{2, 3});
    CHECK(clip::approximate(0.333) == Rational{333, 1000}); // exactly representable: kept
    CHECK(clip::approximate(10.0 / 7.0) == Rational{10, 7});
    CHECK(clip::approximate(-2.25) == Rational{-9, 4});
    CHECK(clip::approximate(0.0) == Rational{0, 1});
    CHECK(clip::approximate(6.0) == Rational{6, 1});
    CHECK(clip::approximate(30000.0 / 1001.0, 1001) == Rational{30000, 1001});

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> dist(0.0, 20.0);
    for (int i = 0; i < 200; ++i) {
        double v = dist(rng);
        CAPTURE(v);
        for (int64_t maxDen : {7, 100, 1000}) {
            CAPTURE(maxDen);
            CHECK(clip::approximate(v, maxDen) == nearestByScan(v, maxDen));
        }
    }
}

TEST_CASE("exact sums and least common multiples of fractions") {
    CHECK(clip::add({1, 3}, {1, 6}) == Rational{1, 2});
    CHECK(clip::lcm({3, 2}, {5, 2}) == Rational{15, 2});
    CHECK(clip::lcm({1, 3}, {3, 2}) == Rational{3, 1});
    CHECK(clip::lcm({4, 3}, {1, 1}) == Rational{4, 1});
    CHECK_FALSE(clip::lcm({0, 1}, {1, 1}).has_value());
    CHECK_FALSE(clip::lcm({INT64_MAX - 1, 1}, {INT64_MAX - 2, 1}).has_value()); // overflow
    // Against the smallest k for which k a is a whole multiple of b, found by counting.
    for (int64_t an = 1; an <= 9; ++an)
        for (int64_t ad = 1; ad <= 6; ++ad)
            for (int64_t bn = 1; bn <= 9; ++bn)
                for (int64_t bd = 1; bd <= 6; ++bd) {
                    Rational a = clip::approximate(static_cast<double>(an) / ad);
                    Rational b = clip::approximate(static_cast<double>(bn) / bd);
                    int64_t k = 1;
                    while ((k * a.num * b.den) % (a.den * b.num) != 0) ++k;
                    int64_t g = std::gcd(k * a.num, a.den);
                    INFO(an, "/", ad, " and ", bn, "/", bd);
                    CHECK(clip::lcm(a, b) == Rational{k * a.num / g, a.den / g});
                }
}

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

TEST_CASE("frame times, --to and --frames") {
    CHECK(clip::frameTime(0.0, 30, 30.0) == 1.0);
    CHECK(clip::frameTime(0.5, 48, 24.0) == 2.5);
    CHECK(clip::frameTime(0.0, 3, 30.0) == 0.1);
    CHECK(clip::framesBefore(0, 2, 30) == 60);
    CHECK(clip::framesBefore(0.1, 0.3, 30) == 6); // (0.3 - 0.1) * 30 = 5.999999999999999
    CHECK(clip::framesBefore(0, 1.01, 30) == 31);
    CHECK(clip::framesBefore(2, 1, 30) == 0);

    std::string why;
    auto r = clip::parseFrames("10", why);
    REQUIRE(r);
    CHECK((r->first == 0 && r->last == 9));
    r = clip::parseFrames("5..7", why);
    REQUIRE(r);
    CHECK((r->first == 5 && r->last == 7 && r->count() == 3));
    for (const char* bad : {"0", "7..5", "a", "3..", "..4", "-1..2", "1.5", "2..3..4", "",
                            "0..9223372036854775807"}) {
        CAPTURE(bad);
        CHECK_FALSE(clip::parseFrames(bad, why));
        CHECK(why.find("--frames") != std::string::npos);
    }
}

TEST_CASE("output names: a printf-style frame number in the file name") {
    std::string why;
    auto p = clip::parseNamePattern("out/frame_%04d.png", why);
    REQUIRE(p);
    CHECK(p->name(7) == "out/frame_0007.png");
    CHECK(p->name(12345) == "out/frame_12345.png");
    p = clip::parseNamePattern("f%d.exr", why);
    REQUIRE(p);
    CHECK(p->name(42) == "f42.exr");
    p = clip::parseNamePattern("f%3d.png", why);
    REQUIRE(p);
    CHECK(p->name(5) == "f  5.png");
    p = clip::parseNamePattern("100%%/at_%%_%02d.png", why);
    REQUIRE(p);
    CHECK(p->name(3) == "100%%/at_%_03.png"); // the directory is taken as written
    p = clip::parseNamePattern("still.png", why);
    REQUIRE(p);
    CHECK_FALSE(p->numbered);
    CHECK(p->name(9) == "still.png");
    for (const char* bad : {"f_%s.png", "f_%d_%d.png", "f_%.png", "f_%x.png", "f_%-4d.png"}) {
        CAPTURE(bad);
        CHECK_FALSE(clip::parseNamePattern(bad, why));
    }
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
