// The envelope (§4.4) of the families that advance by something other than a phase shift,
// against brute force over the pattern itself:
//  - lattices advance by a translation, and their index is a pair: the envelope sweeps both
//    generators over the unit cell (the rank-two case), so its oracle is the pattern
//    re-rendered with every lattice translated by du and dv of its own generating steps (each
//    layer's `origin` literal moved), over a 48 x 48 grid of the cell, averaged;
//  - the radial pencil advances by a rotation (its `rotation` literal moved by a pi / N per
//    advance a), its member gap growing with the radius; 1,024 rotations, with the second
//    layer turned backwards where the two index gradients point against each other (the
//    sum beat, as tests/envelope_test.cpp's oracle does for the phase families);
//  - a morph across kinds (rings into a fan) advances each member its own way, blended as the
//    pattern blends them: its oracle moves the rings' phase and the fan's rotation at once.
// The envelope must match within one colour step at 99.9% of the samples, at enough taps.
// Then the pencil's other views: its winding index's gradient against its closed form, and
// two fans beating in the ratio view. (A family given by its distance alone is still refused
// by the views that sweep: tests/errors/view_cannot_sweep.)
#include "runtime/Probe.h"
#include "tests/support/BruteMean.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr int kW = 64, kH = 48;
constexpr double kPi = std::numbers::pi;
// Each layer's origin (x, y), a sentinel to find its literal slot, and its rotation
// (radians), likewise; all positive (a negative number is a positive literal negated).
using Origins = std::array<std::array<double, 2>, 2>;
constexpr double kTurn[2] = {0.0000567, 5 * kPi / 180 + 0.0000678};

std::string twoLayers(const std::string& a, const std::string& b, const Origins& at) {
    std::string out = fmt::format("scene {{ size = ({}, {}); background = #f4f0e8 }}\n", kW, kH);
    const std::string* family[2] = {&a, &b};
    for (int i = 0; i < 2; ++i)
        out += fmt::format("layer {{ {}; origin = ({}, {}); rotation = {}rad }}\n", *family[i],
                           at[i][0], at[i][1], kTurn[i]);
    return out;
}

// The slots of one layer's origin and rotation.
struct Slots {
    int ox, oy, turn;
};

// Moves layer i's literals for the advance (a, b): a one-index advance uses a alone.
using Advance = std::function<void(std::vector<double>&, const Slots&, int i, double a, double b)>;

// The mean RGB of the pattern over the advances `taps` (each (a, b), the same for every layer,
// except that the second layer takes (-a, -b) where `backwards`), kW x kH x 3.
std::vector<double> bruteMean(const std::string& scene, const Origins& at, const Advance& move,
                              const std::vector<std::pair<double, double>>& taps,
                              bool sumWhereOpposed, double time = 0.0) {
    // The pattern point-sampled: the envelope is the mean of that picture over the advances.
    auto p = test::compileOk(scene, {.layerFields = true, .filter = sema::FilterMode::Point});
    auto jit = test::makeBackendOrSkip("jit");
    REQUIRE(jit);
    auto kernel = jit->compile(p->kernel);
    Slots slots[2];
    for (int i = 0; i < 2; ++i)
        slots[i] = {test::literalSlot(*p, at[i][0]), test::literalSlot(*p, at[i][1]),
                    test::literalSlot(*p, kTurn[i])};
    std::vector<double> backwards;
    if (sumWhereOpposed) backwards = test::sumSweepShares(*p, *kernel, p->literals, time);
    std::vector<double> sums[2];
    for (int dir = 0; dir < (sumWhereOpposed ? 2 : 1); ++dir)
        for (const auto& [a, b] : taps) {
            std::vector<double> l = p->literals;
            const double sign = dir == 1 ? -1.0 : 1.0;
            move(l, slots[0], 0, a, b);
            move(l, slots[1], 1, sign * a, sign * b);
            test::addFrameRGB(*p, *kernel, l, sums[dir], time);
        }
    return test::fadedMean(sums, backwards, static_cast<double>(taps.size()));
}

Image envelopeOf(const std::string& scene, double taps, double time = 0.0) {
    auto p = test::compileOk(
        scene, {.view = sema::ViewMode::Envelope, .envelopeGain = 1.0, .envelopeTaps = taps});
    auto jit = test::makeBackendOrSkip("jit");
    REQUIRE(jit);
    return test::renderScene(*p, *jit, 0, 0, time);
}

