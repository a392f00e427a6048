// A family given by its distance (`family f { distance = ... }`) under the mean filter
// (docs/filtering.md, "Families given by their distance"). Such a family gives the distance to
// its nearest member and nothing of its other members, so the distance form (Prefilter.h:
// distanceMeanInk) read the pixel as one straight member's stroke: it counted one member
// where several crowd into the pixel, and one side of a ridge where the pixel straddles the
// line between two members' reach (a grid's lines crossing, a ring's neighbour), and it took
// the distance as a Euclidean one where the family's own is not (|grad d| != 1: the stroke
// d < h is 2h / |grad d| wide, not 2h).
//
// Any pixel's ink is the share of its points nearer than h to a member, which the nearest
// distance alone says (a point within h of some member is within h of its nearest). So where
// the distance runs as one straight member's across the pixel, d(p + o) = |d + grad d . o| to
// first order, the distance form is the pixel's mean once the distance is read in its own
// units (d / |grad d|, the stroke h / |grad d| to either side). Where a corner reads off that
// (another member is nearer there, or the member bends) and that member's stroke may reach
// into the pixel, the pixel is cut into kDistanceTaps^2 squares, each read the same way about
// its own centre: the box filter of the pixel is the mean of its parts' boxes, exact while
// each part holds one straight member's stroke; where a part's neighbour reads a member whose
// stroke reaches into the part, into kDistanceFineTaps^2, each of those parts with the nearest
// such stroke as well, the two strokes' union by inclusion and exclusion, and its own stroke's
// near edge moved in by the lens a straight edge adds where it bends (its curvature read from
// how the neighbours' normals turn). Members finer than those parts are read by their tubes
// (DistanceTubes.h), handing over from the parts as they crowd; where they run parallel, or
// two ways as a grid's lines do (DistanceGrid.h), in closed form by the index they run by.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/DistanceReading.h"
#include "compiler/lower/DistanceTubes.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

namespace moire::lower {

// The pixel's parts a side where a corner reads another member whose stroke may reach in, and
// where a part's neighbour reads one whose stroke reaches into the part (members closer than
// the parts).
constexpr int kDistanceTaps = 4;
// How far (a share of the distance's change across a pixel, |grad d| x pixel) a corner's
// distance may stand off the first-order one before the pixel is read in parts: a member
// bending by that much across the pixel's half-diagonal (a radius of about 5 pixels).
constexpr double kStraightSlack = 0.05;

// The crowd estimate of a family given by its distance: `nearest`, the pixel's mean ink read
// as above (taken by the compose step in place of the distance form); `runs`, where the
// members crowd and run parallel over the pixel (its 4 x 4 parts' normals agree), the index
// they run by, read from the centre's distance and its ray to the ridge (half the spacing),
// with which the union of fine layers lets the family beat with another layer as a phase
// family does (FineUnion.h); and `strokesCrowded`, 1 where the pixel was read in parts (the
// nearest member's stroke is not the layer's strokes there, which stroke pairs then take as
// independent: StrokePairs.h), but where the members run parallel and stand apart, where the
// nearest stroke stands for them as a phase family's does, handed over to the union as they
// crowd.
CrowdEstimate distanceFamilyCrowd(ir::Builder& b, ir::ValueId distance, const DistanceAt& at,
                                  ir::ValueId halfWidth, const PixelFootprint& pixel);

} // namespace moire::lower
