// The mean filter (docs/filtering.md, issue: members finer than pixels): fine lines (upright
// and slanted), fine circles and a fine spiral rendered on the JIT at one sample a pixel over two
// decades of zoom, point-sampled and with the filtered mean, each pixel against a 256-sample
// box-filtered reference of the exact field (ink wherever the world distance to the nearest member
// is under half the stroke), computed here in double from the families' own geometry. Then two
// walking families that the solver answers in closed form (§7.5: translated circles, translated
// hexagons), whose reference is the exhaustive one of tests/reference (every member within reach
// of the pixel gathered from its definition, Eq. 24). The mean absolute error must be at least
// 10 times lower with the mean where members are unresolved (one member a pixel or more), and no
// worse where they are resolved (4 pixels a member or more).
#include "experiments/Harness.h"
#include "experiments/RenderedInk.h"
#include "tests/reference/WalkingReference.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

constexpr double kSpacing = 1.0, kStroke = 0.2; // every member inks 20% of its period
constexpr double kSlant = 30.0;                 // degrees

enum Family { kLines, kSlanted, kCircles, kSpiral, kWalkingCircles, kWalkingHexagons, kFamilies };
const char* const kFamilyNames[kFamilies] = {"lines",
                                             "slanted lines",
                                             "circles",
                                             "spiral",
                                             "walking circles, offset (0.3, 0.1)",
                                             "walking hexagons, offset (0.3, 0.2)"};
const char* const kFamilyLayers[kFamilies] = {"family = lines",
                                              "family = lines; angle = 30deg",
                                              "family = circles",
                                              "family = spiral",
                                              "family = circles; offset = (0.3, 0.1)",
                                              "family = hexagons; offset = (0.3, 0.2)"};

// The walking families as the exhaustive reference writes them (no turn: closed forms).
reference::Walking walkingOf(Family family) {
    reference::Walking w;
    w.facets = family == kWalkingCircles ? 0 : 6;
    w.spacing = kSpacing;
    w.offsetX = 0.3, w.offsetY = family == kWalkingCircles ? 0.1 : 0.2;
    return w;
}

std::string sceneText(Family family, double zoom, int width, int height, const char* filter) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "scene { size = (%d, %d); filter = %s }\ncamera { zoom = %.17g }\n"
                  "layer a { %s; spacing = %g; stroke = %g }\n",
                  width, height, filter, zoom, kFamilyLayers[family], kSpacing, kStroke);
    return buf;
}

// The exact field's ink at a world point: the distance to the nearest member (lines
// x cos a + y sin a = n s; circles r = n s, member 0 the centre point) under half the stroke.
// The spiral's members are r - s theta / 2 pi = n s; its distance is the index residual over
// the index's gradient, |(1/s, 1 / (2 pi r))| (to first order: the arms are straight and evenly
// spaced over the stroke's width once r is a few spacings).
bool exactInk(Family family, double x, double y) {
    if (family == kSpiral) {
        const double r = std::hypot(x, y);
        const double index = (r - kSpacing * std::atan2(y, x) / (2 * M_PI)) / kSpacing;
        const double grad = std::hypot(1.0 / kSpacing, 1.0 / (2 * M_PI * std::max(r, 1e-12)));
        return std::abs(index - std::round(index)) / grad < 0.5 * kStroke;
    }
    const double a = kSlant * M_PI / 180.0;
    const double phase = family == kLines     ? x
                         : family == kSlanted ? x * std::cos(a) + y * std::sin(a)
                                              : std::hypot(x, y);
    const double index = phase / kSpacing;
    return std::abs(index - std::round(index)) * kSpacing < 0.5 * kStroke;
}

// A walking family's reference: each pixel's 256-sample mean of the union of its members'
// strokes, over the members that can reach the pixel (gathered once at its middle: the
// residual is 1-Lipschitz in p, so they are those within the half-stroke and half the
// pixel's diagonal).
std::vector<double> walkingReference(Family family, double zoom, int width, int height) {
    const reference::Walking w = walkingOf(family);
    const double pixel = 1.0 / zoom, half = 0.5 * kStroke;
    std::vector<double> out(size_t(width) * height);
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            const double cx = (px + 0.5 - 0.5 * width) * pixel,
                         cy = (0.5 * height - py - 0.5) * pixel;
            const std::vector<int64_t> near =
                reference::membersWithin(w, cx, cy, half + pixel * std::sqrt(0.5));
            int count = 0;
            for (int j = 0; j < kReferenceSamples && !near.empty(); ++j) {
                const auto [u, v] = referenceSample(j);
                const double x = (px + u - 0.5 * width) * pixel,
                             y = (0.5 * height - (py + v)) * pixel;
                for (int64_t n : near)
                    if (std::abs(reference::residual(w, x, y, n)) < half) {
                        ++count;
                        break;
                    }
            }
            out[size_t(py) * width + px] = double(count) / kReferenceSamples;
        }
    return out;
}

// The reference: each pixel's 256-sample mean of the exact ink.
std::vector<double> exactReference(Family family, double zoom, int width, int height) {
    if (family == kWalkingCircles || family == kWalkingHexagons)
        return walkingReference(family, zoom, width, height);
    return boxReference(width, height, zoom,
                        [&](double x, double y) { return exactInk(family, x, y); });
}

// The mean absolute difference between the rendered ink and the reference.
double renderedError(Backend& jit, Family family, double zoom, int width, int height,
                     const char* filter, const std::vector<double>& ref) {
    return meanAbsError(
        renderedInk(jit, "filter_mean.moire", sceneText(family, zoom, width, height, filter)), ref);
}

} // namespace

int main(int argc, char** argv) {
    Options o = parseOptions(argc, argv,
                             "fine lines and circles over two decades of zoom: the error of "
                             "point sampling and of the filtered mean against 256 samples");
    const int width = o.quick ? 96 : 320, height = o.quick ? 64 : 200;
    const std::vector<double> zooms = zoomSweep(o.quick);
    auto jit = makeBackend("jit");
    bool ok = true;
    std::string why;
    for (int f = 0; f < kFamilies; ++f) {
        const Family family = static_cast<Family>(f);
        std::printf("\nfine %s: spacing 1, stroke 0.2, %d x %d pixels; mean absolute error "
                    "against 256 samples\n",
                    kFamilyNames[f], width, height);
        std::printf("  %8s %12s %12s %12s %8s\n", "zoom", "members/px", "point", "mean", "ratio");
        for (double zoom : zooms) {
            const double members = 1.0 / (kSpacing * zoom);
            std::vector<double> ref = exactReference(family, zoom, width, height);
            double point = renderedError(*jit, family, zoom, width, height, "point", ref);
            double mean = renderedError(*jit, family, zoom, width, height, "mean", ref);
            std::printf("  %8.3f %12.3f %12.4f %12.4f %8.1f\n", zoom, members, point, mean,
                        point / std::max(mean, 1e-9));
            if (members >= 1.0 && !(mean * 10.0 <= point)) {
                ok = false;
                why = std::string(kFamilyNames[f]) + ": the mean not 10x better where unresolved";
            }
            if (members <= 0.25 && !(mean <= point + 1e-6)) {
                ok = false;
                why = std::string(kFamilyNames[f]) + ": the mean worse where resolved";
            }
        }
    }
    return verdict(ok, why);
}