// A lattice's generating steps per unit of spacing, in its unstretched frame (the bases of
// stdlib/families.moire's lattices, worked out here anew: the square's grid steps, the
// triangle lattice's neighbours at 0 and 60 degrees, the honeycomb's centres s sqrt3 apart).
struct Lattice {
    const char* name;
    double c1x, c1y, c2x, c2y;
    double spacing, sx, sy;
};

std::string latticeFamily(const Lattice& l, const std::string& extra) {
    return fmt::format("family = {}; spacing = {}; scale = ({}, {}); {}", l.name, l.spacing, l.sx,
                       l.sy, extra);
}

// The view keeps a lattice dot's true ink, pi h^2 for the half-width h (its ramp is centred
// to give back what its band adds, Envelope.cpp). The pattern's dot, ramped over its 0.7 px
// band (here 0.7 world units), holds pi (h^2 + 0.7^2 / 5) instead, so the oracle draws its
// dots with the stroke whose pattern holds pi h^2: 2 sqrt(h^2 - 0.7^2 / 5). (The 1/5 is the
// smoothstep ramp's, worked out by hand: the integral of 2 pi r over the ramp about h.)
std::string oracleDots(double stroke) {
    const double h = stroke / 2;
    return fmt::format("stroke = {}", 2 * std::sqrt(h * h - 0.49 / 5));
}

} // namespace

TEST_CASE(
    "envelope of lattices: the taps over the unit cell match the pattern translated over it") {
    const double r3 = std::sqrt(3.0);
    struct Case {
        const char* what;
        Lattice lattice[2];
        std::string extra[2];
        double stroke[2];
        bool dots[2];
    };
    const Case cases[] = {
        {"two hexagonal lattices at a five-degree twist (the teaser's panel 4)",
         {{"hex_lattice", r3, 0, r3 / 2, 1.5, 6, 1, 1},
          {"hex_lattice", r3, 0, r3 / 2, 1.5, 6, 1, 1}},
         {"color = #15202b", "color = #a02010"},
         {3, 3},
         {true, true}},
        {"a stretched square grid's edges over a triangle lattice's points",
         {{"square_lattice", 1, 0, 0, 1, 7, 1.2, 0.9},
          {"triangle_lattice", 1, 0, 0.5, r3 / 2, 6.5, 1, 1}},
         {"edges = 1", "color = #2040a0"},
         {2.4, 3.4},
         {false, true}},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        const Origins at = {{{0.000123, 0.000234}, {0.000345, 0.000456}}};
        auto layer = [&](int i, bool oracle) {
            const std::string stroke = oracle && c.dots[i]
                                           ? oracleDots(c.stroke[i])
                                           : fmt::format("stroke = {}", c.stroke[i]);
            return latticeFamily(c.lattice[i], c.extra[i] + "; " + stroke);
        };
        const std::string scene = twoLayers(layer(0, false), layer(1, false), at);
        const std::string oracle = twoLayers(layer(0, true), layer(1, true), at);
        // The lattice advanced by (du, dv) is the lattice at q + S s (du c1 + dv c2) in its
        // frame q = Rot(-turn)(p - origin): its origin moves by -Rot(turn) S s (du c1 + dv c2).
        Advance move = [&](std::vector<double>& l, const Slots& at, int i, double du, double dv) {
            const Lattice& k = c.lattice[i];
            const double x = k.sx * k.spacing * (du * k.c1x + dv * k.c2x);
            const double y = k.sy * k.spacing * (du * k.c1y + dv * k.c2y);
            const double t = kTurn[i];
            l[at.ox] -= std::cos(t) * x - std::sin(t) * y;
            l[at.oy] -= std::sin(t) * x + std::cos(t) * y;
        };
        std::vector<std::pair<double, double>> grid;
        const int g = 48;
        for (int a = 0; a < g; ++a)
            for (int b = 0; b < g; ++b) grid.push_back({(a + 0.5) / g, (b + 0.5) / g});
        // 80 taps a generator: 1,600 over the cell, whose rule integrates every harmonic of
        // the cell below 37 exactly; two taps stay under the pattern's antialias band.
        CHECK(test::shareWithinOneStep(envelopeOf(scene, 80),
                                       bruteMean(oracle, at, move, grid, false)) >= 0.999);
    }
}

