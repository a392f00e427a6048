// The eight panels of the teaser (the spec's Fig. 1, docs/figures.md) against their captions.
// Each panel is rendered again here with the real binary exactly as scripts/render-figures.sh
// renders it (a 480x320 `split`: the pattern left of the dashed rule, the envelope right of
// it), compared with the picture in docs/images, and measured for what its caption claims:
//
// 1. two ring families: the envelope's fringes are the level sets of the difference of the
//    radii (hyperbolae) where the rings run alike, of their sum (ellipses) where they run
//    against each other between the centres: its grey correlates with cos(2 pi D), D the
//    difference or sum of the two ring indices computed here from the centres alone;
// 2. a terrain field: the envelope correlates with cos(2 pi gain terrain), the terrain
//    computed here from its formula (a copy of stdlib/fields.moire's, kept as the oracle);
// 3. spirals of opposite hand: the envelope depends on the polar angle alone, with the
//    12 fringes a turn that arms +6 and -6 give (6 in the right half): it correlates with
//    cos(12 theta), and a ring of pixels near the centre and one far out see the same rays;
// 4. hexagonal lattices at a 5 degree twist: the envelope's coincidence spots lie on a
//    superlattice of period p / (2 sin 2.5deg), p = 9 sqrt 3 the honeycomb's repeat;
// 5. four point vortices: the envelope correlates with cos(2 pi swirl), swirl copied as in 2;
// 6. one walking family: its envelope has fringes (a spread of greys) that the same family
//    without its walk does not have;
// 7. three radial fans: the core where the three open discs overlap is bare paper, and the
//    envelope is not crushed to black;
// 8. two walking families drifting: the frame moves (t = 0 and t = 7.5 s differ) and returns
//    after the 30 s cycle, and the envelope has fringes.
// Every panel: left of the rule is exactly the pattern view, right of it the envelope view,
// and the two differ.
#include "tests/support/DocImages.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>

using namespace moire;

namespace {

constexpr int kW = 480, kH = 320;
constexpr double kPi = 3.14159265358979323846;
// The envelope half, clear of the dashed rule at the middle, and the pattern half.
constexpr int kEnvelopeX0 = kW / 2 + 4, kPatternX1 = kW / 2 - 4;

struct Panel {
    int number;
    std::string scene, image;
    double zoom; // the scene's camera zoom (every panel's scene is 1200x800 about (0, 0))
};

const std::vector<Panel>& panels() {
    static const std::vector<Panel> all = {
        {1, "examples/two_rings.moire", "teaser-1-two-rings.png", 1.2},
        {2, "examples/terrain_contours.moire", "teaser-2-terrain.png", 1.0},
        {3, "examples/counter_spirals.moire", "teaser-3-counter-spirals.png", 1.4},
        {4, "examples/hexagonal_twist.moire", "teaser-4-hexagonal-twist.png", 1.3},
        {5, "examples/vortex_streamlines.moire", "teaser-5-vortices.png", 1.0},
        {6, "examples/walking_squares.moire", "teaser-6-one-walking-family.png", 1.2},
        {7, "examples/radial_fans.moire", "teaser-7-radial-fans.png", 1.4},
        {8, "examples/drifting_walks.moire", "teaser-8-drifting-walks.png", 1.1},
    };
    return all;
}

Image renderPanel(const Panel& p, const test::TempDir& dir, const std::string& extra = "") {
    return test::renderWithMoire("--view split --size 480x320 " + p.scene + " " + extra, dir,
                                 "panel" + std::to_string(p.number));
}

// The world point at the centre of pixel (px, py) of a 480x320 render of a 1200x800 frame.
struct World {
    double x, y;
};
World world(const Panel& p, int px, int py) {
    const double s = p.zoom * kW / 1200.0;
    return {(px + 0.5 - kW / 2) / s, -(py + 0.5 - kH / 2) / s};
}

// The correlation of the envelope half's grey with cos(2 pi f(x, y)) over its pixels where
// `keep(x, y)` holds.
template <class F, class K>
double envelopeCorrelation(const Image& img, const Panel& p, F f, K keep) {
    std::vector<double> g, c;
    for (int py = 0; py < kH; ++py)
        for (int px = kEnvelopeX0; px < kW; ++px) {
            World w = world(p, px, py);
            if (!keep(w.x, w.y)) continue;
            g.push_back(test::grey(img, px, py));
            c.push_back(std::cos(2 * kPi * f(w.x, w.y)));
        }
    REQUIRE(g.size() > 200);
    return test::correlation(g, c);
}

// The spread of the envelope half's greys: the 95th percentile less the 5th.
double envelopeSpread(const Image& img) {
    std::vector<double> g;
    for (int py = 0; py < kH; ++py)
        for (int px = kEnvelopeX0; px < kW; ++px) g.push_back(test::grey(img, px, py));
    std::sort(g.begin(), g.end());
    return g[g.size() * 95 / 100] - g[g.size() * 5 / 100];
}

// Oracles: the fields of stdlib/fields.moire, copied so that the test does not read the
// fringes' expected places off the compiler it checks.
double terrain(double x, double y) {
    return 2.2 * std::sin(x / 97 + 0.3) + 1.7 * std::sin((0.6 * x + 0.8 * y) / 71 + 1.1) +
           1.3 * std::sin((-0.7 * x + 0.71 * y) / 53 + 2.3) +
           0.9 * std::sin((0.25 * x - 0.97 * y) / 37 + 0.7) +
           0.6 * std::sin((0.94 * x + 0.34 * y) / 23 + 4.1);
}
double swirl(double x, double y) {
    auto l = [](double a, double b) { return std::log(std::hypot(a, b)); };
    return 2 *
           (l(x - 150, y - 110) - l(x + 150, y - 110) + l(x + 150, y + 110) - l(x - 150, y + 110));
}

} // namespace

