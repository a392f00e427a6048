// A crowd of members given by their distance that run two ways over the pixel, a grid's lines
// (docs/filtering.md, "A grid given by its distance"): read as two families of parallel lines,
// each by the index it runs by, and its mean in closed form. The distance is the nearer of
// the two families' distances, so the stroke d < h is the union of the two families' strokes;
// each family's mean is a phase family's (Prefilter.h, squareMeanInk) once its spacing and
// the pixel's place among its lines are known, and over a pixel that holds at least two of
// each the two cross at every offset alike, so their union is that of independent inks.
//
// The two directions come from the 4 x 4 parts (DistanceFamily.cpp reads them), each part's
// normal as a doubled angle (a normal and its opposite are one direction): the parts within
// 45 degrees of the pixel centre's normal are the first family's, the rest the second's, and
// each family's mean direction must stand for its parts (the length of their mean). A
// family's spacing is read from its part furthest from its own line, by probes along the
// other family's lines (where the other's distance stays as it is) until one reads the next
// line of its own (a normal parallel to the part's, a foot further along it).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/DistanceReading.h"

#include <span>
#include <vector>

namespace moire::lower {

// The parts' two directions, gathered over the parts as loop-carried values: how many parts
// are the second family's and their doubled angles' sums, and each family's part furthest
// from its line (its distance along its normal and its place in the pixel, world units
// along the pixel's sides).
class TwoDirections {
  public:
    static constexpr size_t kCarried = 9;
    // `centre`: the pixel centre's reading, whose direction is the first family's.
    TwoDirections(ir::Builder& b, const Reading& centre);
    std::vector<ir::ValueId> start() const;
    // A part at p: its distance along its normal `away`, its normal's doubled angle (cos2,
    // sin2), `some` where it has one. Returns the carried values with it counted.
    std::vector<ir::ValueId> add(std::span<const ir::ValueId> carried, ir::ValueId away,
                                 ir::ValueId cos2, ir::ValueId sin2, ir::ValueId some,
                                 PixelPoint p) const;

  private:
    ir::Builder& b_;
    ir::ValueId cos2_, sin2_;
};

// The grid's reading: `trust`, how far the parts run two ways and both families' spacings
// were found (0 to 1); `mean`, the pixel's mean ink in closed form; `members`, the sparser
// family's lines a pixel (by which the caller hands over to the closed form); and each way's
// index as a phase family's (members at its integers): its value at the pixel's centre, its
// gradient's length and world components per world unit, and its mean ink over the pixel
// (with which the union of fine layers lets the grid beat with another layer, as a lattice's
// lines do); `halfWidth`, the stroke's half-width across the lines in world units.
struct GridRead {
    ir::ValueId trust, mean, members;
    struct Way {
        ir::ValueId index, grad, gradX, gradY, mean;
    };
    Way ways[2];
    ir::ValueId halfWidth;
};
// A point whose nearest member crosses the centre's (where `found`), taken as the second
// family's start where no part reads that family (the parts alias with the grid).
struct CrossingStart {
    ir::ValueId found;
    PixelPoint at;
};
// Whether a few points of the pixel away from the parts' lattice (kCrossingLooks of them,
// moved from pixel to pixel by pixelShift) read a member crossing the direction whose
// doubled angle is (cos2, sin2), the parts' axis: the first such point. The 4 x 4 parts
// stand a quarter of a pixel apart, and at zooms where that is nearly a whole number of a
// grid's lines they all read the same relative place, and one family.
CrossingStart crossingSeen(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                           ir::ValueId cos2, ir::ValueId sin2);

// `carried`: TwoDirections' values after every part; (cos2, sin2) the sums of every part's
// doubled angle, `directed` how many have one. Read where `wanted` (else 0s).
GridRead gridRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                  ir::ValueId halfWidth, std::span<const ir::ValueId> carried, ir::ValueId cos2,
                  ir::ValueId sin2, ir::ValueId directed, ir::ValueId wanted,
                  const CrossingStart& crossing);

} // namespace moire::lower