TEST_CASE("envelope of lines over a lattice: the lines ride the generator they beat with") {
    // Lines at the lattice's pitch, their normal 4 degrees off the square grid's second
    // generator: the fringe is lines minus the v rows. The lines must advance with v (the
    // envelope reads that from the winning character, per pixel); riding u, the first
    // generator, would average that fringe away (checked below against the same oracle).
    const Origins at = {{{0.000123, 0.000234}, {0.000345, 0.000456}}};
    const std::string lines =
        "family = lines; angle = 90deg; spacing = 6; stroke = 2.4; color = #2040a0";
    const std::string scene =
        twoLayers("family = square_lattice; spacing = 6; stroke = 3", lines, at);
    const std::string oracle =
        twoLayers("family = square_lattice; spacing = 6; " + oracleDots(3), lines, at);
    auto moveWith = [&](bool rideV) {
        return [&, rideV](std::vector<double>& l, const Slots& slot, int i, double du, double dv) {
            // The lattice's frame moves by 6 (du, dv); the lines' (index y / 6) by 6 along y
            // per unit of the generator they ride.
            const double x = i == 0 ? 6 * du : 0.0;
            const double y = i == 0 ? 6 * dv : 6 * (rideV ? dv : du);
            const double t = kTurn[i];
            l[slot.ox] -= std::cos(t) * x - std::sin(t) * y;
            l[slot.oy] -= std::sin(t) * x + std::cos(t) * y;
        };
    };
    std::vector<std::pair<double, double>> grid;
    for (int a = 0; a < 48; ++a)
        for (int b = 0; b < 48; ++b) grid.push_back({(a + 0.5) / 48, (b + 0.5) / 48});
    const Image view = envelopeOf(scene, 80);
    CHECK(test::shareWithinOneStep(view, bruteMean(oracle, at, moveWith(true), grid, false)) >=
          0.999);
    CHECK(test::shareWithinOneStep(view, bruteMean(oracle, at, moveWith(false), grid, false)) <
          0.5);
}

TEST_CASE("envelope of radial pencils: 24 taps match the pattern turned over 1,024 rotations") {
    // Two fans with centres 17 units apart, as panel 7's are.
    const int lines = 24;
    // (Sentinels are positive: a negative number is a positive literal negated.)
    const Origins at = {{{1.5123, 0.25123}, {18.5234, 1.5345}}};
    const std::string scene =
        "camera { center = (10, 0) }\n" +
        twoLayers(
            fmt::format("family = pencil; lines = {}; start = 6; stroke = 2.4", lines),
            fmt::format("family = pencil; lines = {}; start = 5; stroke = 2.6; color = #a02010",
                        lines),
            at);
    // Advancing the winding index theta N / pi by a turns the lines by a pi / N.
    Advance move = [&](std::vector<double>& l, const Slots& slot, int, double a, double) {
        l[slot.turn] -= a * kPi / lines;
    };
    std::vector<std::pair<double, double>> turns;
    for (int j = 0; j < 1024; ++j) turns.push_back({(j + 0.5) / 1024, 0.0});
    CHECK(test::shareWithinOneStep(envelopeOf(scene, 24),
                                   bruteMean(scene, at, move, turns, true)) >= 0.999);
}

TEST_CASE("envelope of a morph across kinds: each member advances its own way, blended") {
    // Rings morphing into a fan, half-way (the timing's first share, travelling all of it,
    // read at its middle: weight 1/2), over plain lines. Advancing the morph's index moves
    // the rings' phase (a s) and turns the fan (a pi / N): the rings ignore the turn, the fan
    // the phase, so the oracle moves both literals at once.
    const int lines = 30;
    const double spacing = 6, phase = 0.000789;
    const Origins at = {{{0.000123, 0.000234}, {0.000345, 0.000456}}};
    const std::string scene =
        "timing m { period = 2; mode = loop }\n" +
        twoLayers(fmt::format("family = morph(m, circles, pencil); lines = {}; start = 4; "
                              "morph_time = 1; spacing = {}; phase = {}; stroke = 2.4",
                              lines, spacing, phase),
                  "family = lines; spacing = 6.3; stroke = 2.4; color = #2040a0", at);
    const double time = 0.5;
    // The phase's slot, in the program the oracle compiles (with the layers' fields).
    const int phaseSlot = test::literalSlot(*test::compileOk(scene, {.layerFields = true}), phase);
    Advance move = [&](std::vector<double>& l, const Slots& slot, int i, double a, double) {
        if (i == 0) {
            l[slot.turn] -= a * kPi / lines;
            l[phaseSlot] = phase - a * spacing;
            return;
        }
        // The lines' index x / 6.3 (in their frame) advances by a as the frame moves 6.3 a.
        const double t = kTurn[1];
        l[slot.ox] -= std::cos(t) * 6.3 * a;
        l[slot.oy] -= std::sin(t) * 6.3 * a;
    };
    std::vector<std::pair<double, double>> turns;
    for (int j = 0; j < 512; ++j) turns.push_back({(j + 0.5) / 512, 0.0});
    CHECK(test::shareWithinOneStep(envelopeOf(scene, 48, time),
                                   bruteMean(scene, at, move, turns, false, time)) >= 0.999);
    // The blend of the members' taps, drawn alike by every backend (one missing is skipped),
    // a lattice among the members too.
    const std::string three =
        "timing m { period = 3; mode = loop }\nscene { size = (48, 32) }\n"
        "layer { family = morph(m, circles, pencil, hex_lattice); lines = 40; morph_time = 1; "
        "spacing = 5; stroke = 2 }\n"
        "layer { family = lines; spacing = 5.2; stroke = 2; rotation = 5deg }\n";
    auto split = test::compileOk(three, {.view = sema::ViewMode::Split});
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (double t : {0.5, 1.5, 2.5})
        for (const char* name : {"jit", "vulkan"}) {
            auto backend = test::makeBackendOrSkip(name);
            if (!backend) continue;
            INFO(name, " at t = ", t);
            test::ImageDiff d =
                test::compareImages(test::renderScene(*split, *interp, 0, 0, t),
                                    test::renderScene(*split, *backend, 0, 0, t), 2.0 / 255);
            CHECK(d.fractionWithin() >= 0.99);
        }
}

