// What the walking-family experiments share (spec §9.3, §9.6): the parameter grid's shapes,
// one setting of it, the shipped kernel compiled once per shape and solver variant and set
// to a setting through its params (no recompiling), quasi-random sample points, and the
// renderer's coverage, so that the solver can be judged against tests/reference.
#pragma once

#include "compiler/Compile.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/WalkingVariant.h"
#include "runtime/FrameEval.h"
#include "tests/reference/WalkingReference.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace moire::exp {

// A shape of the sweep: the family's name, its side count (0: circle) and any extra property.
struct Shape {
    const char* name;
    const char* family;
    int facets;
    const char* extra; // e.g. "sides = 9; " for the nonagon
};
// Circle, triangle, square, hexagon, nonagon.
const std::array<Shape, 5>& sweepShapes();

// One setting of the grid. The frame is the scene's: kFrameW x kFrameH pixels at `zoom`.
struct WalkSetting {
    int shape = 0; // into sweepShapes()
    double spacing = 10, offsetX = 0, offsetY = 0, turnDeg = 0, zoom = 1;
    double phase = 0;
};
constexpr int kFrameW = 1200, kFrameH = 800; // the spec's measurement grid (§9.1)
constexpr double kStroke = 1.5;              // stroke width in world units

// The grid's axes. Offsets are fractions of the spacing, in each direction (degrees from
// the x axis); a zero offset is taken once, in the first direction.
struct GridAxes {
    std::vector<double> spacings, offsets, directionsDeg, turnsDeg, zooms;
};
// Every shape x spacing x offset x direction x turn x zoom, in that nesting order.
std::vector<WalkSetting> walkGrid(const GridAxes& axes);
// §9.6's broad sweep (Fig. 16; the strided band and its mean): five shapes x nine spacings x
// thirteen offsets in three directions x six turns x five zooms, less the concentric settings
// (no offset, no turn), which have no interval.
std::vector<WalkSetting> intervalGrid();

// The family as the reference sees it.
reference::Walking walkingOf(const WalkSetting& s);

// A point the kernel solved: the clamped distance, Theorem 4's interval as the kernel
// computed it (aux0, aux1: n_lo and the uncapped n_hi) and its evaluations of rho.
struct Solved {
    double distance = 0, nLo = 0, nHi = 0;
    double evaluations = 0;
    double ink = 0; // the pixel's ink as drawn (1 - its grey: black ink on white paper)
};

// The shipped kernel (compiled through compileScene, run on the interpreter in its counting
// mode) for one shape and one solver variant; set() moves it to a setting by writing its
// params into the literal table, so one compile serves the whole grid.
class WalkingKernel {
  public:
    // `filter`: the stroke filter the kernel is compiled with (the scene's default, the
    // mean, when not given); Solved::ink is drawn under it.
    WalkingKernel(int shape, const lower::WalkingVariant& variant,
                  std::optional<sema::FilterMode> filter = std::nullopt);
    ~WalkingKernel();
    void set(const WalkSetting& s);
    Solved at(double pixelX, double pixelY);
    // The world point under a pixel, and the stroke band and guard there, for the reference.
    std::array<double, 2> world(double pixelX, double pixelY) const;
    lower::StrokeBandT<double> band() const { return band_; }
    double guard() const { return guard_; }
    double pixelSize() const { return pixel_; } // world units a pixel

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    lower::StrokeBandT<double> band_{};
    double guard_ = 0, pixel_ = 1;
};

// n quasi-random pixel positions over a w x h frame (the Halton sequence in bases 2 and 3,
// from index 1), so that every setting is sampled at the same well-spread points.
std::vector<std::array<double, 2>> haltonPixels(int n, int w, int h);

// The renderer's coverage of a distance d for a stroke band (1 - smoothstep, Eq. 4).
double coverageOf(double d, const lower::StrokeBandT<double>& band);

// Theorem 4's interval span at p in double, independently of the kernel: n_hi - n_lo + 1
// with the per-branch upper bounds of §7.6 (infinite at m = s).
double intervalSpan(const reference::Walking& w, double px, double py, double guard);

} // namespace moire::exp
