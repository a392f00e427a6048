// Every stdlib phase family against an independent reference (tests/support/NearestMember):
// at seeded random points, for several settings of each family (phase offsets, origins and
// rotations included), the renderer's index must be Table 1's phase, and its distance (Eq. 5,
// residual over the AD gradient) must be the true Euclidean distance to the nearest member,
// found by a numeric search that never sees a gradient:
//  - exactly, for lines and circles everywhere and for the polygons on their flat sides;
//  - within the geometric bound cos(pi / N) past a polygon's corners;
//  - for the curved families (wave, parabola, hyperbola, spiral), within the exact envelope
//    of a first-order approximation at every point, and within measured tolerances in the
//    band that is inked (distance up to a quarter spacing).
// docs/families.md tabulates the measured errors; MOIRE_FAMILIES_REPORT=1 prints them.
#include "runtime/Probe.h"
#include "tests/support/NearestMember.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <doctest/doctest.h>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;
using test::RefLayer;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kPoints = 160; // per setting: enough to reach every region, cheap (~0.5 ms each)

struct Setting {
    std::string family, args; // the stdlib family and its parameters, in scene syntax
    RefLayer ref;             // the same layer, for the reference
};

Setting setting(std::string family, std::string args, test::RefFamily ref, double spacing,
                double phase = 0.0, double ox = 0.0, double oy = 0.0, double rotationDeg = 0.0) {
    return {std::move(family), std::move(args),
            RefLayer{std::move(ref), spacing, phase, ox, oy, rotationDeg * kDeg}};
}

// One sampled point: where it is, what the renderer says, what the reference says.
struct Sample {
    double lx = 0, ly = 0;          // in the layer frame
    double index = 0, distance = 0; // the renderer (the double-precision interpreter)
    double refIndex = 0;            // Table 1's phase
    test::Nearest nearest;          // the search
};

