// The union of fine layers under the mean filter (docs/filtering.md, "Fine layers together"):
// two fine families whose beat is coarse (upright lines 1 and 1.05 apart, concentric circles
// as far apart, the same rings given by their distance alone (`family f { distance = ... }`,
// whose index the mean filter reads from the crowd: DistanceFamily.h), and a fork grating:
// lines beside their twin with five members gained around the origin) rendered on the JIT at one
// sample a pixel over two decades of zoom, point-sampled and with the filtered mean, against a
// 256-sample box-filtered reference of the exact pair field (ink wherever either family's stroke
// covers the point), computed here in double from the families' geometry. Two figures: (a) the
// fringe's contrast, the amplitude of the beat's fundamental in the picture, 2 |mean over the
// pixels of ink x exp(-2 pi i D)|, D the beat's index at the pixel's centre (the same projection
// for the reference and the renders), and (b) each pixel's mean absolute error. The mean must keep
// the fringe where the members are unresolved and the beat is not (within 20% of the reference's
// contrast), its error must be at least 10 times lower than point sampling's where the members are
// unresolved, and no worse where they are resolved.
#include "experiments/Harness.h"
#include "experiments/RenderedInk.h"

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

constexpr double kSpacing = 1.0, kOther = 1.05, kStroke = 0.3; // each inks 30% of its period
constexpr double kForkGain = 5.0; // members the fork gains around the origin

enum Pair { kLines, kCircles, kRings, kFork, kPairs };
const char* const kPairNames[kPairs] = {"lines 1 and 1.05", "circles 1 and 1.05",
                                        "rings given by their distance, 1 and 1.05",
                                        "fork grating, spacing 1"};

std::string sceneText(Pair pair, double zoom, int width, int height, const char* filter) {
    char layers[512];
    switch (pair) {
    case kLines:
    case kCircles: {
        const char* family = pair == kLines ? "lines" : "circles";
        std::snprintf(layers, sizeof layers,
                      "layer a { family = %s; spacing = %g; stroke = %g }\n"
                      "layer b { family = %s; spacing = %g; stroke = %g }\n",
                      family, kSpacing, kStroke, family, kOther, kStroke);
        break;
    }
    case kRings:
        std::snprintf(layers, sizeof layers,
                      "family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
                      "layer a { family = rings; spacing = %g; stroke = %g }\n"
                      "layer b { family = rings; spacing = %g; stroke = %g }\n",
                      kSpacing, kStroke, kOther, kStroke);
        break;
    default:
        std::snprintf(layers, sizeof layers,
                      "layer a { family = lines; spacing = %g; stroke = %g }\n"
                      "layer b { family = lines; spacing = %g; stroke = %g; field = theta / tau; "
                      "gain = %g }\n",
                      kSpacing, kStroke, kSpacing, kStroke, kForkGain);
    }
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "scene { size = (%d, %d); filter = %s }\ncamera { zoom = %.17g }\n%s", width,
                  height, filter, zoom, layers);
    return buf;
}

// The two families' indices at a world point (member n where the index is n). The fork's
// encoded layer has the phase x - gain spacing theta / tau (docs/language.md, fields as an
// instrument), theta in (-pi, pi].
void indices(Pair pair, double x, double y, double& f1, double& f2) {
    switch (pair) {
    case kLines:
        f1 = x / kSpacing, f2 = x / kOther;
        return;
    case kCircles:
    case kRings:
        f1 = std::hypot(x, y) / kSpacing, f2 = std::hypot(x, y) / kOther;
        return;
    default:
        f1 = x / kSpacing;
        f2 = x / kSpacing - kForkGain * std::atan2(y, x) / (2.0 * M_PI);
    }
}

// The exact pair's ink: either stroke covers the point, the world distance to a member (the
// index's residual over its gradient's length) under half the stroke. The lines' and circles'
// indices run at 1 / spacing a world unit; the fork's gradient is (1 / s, 0) less
// gain / tau times grad theta = (-y, x) / r^2, and its strokes keep their thickness.
bool exactInk(Pair pair, double x, double y) {
    double f1, f2;
    indices(pair, x, y, f1, f2);
    double grad2 = 1.0 / kOther;
    if (pair == kFork) {
        const double r2 = std::max(x * x + y * y, 1e-12), k = kForkGain / (2.0 * M_PI);
        grad2 = std::hypot(1.0 / kSpacing + k * y / r2, -k * x / r2);
    }
    return std::abs(f1 - std::round(f1)) * kSpacing < 0.5 * kStroke ||
           std::abs(f2 - std::round(f2)) / grad2 < 0.5 * kStroke;
}