TEST_CASE("the pencil's winding index: its gradient is N / (pi r) around the centre, and two "
          "fans beat in the ratio view") {
    // The gradient of theta N / pi in world units, worked out by hand: N / (pi r) along the
    // direction of increasing angle about the layer's origin (a rotation turns the lines,
    // not the gradient's direction).
    const int lines = 36;
    const double ox = 4, oy = -3;
    const std::string layer = fmt::format(
        "layer {{ family = pencil; lines = {}; start = 2; origin = ({}, {}); rotation = 20deg }}\n",
        lines, ox, oy);
    auto program =
        test::compileOk(layer, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    const auto& L = program->layout;
    for (double r : {3.0, 10.0, 41.0})
        for (int k = 0; k < 12; ++k) {
            const double a = 0.1 + k * kPi / 6;
            const std::vector<double> out = probe.at(ox + r * std::cos(a), oy + r * std::sin(a));
            const double g = lines / (kPi * r);
            CAPTURE(r);
            CAPTURE(a);
            CHECK(out[L.gradXSlot(0)] == doctest::Approx(-g * std::sin(a)).epsilon(1e-6));
            CHECK(out[L.gradYSlot(0)] == doctest::Approx(g * std::cos(a)).epsilon(1e-6));
        }
    // Two fans 6 units apart: far from both centres their gradients nearly agree, so the
    // difference beat is slow and the ratio view is dark there (a fan's gradient read as
    // zero, as the sector index's is, would leave the whole frame white).
    const std::string fans = "scene { size = (60, 40) }\ncamera { zoom = 0.5 }\n"
                             "layer { family = pencil; lines = 60; start = 3; origin = (-3, 0) }\n"
                             "layer { family = pencil; lines = 60; start = 3; origin = (3, 0) }\n";
    auto ratio = test::compileOk(fans, {.view = sema::ViewMode::Ratio});
    auto jit = test::makeBackendOrSkip("jit");
    REQUIRE(jit);
    const Image img = test::renderScene(*ratio, *jit);
    double dark = 0;
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (std::abs(x - 30) < 12) continue; // the centres' lobes
            const float* p = img.row(y) + static_cast<size_t>(x) * img.channels;
            dark += (p[0] + p[1] + p[2]) / 3 < 0.25;
            ++n;
        }
    CHECK(dark / n > 0.5);
}

TEST_CASE("envelope of lattices: the same world points give the same value at zoom 1 and 4") {
    // Two taps of the lattice rule are wider than the pattern's band at both zooms, and a
    // dot keeps its true ink whatever its band (Envelope.cpp): nothing depends on the pixel.
    const std::string scene =
        "layer { family = hex_lattice; spacing = 6; stroke = 3 }\n"
        "layer { family = hex_lattice; spacing = 6; stroke = 3; rotation = 5deg }\n";
    // World points over a few superlattice cells.
    CHECK(test::zoomDifference(scene, 120.0, 80.0, "jit") <= 1.0);
}