// kPoints seeded points, uniform over the disc |q| <= radius (in spacings) of the layer
// frame, mapped into the world through the layer's origin and rotation. With `corners` = N,
// every third point is aimed within 0.15 rad of a vertex direction of an N-gon instead
// (vertices lie half way between facet normals), so the small regions past the corners get
// enough points.
std::vector<Sample> sampleSetting(const Setting& st, double radius, uint64_t seed,
                                  int corners = 0) {
    auto program = test::compileOk(test::layerSource(st.family, st.args, st.ref),
                                   {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    const double s = st.ref.spacing;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Sample> out;
    for (int i = 0; i < kPoints; ++i) {
        double r = s * radius * std::sqrt(unit(rng));
        double a = 2.0 * kPi * unit(rng);
        if (corners && i % 3 == 0)
            a = 2.0 * kPi * (std::floor(a / (2.0 * kPi) * corners) + 0.5) / corners +
                0.3 * (unit(rng) - 0.5);
        Sample p;
        p.lx = r * std::cos(a);
        p.ly = r * std::sin(a);
        double wx, wy;
        st.ref.toWorld(p.lx, p.ly, wx, wy);
        std::vector<double> v = probe.at(wx, wy);
        p.index = v[program->layout.indexSlot(0)];
        p.distance = v[program->layout.distanceSlot(0)];
        p.refIndex = st.ref.index(wx, wy);
        // Two spacings holds the nearest member of every point sampled here (the farthest
        // is a spacing and a third, at the centre of the hyperbola with phase 3 of 10).
        p.nearest = test::nearestMember(st.ref, wx, wy, 2.0 * s);
        out.push_back(p);
    }
    return out;
}

// The checks every setting gets: the stdlib phase is Table 1's, and the search found a member.
void checkIndexAndSearch(const Sample& p) {
    CAPTURE(p.lx);
    CAPTURE(p.ly);
    CHECK(std::fabs(p.index - p.refIndex) <= 1e-9 * (1.0 + std::fabs(p.refIndex)));
    REQUIRE(p.nearest.found);
}

// Signed relative errors (renderer - truth) / truth, by family and region.
struct Stat {
    int count = 0;
    double lo = 0.0, hi = 0.0; // most negative and most positive
};
using Stats = std::map<std::string, Stat>;

void record(Stats& stats, const std::string& key, double rel) {
    Stat& s = stats[key];
    s.lo = s.count ? std::min(s.lo, rel) : rel;
    s.hi = s.count ? std::max(s.hi, rel) : rel;
    ++s.count;
}

void report(const char* title, const Stats& stats) {
    if (!std::getenv("MOIRE_FAMILIES_REPORT")) return;
    std::printf("%s\n", title);
    for (const auto& [key, s] : stats)
        std::printf("  %-44s n=%4d  rel. error %+.2e .. %+.2e\n", key.c_str(), s.count, s.lo, s.hi);
}

std::string settingName(const Setting& st) {
    return st.family + (st.args.empty() ? "" : " (" + st.args + ")");
}

// The renderer's member: the rounded index, clamped to the family's first member.
long rendererMember(const Setting& st, double index) {
    long n = static_cast<long>(std::floor(index + 0.5));
    return st.ref.family.first ? std::max<long>(n, *st.ref.family.first) : n;
}

} // namespace

TEST_CASE("families: lines and circles are drawn at their exact Euclidean distance") {
    // Eq. 5 is exact when |grad phi| = 1 and the members are parallel curves of each other:
    // the residual is then the distance. The tolerance 1e-6 s is loose only against the
    // search's own error (~1e-12 s); anything real (a wrong frame, a wrong gradient, a
    // member off by one) is orders of magnitude larger.
    const std::vector<Setting> settings = {
        setting("lines", "", test::refLines(0.0), 8),
        setting("lines", "angle = 30deg", test::refLines(30 * kDeg), 8, 2.5, 3, -2),
        setting("lines", "angle = -75deg", test::refLines(-75 * kDeg), 5, 0, -6, 4, 40),
        setting("lines", "angle = 123deg", test::refLines(123 * kDeg), 12, -3.5),
        setting("circles", "", test::refCircles(), 8),
        setting("circles", "", test::refCircles(), 5, 1.5, 3, -7),
        setting("circles", "", test::refCircles(), 10, 4, -2, 9, 33),
    };
    Stats stats;
    uint64_t seed = 1;
    for (const Setting& st : settings) {
        CAPTURE(test::layerSource(st.family, st.args, st.ref));
        for (const Sample& p : sampleSetting(st, 5.0, seed++)) {
            checkIndexAndSearch(p);
            CHECK(std::fabs(p.distance - p.nearest.distance) <= 1e-6 * st.ref.spacing);
            record(stats, st.family + ": everywhere",
                   (p.distance - p.nearest.distance) / p.nearest.distance);
        }
    }
    report("lines and circles", stats);
}

TEST_CASE("families: polygons are exact on their flat sides and within cos(pi/N) past a corner") {
    struct Poly {
        Setting st;
        int sides;
    };
    const std::vector<Poly> polys = {
        {setting("squares", "", test::refSquares(), 8), 4},
        {setting("squares", "", test::refSquares(), 6, 2, -4, 5, 20), 4},
        {setting("triangles", "", test::refTriangles(), 8), 3},
        {setting("triangles", "", test::refTriangles(), 7, 1, 2, 3, -35), 3},
        {setting("hexagons", "", test::refHexagons(), 8), 6},
        {setting("hexagons", "", test::refHexagons(), 9, 3, 5, 1, 10), 6},
        {setting("ngon", "sides = 5", test::refNgon(5), 8), 5},
        {setting("ngon", "sides = 7", test::refNgon(7), 8, 2), 7},
        {setting("ngon", "sides = 12", test::refNgon(12), 6, 0, -3, -3, 15), 12},
    };
    Stats stats;
    uint64_t seed = 100;
    for (const Poly& poly : polys) {
        const Setting& st = poly.st;
        const double s = st.ref.spacing;
        CAPTURE(test::layerSource(st.family, st.args, st.ref));
        // Every row is a support function max_k <q, n_k>, facet normals n_k at angles 2 pi k / N
        // (a flat side faces +x). Inside a member, the distance to it is exactly the least
        // gap to a side line, min_k (c - <q, n_k>) = c - phi: Eq. 5 is exact. Outside it,
        // phi - c is the gap to the nearest side's line, which is the distance only when the
        // foot of the perpendicular lands on the side; past a corner the nearest point is the
        // vertex, and for q at angle a from one normal and 2 pi / N - a from the next,
        // phi - c = |q - v| max(cos a, cos(2 pi / N - a)) >= |q - v| cos(pi / N).
        // All phase offsets here are in [0, s/2], so the member the renderer picks exists.
        int corners = 0, flats = 0;
        double worstCorner = 0.0;
        for (const Sample& p : sampleSetting(st, 5.0, seed++, poly.sides)) {
            checkIndexAndSearch(p);
            CAPTURE(p.lx);
            CAPTURE(p.ly);
            double phi = p.refIndex * s + st.ref.phase;
            long n = rendererMember(st, p.refIndex);
            double c = n * s + st.ref.phase; // the level of the member Eq. 5 measures to
            bool flat = true;
            if (phi > c) { // outside that member: does the foot land on the active side?
                int active = 0;
                double best = -1e300;
                for (int k = 0; k < poly.sides; ++k) {
                    double dot = p.lx * std::cos(2 * kPi * k / poly.sides) +
                                 p.ly * std::sin(2 * kPi * k / poly.sides);
                    if (dot > best) best = dot, active = k;
                }
                double fx = p.lx - (phi - c) * std::cos(2 * kPi * active / poly.sides);
                double fy = p.ly - (phi - c) * std::sin(2 * kPi * active / poly.sides);
                for (int k = 0; k < poly.sides; ++k)
                    if (fx * std::cos(2 * kPi * k / poly.sides) +
                            fy * std::sin(2 * kPi * k / poly.sides) >
                        c + 1e-9 * s)
                        flat = false;
            }
            double rel = (p.distance - p.nearest.distance) / p.nearest.distance;
            if (flat) {
                ++flats;
                CHECK(std::fabs(p.distance - p.nearest.distance) <= 1e-6 * s);
            } else {
                ++corners;
                worstCorner = std::min(worstCorner, rel);
                CHECK(p.distance <= p.nearest.distance + 1e-6 * s);
                CHECK(p.distance >= std::cos(kPi / poly.sides) * p.nearest.distance - 1e-6 * s);
            }
            std::string key = settingName(st) + (flat ? ": flat sides" : ": past a corner");
            record(stats, key, rel);
            if (p.nearest.distance <= s / 4) record(stats, key + ", d <= s/4", rel);
        }
        // Both regions were reached, and the corner error is really there (and really seen).
        CHECK(flats > kPoints / 4);
        CHECK(corners > 3);
        CHECK(worstCorner < -1e-3);
    }
    report("polygons", stats);
}

namespace {

// Eq. 5 along the straight segment from the nearest point f to p (length d, unit vector t
// oriented up the phase): the residual |phi(p) - c| is the integral over the segment of the
// directional derivative grad(phi) . t, and Eq. 5 divides it by |grad phi(p)|. So
// d_eq5 / d is the segment's mean of grad(phi) . t over |grad phi(p)|, and lies between
// that derivative's least and greatest values on the segment, over |grad phi(p)|. This is
// exact, not an estimate: it shows the error is Eq. 5's own, whatever its size. The
// derivative is sampled at 33 points by central differences of Table 1's phase, and the
// envelope widened by 2% of its width for what the sampling can miss.
std::pair<double, double> eikonalEnvelope(const RefLayer& L, const Sample& p) {
    const test::Nearest& f = p.nearest;
    double d = f.distance;
    double side =
        (p.refIndex * L.spacing + L.phase) > (f.member * L.spacing + L.phase) ? 1.0 : -1.0;
    double tx = side * (p.lx - f.lx) / d, ty = side * (p.ly - f.ly) / d;
    double h = 1e-6 * L.spacing, lo = 1e300, hi = -1e300;
    for (int j = 0; j <= 32; ++j) {
        double x = f.lx + (p.lx - f.lx) * j / 32.0, y = f.ly + (p.ly - f.ly) * j / 32.0;
        double ref = std::atan2(y, x);
        double dphi = (L.family.phi(x + h * tx, y + h * ty, ref) -
                       L.family.phi(x - h * tx, y - h * ty, ref)) /
                      (2 * h);
        lo = std::min(lo, dphi);
        hi = std::max(hi, dphi);
    }
    double g = L.family.gradNorm(p.lx, p.ly), pad = 0.02 * (hi - lo) + 1e-7 * g;
    return {(lo - pad) / g, (hi + pad) / g};
}

} // namespace

TEST_CASE("families: the curved families are first-order accurate, within measured bounds") {
    // Table 1's last four rows have a gradient that varies, so Eq. 5 is a first-order
    // (eikonal) estimate whose relative error grows in proportion to the distance. Each
    // region's tolerance below applies in the inked band, true distance <= s/4, and is the
    // worst error measured over these settings (docs/families.md) with about 25% headroom,
    // so a regression of a few percent fails; the exact envelope above backs every point
    // (dropping the gradient divide fails it at hundreds of points in every setting).
    // Trouble spots get their own regions and looser bounds:
    //  - hyperbola: `below first member` (between the excluded asymptote pair and member 1,
    //    where the pipeline measures on phi^2) and `near asymptotes` (between members 1 and
    //    2, where |grad phi| = |p| / phi changes fastest); `away` is beyond member 2;
    //  - spiral: `centre` is r < 2 s, where the turns curl fastest;
    //  - wave and parabola: `crest` is where the point is farther from its nearest member
    //    than half the member's radius of curvature there (curvature x distance > 1/2,
    //    the curvature from Table 1's phase by finite differences); `flank` is the rest.
    struct Curved {
        Setting st;
        double radius; // of the sampled disc, in spacings
    };
    const std::vector<Curved> curved = {
        {setting("wave", "", test::refWave(10, 1, 0), 8), 5},
        {setting("wave", "amplitude = 4; frequency = 2; shift = 45deg",
                 test::refWave(4, 2, 45 * kDeg), 8),
         5},
        {setting("wave", "amplitude = 12; frequency = 0.5; shift = -30deg",
                 test::refWave(12, 0.5, -30 * kDeg), 6, 0, 4, -2, 25),
         5},
        {setting("wave", "amplitude = 6; frequency = 1.5; shift = 90deg",
                 test::refWave(6, 1.5, 90 * kDeg), 10, 3),
         5},
        {setting("parabola", "bend = 1", test::refParabola(1), 8), 5},
        {setting("parabola", "bend = 3", test::refParabola(3), 8, 2), 5},
        {setting("parabola", "bend = -2", test::refParabola(-2), 6, 0, -5, 3, 60), 5},
        {setting("hyperbola", "", test::refHyperbola(), 8), 5},
        {setting("hyperbola", "", test::refHyperbola(), 6, -2, 2, -3, 30), 5},
        {setting("hyperbola", "", test::refHyperbola(), 10, 3), 5},
        {setting("spiral", "", test::refSpiral(1, 8), 8), 6},
        {setting("spiral", "arms = 2", test::refSpiral(2, 8), 8), 6},
        {setting("spiral", "arms = -3", test::refSpiral(-3, 6), 6, 1.5, -4, 2, 45), 6},
    };
    // Tolerances on |relative error| for true distance <= s/4, by family and region.
    // (Measured worst: wave 0.199 / 0.134, parabola 0.023, hyperbola 0.084 / 0.232 / 0.121,
    // spiral 0.0011 / 0.148.)
    const std::map<std::string, double> tolerance = {
        {"wave: flank", 0.25},
        {"wave: crest", 0.17},
        {"parabola: flank", 0.03},
        {"parabola: crest", 0.03},
        {"hyperbola: away", 0.11},
        {"hyperbola: near asymptotes", 0.30},
        {"hyperbola: below first member", 0.16},
        {"spiral: away", 0.0015},
        {"spiral: centre", 0.20},
    };
    Stats stats;
    uint64_t seed = 200;
    for (const Curved& c : curved) {
        const Setting& st = c.st;
        const RefLayer& L = st.ref;
        const double s = L.spacing;
        CAPTURE(test::layerSource(st.family, st.args, L));
        int enveloped = 0;
        for (const Sample& p : sampleSetting(st, c.radius, seed++)) {
            checkIndexAndSearch(p);
            CAPTURE(p.lx);
            CAPTURE(p.ly);
            const double d = p.nearest.distance, rel = (p.distance - d) / d;
            std::string region;
            bool fold = false;
            if (st.family == "hyperbola") {
                double u = p.refIndex;
                fold = u < 1.0;
                region = fold ? "below first member" : u < 2.0 ? "near asymptotes" : "away";
            } else if (st.family == "spiral") {
                region = std::hypot(p.lx, p.ly) < 2.0 * s ? "centre" : "away";
            } else {
                region = test::memberCurvature(L, p.nearest) * d > 0.5 ? "crest" : "flank";
            }
            const std::string key = st.family + ": " + region;
            // Where the renderer measures to the member the search found nearest, Eq. 5 obeys
            // the exact envelope. (Elsewhere it measures to a neighbour that is nearer in
            // phase but not in space: a point near the midline between two members, in the
            // inked band only where the hyperbola's members crowd. 49 of 2080 points.) The
            // hyperbola's fold band uses phi^2 instead, checked below.
            if (!fold && rendererMember(st, p.index) == p.nearest.member) {
                auto [lo, hi] = eikonalEnvelope(L, p);
                CHECK(p.distance / d >= lo);
                CHECK(p.distance / d <= hi);
                ++enveloped;
            }
            if (fold) {
                // Member 0 (the asymptote pair) is excluded, so nothing here may be drawn
                // closer than it is: Eq. 5 on phi^2 errs long, if anything (measured 0 to
                // +12%), and 3% allows for rounding near member 1, where the error is ~0.
                CHECK(p.distance >= 0.97 * d);
            }
            if (d <= s / 4) {
                record(stats, key, rel);
                record(stats,
                       "  " + settingName(st) + " phase " + std::to_string(L.phase).substr(0, 4) +
                           ": " + region,
                       rel);
                record(stats,
                       key + (d <= s / 16  ? ", d <= s/16"
                              : d <= s / 8 ? ", d <= s/8"
                                           : ", d <= s/4"),
                       rel);
                CHECK(std::fabs(rel) <= tolerance.at(key));
            }
        }
        CHECK(enveloped >= kPoints * 3 / 4); // the envelope was really checked
    }
    report("curved families", stats);
}
