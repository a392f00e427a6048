// Table 5 of the spec (§9.3): the fidelity sweep. Every setting of the grid (five shapes x
// seven spacings x six offsets x four turns x four zooms) is sampled at 240 quasi-random
// points of a 1200 x 800 frame and solved by Sweep, Loose and Window (the shipped kernel's
// three variants, compiled once each per shape and run on the interpreter), each judged
// against the exhaustive reference (tests/reference). A point lost ink where the solver's
// coverage is more than 0.5 below the reference's; a setting has holes where more than
// 0.2% of its points lost ink. The trivial concentric settings (no offset, no turn) are
// skipped, and those where the reference needs more than 6,000 evaluations at some point
// are counted and excluded, as the paper does.
//
//   build/bin/experiments/table5_fidelity [--quick] [--neighbours N]
//
// --neighbours N adds a fourth column: Sweep with N members either side of its seed in
// place of the default 100.
#include "experiments/Harness.h"
#include "experiments/WalkingSettings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;
namespace ref = moire::reference;
using Solver = lower::WalkingVariant::Solver;

namespace {

constexpr double kReferenceCap = 6000; // evaluations per point past which a setting is excluded
constexpr double kLegible = 0.70;      // exact ink under which a pattern is legible (§9.3)

// The grid. Offsets are fractions of the spacing, along a direction 30 degrees above the x
// axis (for the triangle the walk then leads with a vertex less than fully, so m < ||delta||).
std::vector<WalkSetting> grid() {
    return walkGrid({.spacings = {1, 2, 4, 8, 16, 40, 80},
                     .offsets = {0, 0.1, 0.3, 0.6, 0.9, 1.2},
                     .directionsDeg = {30},
                     .turnsDeg = {0, 0.2, 1, 5},
                     .zooms = {0.15, 0.4, 1, 2}});
}

struct Column {
    std::string name;
    lower::WalkingVariant variant;
    // Over the measured settings:
    int holes = 0, inHoles = 0, legibleHoles = 0, invented = 0;
    double worst = 0, inWorst = 0, legibleWorst = 0, evaluations = 0;
    std::string worstLegible; // the setting of legibleWorst, and its points past the budget
    std::vector<std::unique_ptr<WalkingKernel>> kernels; // one per shape
};

} // namespace