TEST_CASE("the teaser's panels are the scenes docs/figures.md names, drawn as the script does") {
    const std::string figures = test::readFile(test::sourcePath("docs/figures.md"));
    const std::string script = test::readFile(test::sourcePath("scripts/render-figures.sh"));
    test::TempDir dir("teaser");
    for (const Panel& p : panels()) {
        CAPTURE(p.number);
        // The caption's row names the scene and shows the picture; the script draws it.
        const std::string row = "| " + std::to_string(p.number) + ". ";
        size_t at = figures.find(row);
        REQUIRE(at != std::string::npos);
        const std::string line = figures.substr(at, figures.find('\n', at) - at);
        CHECK(line.find("`" + p.scene + "`") != std::string::npos);
        CHECK(line.find("(images/" + p.image + ")") != std::string::npos);
        CHECK(script.find("render --view split " + p.scene + " -o \"$out/" + p.image + "\"") !=
              std::string::npos);
        Image img = renderPanel(p, dir);
        test::checkSameAsStored(img, test::sourcePath("docs/images/" + p.image));
        // Split: left of the rule the pattern, right of it the envelope, each exactly as
        // that view draws it alone at the same settings.
        Image pattern =
            test::renderWithMoire("--view pattern --size 480x320 " + p.scene, dir, "pattern");
        Image envelope =
            test::renderWithMoire("--view envelope --size 480x320 " + p.scene, dir, "envelope");
        size_t off = 0;
        for (int py = 0; py < kH; ++py) {
            for (int px = 0; px < kPatternX1; ++px)
                off += std::fabs(test::grey(img, px, py) - test::grey(pattern, px, py)) > 1.5 / 255;
            for (int px = kEnvelopeX0; px < kW; ++px)
                off +=
                    std::fabs(test::grey(img, px, py) - test::grey(envelope, px, py)) > 1.5 / 255;
        }
        INFO(off, " pixels of the split differ from their view's");
        CHECK(off == 0);
        // And the two views differ: the envelope is not the pattern.
        CHECK(test::compareImages(pattern, envelope, 0.1).meanAbs > 0.02);
    }
}

TEST_CASE("panel 1: hyperbolae where the ring radii differ by a spacing, ellipses where they sum") {
    test::TempDir dir("teaser1");
    const Panel& p = panels()[0];
    Image img = renderPanel(p, dir);
    // Centres (-40, 0) and (40, 0), spacing 8: the ring indices are r1 / 8 and r2 / 8.
    auto r1 = [](double x, double y) { return std::hypot(x + 40, y); };
    auto r2 = [](double x, double y) { return std::hypot(x - 40, y); };
    auto along = [&](double x, double y) { // cosine of the angle between the two rings' normals
        return ((x + 40) * (x - 40) + y * y) / (r1(x, y) * r2(x, y));
    };
    auto diff = [&](double x, double y) { return (r1(x, y) - r2(x, y)) / 8; };
    auto sum = [&](double x, double y) { return (r1(x, y) + r2(x, y)) / 8; };
    auto alike = [&](double x, double y) { return along(x, y) > 0.3; };
    auto against = [&](double x, double y) { return along(x, y) < -0.3; };
    const double hyperbolae = envelopeCorrelation(img, p, diff, alike);
    const double ellipses = envelopeCorrelation(img, p, sum, against);
    const double wrongOutside = envelopeCorrelation(img, p, sum, alike);
    const double wrongBetween = envelopeCorrelation(img, p, diff, against);
    MESSAGE("panel 1: hyperbolae ", hyperbolae, ", ellipses ", ellipses, " (wrong: ", wrongOutside,
            ", ", wrongBetween, "), spread ", envelopeSpread(img));
    CHECK(hyperbolae > 0.85);
    CHECK(ellipses > 0.85);
    CHECK(std::fabs(wrongOutside) < 0.2);
    CHECK(std::fabs(wrongBetween) < 0.2);
    CHECK(envelopeSpread(img) > 0.3); // both light and dark fringes
}

