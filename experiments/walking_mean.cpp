// §9.6 of the spec under the mean filter (docs/filtering.md, "Walking families past the
// budget"): where Theorem 4's interval is wider than the budget the scan strides and loses ink;
// the filter hands the drawn ink over to the family's crowd estimate (WalkingCrowd.cpp,
// WalkingDensity.cpp).
//
//   build/bin/experiments/walking_mean [--quick]
//
// 1. The strided band of interval_span's grid (settings past the budget whose solver scans),
//    a stratified sample of it (legible, under 50% ink, and saturated), each at quasi-random
//    pixels. Per pixel, four numbers:
//     - point: the shipped kernel (B = 1024) with filter = point, the floored stroke;
//     - mean: the same kernel with filter = mean (the default);
//     - the paper's reference: the solver with the budget raised to 131072 (stride 1 over the
//       capped span), point-sampled with the same floored stroke: the protocol of §9.6;
//     - the exact mean: the pixel's box mean (256 samples on a rank-1 lattice) of the stroke
//       as written (half-width t / 2, no floor), each sample's distance from the exhaustive
//       double reference (tests/reference) over the members the raised solver walks
//       (n < n_lo + 2^16).
//    Ink lost per setting is 1 - ours / reference over its pixels; the paper's figures (4.6%
//    mean, 48.8% worst, 28.7% legible) are point against the paper's reference.
// 2. The two cases of the issue: triangles whose drift equals their spacing at a 0.5 degree
//    turn, and circles offset 7.8 at spacing 8 at a 1 degree turn, over a grid of pixels:
//    mean ink and the share of pixels off the exact mean by more than 8/255, point and mean.
#include "compiler/lower/WalkingFamily.h"
#include "experiments/Harness.h"
#include "experiments/RenderedInk.h"
#include "experiments/WalkingSettings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;
namespace ref = moire::reference;