int main(int argc, char** argv) {
    int neighbours = 0;
    std::vector<char*> rest{argv[0]};
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--neighbours") == 0 && i + 1 < argc)
            neighbours = std::atoi(argv[++i]);
        else
            rest.push_back(argv[i]);
    }
    const Options opt = parseOptions(static_cast<int>(rest.size()), rest.data(),
                                     "Table 5 of spec §9.3 (--neighbours N: also Sweep at N)");
    // Quick: every 23rd setting of the grid at 48 points (a spread over every shape, spacing,
    // offset, turn and zoom, since 23 is prime to the grid's sides).
    const int stride = opt.quick ? 23 : 1;
    const int points = opt.quick ? 48 : 240;

    std::vector<Column> columns;
    auto add = [&](std::string name, Solver solver, int n) {
        Column c;
        c.name = std::move(name);
        c.variant.solver = solver;
        c.variant.sweepNeighbours = n;
        for (int shape = 0; shape < 5; ++shape)
            c.kernels.push_back(std::make_unique<WalkingKernel>(shape, c.variant));
        columns.push_back(std::move(c));
    };
    const int sweepDefault = lower::WalkingVariant{}.sweepNeighbours;
    add(fmt::format("Sweep {}", sweepDefault), Solver::Sweep, sweepDefault);
    if (neighbours > 0 && neighbours != sweepDefault)
        add(fmt::format("Sweep {}", neighbours), Solver::Sweep, neighbours);
    add("Loose", Solver::Loose, sweepDefault);
    add("Window", Solver::Window, sweepDefault);

    const std::vector<std::array<double, 2>> pixels = haltonPixels(points, kFrameW, kFrameH);
    const std::vector<WalkSetting> all = grid();
    int trivial = 0, excluded = 0, measured = 0, legible = 0, sampled = 0;
    std::vector<double> exact(points);
    std::vector<char> inside(points);
    for (size_t k = 0; k < all.size(); k += stride) {
        const WalkSetting& s = all[k];
        ++sampled;
        if (s.offsetX == 0 && s.turnDeg == 0) {
            ++trivial;
            continue;
        }
        const ref::Walking w = walkingOf(s);
        // Any kernel gives the frame's camera and band; the reference needs only those.
        WalkingKernel& probe = *columns.back().kernels[s.shape];
        probe.set(s);
        bool over = false;
        double ink = 0;
        int within = 0;
        for (int i = 0; i < points && !over; ++i) {
            const auto [wx, wy] = probe.world(pixels[i][0], pixels[i][1]);
            const ref::Nearest n =
                ref::nearest(w, wx, wy, probe.guard(), static_cast<int64_t>(kReferenceCap) + 1);
            over = !n.complete || n.evaluations > kReferenceCap;
            exact[i] = coverageOf(n.distance, probe.band());
            ink += exact[i];
            inside[i] = intervalSpan(w, wx, wy, probe.guard()) <= lower::kWalkBudget;
            within += inside[i];
        }
        if (over) {
            ++excluded;
            continue;
        }
        ++measured;
        ink /= points;
        const bool clear = ink < kLegible;
        legible += clear;
        for (Column& c : columns) {
            WalkingKernel& kernel = *c.kernels[s.shape];
            kernel.set(s);
            int lost = 0, lostInside = 0, invented = 0;
            for (int i = 0; i < points; ++i) {
                const Solved got = kernel.at(pixels[i][0], pixels[i][1]);
                const double cover = coverageOf(got.distance, kernel.band());
                c.evaluations += got.evaluations;
                const bool gone = cover < exact[i] - 0.5;
                lost += gone;
                lostInside += gone && inside[i];
                invented += cover > exact[i] + 0.5;
            }
            const double share = double(lost) / points;
            const double shareInside = within ? double(lostInside) / within : 0.0;
            if (share > 0.002) ++c.holes;
            c.worst = std::max(c.worst, share);
            if (shareInside > 0.002) ++c.inHoles;
            c.inWorst = std::max(c.inWorst, shareInside);
            if (clear && share > 0.002) ++c.legibleHoles;
            if (clear && share > c.legibleWorst) {
                c.legibleWorst = share;
                c.worstLegible =
                    fmt::format("{} s {} offset {:.2f}s turn {}deg zoom {}: ink {:.2f}, {} past B",
                                sweepShapes()[s.shape].name, s.spacing,
                                std::hypot(s.offsetX, s.offsetY) / s.spacing, s.turnDeg, s.zoom,
                                ink, percent(1 - double(within) / points));
            }
            c.invented += invented > 0;
        }
    }

    printTitle(fmt::format("table5_fidelity: ink lost against the exhaustive reference, {} points "
                           "a setting{}",
                           points, opt.quick ? " (quick: every 23rd setting)" : ""));
    printRow("settings in the grid (sampled)", "3,360", std::to_string(sampled));
    printRow("trivial (concentric) settings skipped", "140", std::to_string(trivial));
    printRow("excluded: reference over 6,000 evaluations", "819", std::to_string(excluded));
    printRow("measured settings", "2,401", std::to_string(measured));
    printRow("legible settings (exact ink < 70%)", "1,534", std::to_string(legible));
    // The paper's column: holes, worst; in interval: settings, worst; legible: settings, worst.
    using Paper = std::array<const char*, 6>;
    for (const Column& c : columns) {
        Paper p{"-", "-", "-", "-", "-", "-"};
        if (c.name == fmt::format("Sweep {}", sweepDefault))
            p = {"160", "32.9%", "41", "29.6%", "3", "4.2%"};
        if (c.name == "Loose") p = {"46", "48.3%", "13", "48.3%", "0", "0.0%"};
        if (c.name == "Window") p = {"146", "13.8%", "0", "0.0%", "0", "0.0%"};
        const double perPoint = c.evaluations / std::max(1.0, double(measured) * points);
        printRow(c.name + ": evaluations of rho per point", "-", fmt::format("{:.1f}", perPoint));
        printRow(c.name + ": settings with holes", p[0], std::to_string(c.holes));
        printRow(c.name + ": worst ink lost", p[1], percent(c.worst));
        printRow(c.name + ": in interval: settings", p[2], std::to_string(c.inHoles));
        printRow(c.name + ": in interval: worst", p[3], percent(c.inWorst));
        printRow(c.name + ": legible: settings", p[4], std::to_string(c.legibleHoles));
        printRow(c.name + ": legible: worst", p[5], percent(c.legibleWorst));
        printRow(c.name + ": settings where ink was invented", "0", std::to_string(c.invented));
        if (!c.worstLegible.empty()) std::printf("    worst legible: %s\n", c.worstLegible.c_str());
    }
    const Column& window = columns.back();
    bool noneInvented = true;
    for (const Column& c : columns) noneInvented = noneInvented && c.invented == 0;
    // Legible settings are not asserted: in this grid some lie past the budget (see
    // docs/experiments.md), where Window strides and the spec claims nothing.
    return verdict(measured > 0 && window.inHoles == 0 && noneInvented,
                   "Window must lose no ink where the interval fits the budget, and no solver may "
                   "invent ink");
}