TEST_CASE("panel 2 and 5: the fringes are the encoded field's contours") {
    test::TempDir dir("teaser25");
    auto everywhere = [](double, double) { return true; };
    Image terrainImg = renderPanel(panels()[1], dir);
    const double t = envelopeCorrelation(
        terrainImg, panels()[1], [](double x, double y) { return 0.4 * terrain(x, y); },
        everywhere);
    const double tOffGain = envelopeCorrelation(
        terrainImg, panels()[1], [](double x, double y) { return 1.25 * 0.4 * terrain(x, y); },
        everywhere);
    Image swirlImg = renderPanel(panels()[4], dir);
    // Away from the vortices, where the streamlines crowd past what the carrier resolves.
    auto clear = [](double x, double y) {
        for (double cx : {-150.0, 150.0})
            for (double cy : {-110.0, 110.0})
                if (std::hypot(x - cx, y - cy) < 40) return false;
        return true;
    };
    const double s = envelopeCorrelation(
        swirlImg, panels()[4], [](double x, double y) { return swirl(x, y); }, clear);
    const double sOffGain = envelopeCorrelation(
        swirlImg, panels()[4], [](double x, double y) { return 1.25 * swirl(x, y); }, clear);
    MESSAGE("panel 2: terrain ", t, " (at 1.25 times the gain: ", tOffGain, "); panel 5: swirl ", s,
            " (at 1.25 times: ", sOffGain, ")");
    CHECK(t > 0.85);
    CHECK(tOffGain < t - 0.3); // a quarter more contours no longer fit
    CHECK(s > 0.85);
    CHECK(sOffGain < s - 0.3);
}

TEST_CASE("panel 3: counter-spirals beat in a fan of rays, 12 a turn") {
    test::TempDir dir("teaser3");
    const Panel& p = panels()[2];
    Image img = renderPanel(p, dir);
    auto rays = [](double x, double y) { return 12 * std::atan2(y, x) / (2 * kPi); };
    auto offCentre = [](double x, double y) { return std::hypot(x, y) > 25; };
    const double fan = envelopeCorrelation(img, p, rays, offCentre);
    const double ten = envelopeCorrelation(
        img, p, [](double x, double y) { return 10 * std::atan2(y, x) / (2 * kPi); }, offCentre);
    const double fourteen = envelopeCorrelation(
        img, p, [](double x, double y) { return 14 * std::atan2(y, x) / (2 * kPi); }, offCentre);
    MESSAGE("panel 3: 12 rays ", fan, " (10: ", ten, ", 14: ", fourteen, ")");
    CHECK(fan > 0.85);
    CHECK(std::fabs(ten) < 0.5);
    CHECK(std::fabs(fourteen) < 0.5);
}

namespace {

// The envelope half's coincidence spots: the connected patches of its lightest 3% of pixels,
// each taken at its centroid, those touching the half's edges left out (a spot cut by the
// edge has its centre misplaced). Returns the median distance from a spot to its nearest
// neighbour, in pixels.
double spotPeriod(const Image& img) {
    const int w = kW - kEnvelopeX0;
    std::vector<double> g(static_cast<size_t>(w) * kH);
    for (int py = 0; py < kH; ++py)
        for (int px = 0; px < w; ++px) g[py * w + px] = test::grey(img, kEnvelopeX0 + px, py);
    std::vector<double> sorted = g;
    std::sort(sorted.begin(), sorted.end());
    const double light = sorted[sorted.size() * 97 / 100];
    std::vector<int> seen(g.size(), 0);
    std::vector<std::pair<double, double>> spots;
    for (size_t start = 0; start < g.size(); ++start) {
        if (seen[start] || g[start] < light) continue;
        // Flood fill the patch.
        std::vector<size_t> stack = {start};
        seen[start] = 1;
        double sx = 0, sy = 0;
        size_t n = 0;
        bool edge = false;
        while (!stack.empty()) {
            size_t i = stack.back();
            stack.pop_back();
            const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
            sx += x, sy += y, ++n;
            if (x == 0 || y == 0 || x == w - 1 || y == kH - 1) edge = true;
            for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                const int u = x + dx, v = y + dy;
                if (u < 0 || v < 0 || u >= w || v >= kH) continue;
                const size_t j = static_cast<size_t>(v) * w + u;
                if (!seen[j] && g[j] >= light) seen[j] = 1, stack.push_back(j);
            }
        }
        if (!edge && n >= 4) spots.push_back({sx / n, sy / n});
    }
    MESSAGE(spots.size(), " spots");
    REQUIRE(spots.size() >= 3);
    std::vector<double> nearest;
    for (size_t i = 0; i < spots.size(); ++i) {
        double best = 1e9;
        for (size_t j = 0; j < spots.size(); ++j)
            if (j != i)
                best = std::min(best, std::hypot(spots[j].first - spots[i].first,
                                                 spots[j].second - spots[i].second));
        nearest.push_back(best);
    }
    std::sort(nearest.begin(), nearest.end());
    return nearest[nearest.size() / 2];
}

} // namespace