namespace {

constexpr double kLegible = 0.5;
constexpr double kSpanCap = 65536; // lower::kWalkSpanCap

struct Kernels {
    std::vector<std::unique_ptr<WalkingKernel>> point, mean, raised;
    Kernels() {
        lower::WalkingVariant wide;
        wide.budget = 131072;
        for (int shape = 0; shape < 5; ++shape) {
            point.push_back(std::make_unique<WalkingKernel>(shape, lower::WalkingVariant{},
                                                            sema::FilterMode::Point));
            mean.push_back(std::make_unique<WalkingKernel>(shape, lower::WalkingVariant{},
                                                           sema::FilterMode::Mean));
            raised.push_back(std::make_unique<WalkingKernel>(shape, wide, sema::FilterMode::Point));
        }
    }
    void set(const WalkSetting& s) {
        point[s.shape]->set(s);
        mean[s.shape]->set(s);
        raised[s.shape]->set(s);
    }
};

struct Pixel {
    double point = 0, mean = 0, paper = 0, exact = 0;
    double span = 0;
};

// The pixel's box mean of the stroke as written (half-width t / 2, no floor) over the
// reference's kReferenceSamples samples, each sample's distance taken over the members the
// raised solver walks (n < cap). One scan at the pixel's middle gathers every member that
// can reach any of its samples (ref::membersWithin), so each sample looks at those alone:
// the answer ref::nearest would give at every sample, at a fraction of the cost where the
// span is thousands of members wide.
double exactMean(const WalkingKernel& p, const ref::Walking& w, double x, double y, int64_t cap) {
    const double half = kStroke / 2;
    const auto [cx, cy] = p.world(x, y);
    const std::vector<int64_t> near =
        ref::membersWithin(w, cx, cy, half + p.pixelSize() * std::sqrt(0.5), cap);
    int inked = 0;
    for (int j = 0; j < kReferenceSamples; ++j) {
        const auto [u, v] = referenceSample(j);
        const auto [wx, wy] = p.world(x - 0.5 + u, y - 0.5 + v);
        inked += std::any_of(near.begin(), near.end(), [&](int64_t n) {
            return std::fabs(ref::residual(w, wx, wy, n)) < half;
        });
    }
    return double(inked) / kReferenceSamples;
}

// The four numbers at one pixel (the setting already set).
// Without `paper`, the raised solver is not run (its interval is the shipped one's).
Pixel measure(Kernels& k, const WalkSetting& s, double x, double y, bool paper = true) {
    Pixel out;
    WalkingKernel& p = *k.point[s.shape];
    const Solved a = p.at(x, y);
    out.point = a.ink;
    out.span = std::min(kSpanCap, std::max(0.0, a.nHi - a.nLo) + 1);
    out.mean = k.mean[s.shape]->at(x, y).ink;
    if (paper) out.paper = k.raised[s.shape]->at(x, y).ink;
    out.exact = exactMean(p, walkingOf(s), x, y, static_cast<int64_t>(a.nLo + kSpanCap));
    return out;
}

// Ink lost: 1 - ours / reference (negative: ink invented).
double lost(double ours, double reference) {
    return reference > 0 ? 1 - ours / reference : 0.0;
}

struct Tally {
    double meanLoss = 0, worst = 0, worstInk = 0, worstLegible = 0, worstInvented = 0;
    int settings = 0;
    void add(double ours, double reference) {
        const double l = lost(ours, reference);
        meanLoss += std::max(0.0, l);
        ++settings;
        if (l > worst) worst = l, worstInk = reference;
        if (reference < kLegible) worstLegible = std::max(worstLegible, l);
        worstInvented = std::max(worstInvented, -l);
    }
    std::string meanText() const { return percent(settings ? meanLoss / settings : 0); }
};

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "§9.6 of the spec under the mean filter");
    Kernels k;
    // The band is found with `points` pixels a setting and measured at `measured` (the first
    // `points` of them the same): where a setting's strokes are resolved its exact ink is a
    // few lines, and the pixels that happen to meet them set a 128-pixel figure to within 20%.
    const int points = opt.quick ? 12 : 128, measured = opt.quick ? 12 : 512;
    const std::vector<std::array<double, 2>> pixels = haltonPixels(measured, kFrameW, kFrameH);

    // Part 1: the strided band, found as interval_span finds it (90th-percentile span past
    // the budget, a solver that scans), then sampled.
    const std::vector<WalkSetting> all = intervalGrid();
    const size_t step = opt.quick ? 211 : 7;
    std::vector<WalkSetting> legible, solid;
    std::vector<double> spans(points);
    for (size_t i = 0; i < all.size(); i += step) {
        const WalkSetting& s = all[i];
        const ref::Walking w = walkingOf(s);
        const bool closedForm =
            s.turnDeg == 0 && (w.facets == 0 || ref::drift(w) <= s.spacing + lower::kWalkMarginal);
        if (closedForm) continue;
        WalkingKernel& p = *k.point[s.shape];
        p.set(s);
        double ink = 0;
        for (int j = 0; j < points; ++j) {
            const Solved v = p.at(pixels[j][0], pixels[j][1]);
            spans[j] = std::min(kSpanCap, std::max(0.0, v.nHi - v.nLo) + 1);
            ink += v.ink;
        }
        std::sort(spans.begin(), spans.end());
        if (spans[static_cast<size_t>(std::ceil(0.9 * points)) - 1] <= lower::kWalkBudget) continue;
        (ink / points < kLegible ? legible : solid).push_back(s);
    }
    const size_t wantLegible = opt.quick ? 4 : 60, wantSolid = opt.quick ? 3 : 40;
    std::vector<WalkSetting> sample;
    for (const auto* band : {&legible, &solid}) {
        const size_t want = band == &legible ? wantLegible : wantSolid;
        const size_t every = std::max<size_t>(1, (band->size() + want - 1) / want);
        for (size_t j = 0; j < band->size(); j += every) sample.push_back((*band)[j]);
    }

    Tally paper, pointExact, meanExact;
    double meanAbs = 0, pointAbs = 0;
    for (const WalkSetting& s : sample) {
        // MOIRE_WALKING_MEAN_TURN=10: only the settings at that turn (in degrees) are measured.
        const char* only = std::getenv("MOIRE_WALKING_MEAN_TURN");
        if (only && s.turnDeg != std::atof(only)) continue;
        k.set(s);
        double point = 0, mean = 0, raised = 0, exact = 0;
        for (int j = 0; j < measured; ++j) {
            const Pixel px = measure(k, s, pixels[j][0], pixels[j][1]);
            point += px.point, mean += px.mean, raised += px.paper, exact += px.exact;
            pointAbs += std::fabs(px.point - px.exact);
            meanAbs += std::fabs(px.mean - px.exact);
        }
        if (std::getenv("MOIRE_WALKING_MEAN_VERBOSE"))
            std::printf("  %s s=%g off=(%g, %g) turn=%g zoom=%g: point %.3f mean %.3f paper %.3f "
                        "exact %.3f\n",
                        sweepShapes()[s.shape].name, s.spacing, s.offsetX, s.offsetY, s.turnDeg,
                        s.zoom, point / measured, mean / measured, raised / measured,
                        exact / measured);
        paper.add(point / measured, raised / measured);
        pointExact.add(point / measured, exact / measured);
        meanExact.add(mean / measured, exact / measured);
    }
    const double pixelsMeasured = double(sample.size()) * measured;
    printTitle(fmt::format("walking_mean: §9.6 under the mean filter, {} strided settings "
                           "({} legible, {} saturated found){}",
                           sample.size(), legible.size(), solid.size(),
                           opt.quick ? " (quick)" : ""));
    std::printf("  columns: the paper | point against the paper's reference (B = 131072, "
                "floored) | point, mean filter against the exact box mean\n");
    auto row = [&](const char* what, const char* fig, auto get) {
        printRow(what, fig,
                 fmt::format("{} | {} | {}", get(paper), get(pointExact), get(meanExact)));
    };
    row("mean ink lost", "4.6%", [](const Tally& t) { return t.meanText(); });
    row("worst ink lost", "48.8%", [](const Tally& t) { return percent(t.worst); });
    row("  its reference ink", "1.00",
        [](const Tally& t) { return fmt::format("{:.2f}", t.worstInk); });
    row("worst ink lost, legible", "28.7%", [](const Tally& t) { return percent(t.worstLegible); });
    row("worst ink invented", "0", [](const Tally& t) { return percent(t.worstInvented); });
    printRow("a pixel's mean |ink - exact|: point, mean", "-",
             fmt::format("{:.3f}, {:.3f}", pointAbs / pixelsMeasured, meanAbs / pixelsMeasured));

    // Part 2: the two cases, over a grid of pixels.
    struct Case {
        const char* name;
        WalkSetting s;
    };
    WalkSetting tri;
    tri.shape = 1, tri.spacing = 10, tri.offsetX = -10, tri.turnDeg = 0.5; // rho(-delta) = s
    WalkSetting circ;
    circ.shape = 0, circ.spacing = 8, circ.offsetX = 7.8, circ.turnDeg = 1;
    const int cols = opt.quick ? 12 : 48, rows = opt.quick ? 8 : 32;
    bool casesBetter = true;
    for (const Case& c : {Case{"triangles, drift = spacing, 0.5 deg", tri},
                          Case{"circles, offset 7.8, spacing 8, 1 deg", circ}}) {
        k.set(c.s);
        double point = 0, mean = 0, exact = 0;
        int pointOff = 0, meanOff = 0;
        for (int i = 0; i < cols; ++i)
            for (int j = 0; j < rows; ++j) {
                const double x = (i + 0.5) * kFrameW / cols, y = (j + 0.5) * kFrameH / rows;
                const Pixel px = measure(k, c.s, std::floor(x) + 0.5, std::floor(y) + 0.5, false);
                point += px.point, mean += px.mean, exact += px.exact;
                pointOff += std::fabs(px.point - px.exact) > 8.0 / 255;
                meanOff += std::fabs(px.mean - px.exact) > 8.0 / 255;
                if (std::getenv("MOIRE_WALKING_MEAN_VERBOSE") &&
                    std::fabs(px.mean - px.exact) > 8.0 / 255)
                    std::printf("  off at (%g, %g): point %.3f mean %.3f exact %.3f span %g\n", x,
                                y, px.point, px.mean, px.exact, px.span);
            }
        const double n = double(cols) * rows;
        printRow(fmt::format("{}: ink point, mean, exact", c.name), "0.22 / - / 0.95 (tri.)",
                 fmt::format("{:.2f}, {:.2f}, {:.2f}", point / n, mean / n, exact / n));
        printRow("  pixels off by > 8/255: point, mean", "85% (tri.), 9% (circ.)",
                 fmt::format("{}, {}", percent(pointOff / n), percent(meanOff / n)));
        // The ink nearer the exact mean's, and for the circles fewer pixels off it (the
        // triangles' periodic members stand 2.6 pixels apart: there the mean's even grey is off
        // the exact picture's lines pixel by pixel, as point sampling's missing lines are).
        casesBetter = casesBetter && std::fabs(mean - exact) < std::fabs(point - exact);
        if (c.s.shape == 0) casesBetter = casesBetter && meanOff < pointOff;
    }

    // The goal (worst loss under 5%) is printed, not asserted: see docs/experiments.md.
    const bool ok = !sample.empty() && meanExact.meanLoss < 0.5 * pointExact.meanLoss &&
                    meanExact.worstInvented < 0.10 && meanAbs < 0.5 * pointAbs && casesBetter;
    return verdict(ok, "under the mean filter the strided band must lose less than half the ink "
                       "point sampling loses against the exact mean, invent under 10% of it, halve "
                       "point sampling's error pixel by pixel, and draw the issue's cases nearer "
                       "their exact ink");
}
