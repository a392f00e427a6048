// A crowd of members given by their distance that are rings about a lattice's points (docs/
// filtering.md, "Rings given by their distance"): read as the difference of two dot screens,
// the discs within each ring's outer edge less those within its inner edge, each in closed
// form (LatticeCrowd.h, dotScreenMean), where the tubes (DistanceTubes.h) spend 34 rays a
// pixel, leave a grain of their samples and cost some 300 times point sampling.
//
// A ring's centre is its level sets' centre of curvature: the distance |r - R| about a centre
// c has circles about c for its level sets, so the normal line at any point, read as a line
// (a point inside the ring and one outside face opposite ways along it), runs through c, and
// two points a step apart along the level set give two normal lines that meet there, whatever
// the step. The ring's radius is the distance at its centre; it is round where the distance
// falls linearly from there, R - s at s from c in every direction. The lattice of the
// centres is read as a dot screen's is (DistanceDots.h, dotLattice): a point's nearest ring is
// the one whose centre is nearest, where the rings' strokes stand apart, so the rings' cells
// are their centres' cells. With other layers the union of fine layers lays the rings' screen
// on them as two discs' difference too (LatticeUnion.h).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/DistanceDots.h"
#include "compiler/lower/DistanceReading.h"

namespace moire::lower {

// The rings' reading (ScreenRead, DistanceDots.h), where `wanted` (else 0s): `trust` how far
// the members read as round rings about the points of one lattice whose strokes stand apart,
// `radius` and `inner` the radii of the discs within each ring's outer and inner edges (world
// units; the inner 0 where the stroke leaves none). `centre`: the pixel centre's reading;
// `halfWidth`: the stroke's half-width in the distance's units.
ScreenRead ringsRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     ir::ValueId halfWidth, const Reading& centre, ir::ValueId wanted);

} // namespace moire::lower