TEST_CASE("panel 4: the twisted honeycombs' superlattice has period p / (2 sin(twist / 2))") {
    test::TempDir dir("teaser4");
    const Panel& p = panels()[3];
    const double pxPerUnit = p.zoom * kW / 1200.0;
    const double pitch = 9 * std::sqrt(3.0); // the honeycomb of side 9 repeats by its centres
    auto expected = [&](double twistDeg) {
        return pitch / (2 * std::sin(twistDeg / 2 * kPi / 180)) * pxPerUnit;
    };
    const double at5 = spotPeriod(renderPanel(p, dir));
    // The same lattices at a 4 degree twist: the period must grow by sin 2.5deg / sin 2deg.
    const double at4 = spotPeriod(renderPanel(p, dir, "-D top.rotation=4deg"));
    MESSAGE("panel 4: spot period ", at5, " px at 5deg (expected ", expected(5), "), ", at4,
            " px at 4deg (expected ", expected(4), ")");
    CHECK(at5 == doctest::Approx(expected(5)).epsilon(0.03));
    CHECK(at4 == doctest::Approx(expected(4)).epsilon(0.03));
}

TEST_CASE("panel 6: one walking family interferes with itself, and without its walk it does not") {
    test::TempDir dir("teaser6");
    const Panel& p = panels()[5];
    Image walking = renderPanel(p, dir);
    Image still = renderPanel(p, dir, "-D 'walk.offset=(0,0)' -D walk.turn=0deg");
    const double ink = test::meanInk(walking, 0, kPatternX1);
    MESSAGE("panel 6: envelope spread ", envelopeSpread(walking), " walking, ",
            envelopeSpread(still), " without the walk; pattern ink ", ink);
    CHECK(envelopeSpread(walking) > 0.2);
    CHECK(envelopeSpread(still) < 0.05);
    CHECK(ink > 0.15);
    CHECK(ink < 0.85);
}

TEST_CASE("panel 7: three fans leave a white core, and the envelope is not crushed to black") {
    test::TempDir dir("teaser7");
    const Panel& p = panels()[6];
    Image img = renderPanel(p, dir);
    const double paper = (0xf8 + 0xf5 + 0xee) / (3 * 255.0);
    double worst = 0;
    size_t core = 0;
    for (int py = 0; py < kH; ++py)
        for (int px = 0; px < kPatternX1; ++px) {
            World w = world(p, px, py);
            // Well inside all three open discs (radius 64 about centres 40 from the origin).
            if (w.x < -14 || w.x > -4 || std::fabs(w.y) > 6) continue;
            worst = std::max(worst, std::fabs(test::grey(img, px, py) - paper));
            ++core;
        }
    size_t black = 0, all = 0;
    for (int py = 0; py < kH; ++py)
        for (int px = kEnvelopeX0; px < kW; ++px, ++all)
            if (test::grey(img, px, py) < 0.15) ++black;
    MESSAGE("panel 7: ", core, " core pixels, worst off paper ", worst, "; envelope black ",
            double(black) / all);
    CHECK(core > 10);
    CHECK(worst < 0.02);
    CHECK(double(black) / all < 0.3);
}

TEST_CASE("panel 8: two walking families drift, loop in 30 s, and beat") {
    test::TempDir dir("teaser8");
    const Panel& p = panels()[7];
    Image t0 = renderPanel(p, dir, "--time 0");
    Image t7 = renderPanel(p, dir, "--time 7.5");
    Image t30 = renderPanel(p, dir, "--time 30");
    const double moved = test::compareImages(t0, t7, 0.1).meanAbs;
    const double back = test::compareImages(t0, t30, 2.0 / 255).fractionWithin();
    const double ink = test::meanInk(t0, 0, kPatternX1);
    MESSAGE("panel 8: mean change by 7.5 s ", moved, ", same after 30 s ", back,
            ", envelope spread ", envelopeSpread(t0), ", pattern ink ", ink);
    CHECK(moved > 0.03);
    CHECK(back >= 0.999);
    CHECK(envelopeSpread(t0) > 0.2);
    CHECK(ink > 0.15);
    CHECK(ink < 0.85);
}
