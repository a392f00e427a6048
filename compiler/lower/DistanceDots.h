// A crowd of members given by their distance that are dots on a lattice (docs/filtering.md,
// "Dots given by their distance"): read as a dot screen, by the two generators whose whole
// values are the dots' centres, and its mean in closed form (LatticeCrowd.h, dotScreenMean),
// where the tubes (DistanceTubes.h) spend 34 rays a pixel and leave a grain of their samples.
//
// A dot's centre is the foot of a point's foot: a disc's distance grows radially from its
// centre, so a point's foot is the centre; a square's Chebyshev distance max(|dx|, |dy|) puts
// the foot on one of its centre lines, whose own foot is the centre. The dot's shape comes
// first: its distance grows linearly along every ray from its centre (a gauge), read at
// kShapeLooks points about the centre c0 of the pixel centre's dot and again nearer, and its
// area is the gauge's integral; a ring about a point, or a grid's or a ring's line, through
// which the c0 read runs, is no such dot. Then the lattice: every point of c0's cell reads c0,
// and a point just past the cell's edge reads the dot across that edge, a relevant vector of
// the lattice. A ray out from c0 is probed until it reads another dot, then stepped back to
// just past the bisector of c0 and that dot, until the dot read there is the same (the two
// cells meet there). A second ray 75 degrees from the first dot's direction cannot leave through
// the first's edges, so it reads a dot in another direction; two relevant vectors that are not
// parallel are a basis of a plane lattice (its relevant vectors are b1, b2 and b1 + b2 of an
// obtuse superbase, up to sign, and any two of those span it). Reduced (Lagrange), the basis is
// checked at the three half-steps of its cell, where a lattice twice as fine would have its
// further points (a ray past a corner of the cell reads a dot two cells on) and where any other
// dot read is off the lattice.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/DistanceReading.h"
#include "compiler/lower/LatticeCrowd.h"

#include <functional>
#include <span>
#include <vector>

namespace moire::lower {

// A screen's reading, the dots' (here) or the rings' (DistanceRings.h): `trust`, 0 to 1, how
// far the members read as dots (or rings) of one lattice whose strokes stand apart; `mean`,
// the pixel's mean ink in closed form; `members`, the pixel's side over the square root of a
// cell's area (cells along a side), by which the caller hands over to the closed form; the
// generators at the pixel's centre, with their gradients per world unit along the world's axes
// (the members at their whole values); and a member's discs in world units (the union of fine
// layers lays the screen so, LatticeShape): for dots `radius` that of the disc of a dot's area
// (a round dot's own radius) and `inner` 0; for rings the discs within their outer and inner
// edges.
struct ScreenRead {
    ir::ValueId trust, mean, members;
    ir::ValueId u, ux, uy, v, vx, vy;
    ir::ValueId radius, inner;
};
// The dots' reading, where `wanted` (else 0s). `centre`: the pixel centre's reading;
// `halfWidth`: the stroke's half-width in the distance's units.
ScreenRead dotsRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                    ir::ValueId halfWidth, const Reading& centre, ir::ValueId wanted);

// The furthest edge, in pixels, of a screen's member from its centre where the screen is read
// in closed form: members two a pixel (where the closed form begins to take over) stand half a
// pixel apart, and their strokes apart.
constexpr double kScreenMostEdge = 0.25;

// The centre of the member nearest the pixel's point p, whose reading there is r: NaN where it
// cannot be read (a kink met to the last bit). A dot's is the foot of p's foot; a ring's its
// level set's centre of curvature (DistanceRings.h).
using CentreOf = std::function<PixelPoint(ir::Builder&, const Reading&, PixelPoint)>;

// The lattice of the centres about c0, read by `centreOf` (n the first ray's direction, `start`
// the rays' first probe's distance from c0, `furthest` a member's furthest edge from its
// centre): two rays out of c0's cell, their centres' vectors Lagrange-reduced, and the cell's
// half-steps checked. `ok` where both rays settled, the centres read at the half-steps are on
// the lattice, its basis is not flat and the members' strokes stand apart.
struct DotLattice {
    PixelPoint p, q;      // the reduced basis, along the pixel's sides
    ir::ValueId area, ok; // the cell's area
};
DotLattice dotLattice(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                      const CentreOf& centreOf, PixelPoint c0, Normal n, ir::ValueId start,
                      ir::ValueId furthest);

// The screen a lattice about c0 makes: its generators at the pixel's centre, whole at the
// centres, with their world gradients and the pixel (dotScreenMean's inputs), and the pixel's
// side over the square root of a cell's area (cells along a side).
struct ScreenOf {
    LatticeCrowdInputs in;
    ir::ValueId members;
    // The generators and their world gradients, in ScreenRead's order: u, du/dx, du/dy, v,
    // dv/dx, dv/dy.
    std::vector<ir::ValueId> generators() const {
        return {in.genU, in.genUX, in.genUY, in.genV, in.genVX, in.genVY};
    }
};
ScreenOf screenOf(ir::Builder& b, const PixelFootprint& pixel, PixelPoint c0,
                  const DotLattice& lattice);

// A ScreenRead as the values a branch carries (kScreenReadValues of them, NaN held to 0), and
// back.
constexpr size_t kScreenReadValues = 11;
std::vector<ir::ValueId> screenReadValues(ir::Builder& b, ir::ValueId trust, ir::ValueId mean,
                                          const ScreenOf& screen, ir::ValueId radius,
                                          ir::ValueId inner);
ScreenRead screenReadOf(std::span<const ir::ValueId> values);

// The distance's reading a 64th of a pixel beside the pixel's centre, along its first side:
// where the centre stands on its member's centre to the last bit, it has no gradient, and the
// gradient's length is read there.
Reading besideCentre(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel);

} // namespace moire::lower