// Pixel centre to world: the origin at the frame's middle, a pixel 1 / zoom units, y up.
void world(double px, double py, double zoom, int width, int height, double& x, double& y) {
    x = (px - 0.5 * width) / zoom;
    y = (0.5 * height - py) / zoom;
}

std::vector<double> reference(Pair pair, double zoom, int width, int height) {
    return boxReference(width, height, zoom,
                        [&](double x, double y) { return exactInk(pair, x, y); });
}

// The fringe's contrast: 2 |mean of ink exp(-2 pi i D)|, D = f1 - f2 at the pixel's centre.
double fringeContrast(Pair pair, const std::vector<double>& ink, double zoom, int width,
                      int height) {
    std::complex<double> sum = 0.0;
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            double x, y, f1, f2;
            world(px + 0.5, py + 0.5, zoom, width, height, x, y);
            indices(pair, x, y, f1, f2);
            sum += ink[size_t(py) * width + px] * std::polar(1.0, -2.0 * M_PI * (f1 - f2));
        }
    return 2.0 * std::abs(sum) / (double(width) * height);
}

// The rendered ink of the pair's scene under `filter`.
std::vector<double> rendered(Backend& jit, Pair pair, double zoom, int width, int height,
                             const char* filter) {
    return renderedInk(jit, "fine_pairs.moire", sceneText(pair, zoom, width, height, filter));
}

} // namespace

int main(int argc, char** argv) {
    Options o = parseOptions(argc, argv,
                             "two fine families whose beat is coarse over two decades of zoom: "
                             "fringe contrast and error of point sampling and of the mean "
                             "against 256 samples");
    const int width = o.quick ? 96 : 320, height = o.quick ? 64 : 200;
    const std::vector<double> zooms = zoomSweep(o.quick);
    auto jit = makeBackend("jit");
    bool ok = true;
    std::string why;
    auto fail = [&](Pair pair, const std::string& what) {
        ok = false;
        why = std::string(kPairNames[pair]) + ": " + what;
    };
    for (int p = 0; p < kPairs; ++p) {
        const Pair pair = static_cast<Pair>(p);
        std::printf("\n%s: stroke %g, %d x %d pixels; fringe contrast (reference, point, mean) "
                    "and mean absolute error against 256 samples\n",
                    kPairNames[p], kStroke, width, height);
        std::printf("  %8s %10s %8s %8s %8s %8s %10s %10s %8s\n", "zoom", "members/px", "beat px",
                    "ref", "point", "mean", "err point", "err mean", "ratio");
        for (double zoom : zooms) {
            const double members = 1.0 / (kSpacing * zoom);
            // The straight pairs' beat period is 21 units, so 21 zoom pixels; the fork's is
            // 2 pi r / 5 at radius r, shown at the frame's half-height.
            const double beat = pair == kFork ? 2.0 * M_PI * 0.5 * height / kForkGain
                                              : zoom / (1.0 / kSpacing - 1.0 / kOther);
            std::vector<double> ref = reference(pair, zoom, width, height);
            std::vector<double> point = rendered(*jit, pair, zoom, width, height, "point");
            std::vector<double> mean = rendered(*jit, pair, zoom, width, height, "mean");
            const double cRef = fringeContrast(pair, ref, zoom, width, height);
            const double cPoint = fringeContrast(pair, point, zoom, width, height);
            const double cMean = fringeContrast(pair, mean, zoom, width, height);
            const double ePoint = meanAbsError(point, ref), eMean = meanAbsError(mean, ref);
            std::printf("  %8.3f %10.3f %8.1f %8.4f %8.4f %8.4f %10.4f %10.4f %8.1f\n", zoom,
                        members, beat, cRef, cPoint, cMean, ePoint, eMean,
                        ePoint / std::max(eMean, 1e-9));
            if (members >= 1.0 && !(eMean * 10.0 <= ePoint))
                fail(pair, "the mean not 10x better where unresolved");
            if (members <= 0.25 && !(eMean <= ePoint + 1e-6))
                fail(pair, "the mean worse where resolved");
            if (members >= 1.0 && beat >= 4.0 && cRef > 0.02 &&
                !(std::abs(cMean - cRef) <= 0.2 * cRef))
                fail(pair, "the fringe's contrast lost where the beat is resolved");
        }
    }
    return verdict(ok, why);
}
