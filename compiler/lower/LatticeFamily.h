// The lattice families (spec §3.6): points indexed by two integers, found by rounding in the
// lattice basis (cube rounding for the A2 lattices), with a distance either to the nearest
// point or to the nearest edge of its cell, under an anisotropic scale that keeps strokes
// metrically correct. Built once as IR, so every backend runs the same maths.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/FamilyRegistry.h"
#include "compiler/lower/LayerPipeline.h"

#include <string>
#include <vector>

namespace moire::lower {

enum class LatticeKind {
    Square,   // square_lattice: points on a square grid; cells are squares
    Triangle, // triangle_lattice: the A2 lattice; edges are the triangles' sides
    Hex,      // hex_lattice: a honeycomb; points are the hexagons' corners, edges their sides
};

struct LatticeInputs {
    ir::ValueId px, py;             // the point, in the layer's frame
    ir::ValueId spacing;            // distance between neighbouring points
    std::vector<ir::ValueId> scale; // (sx, sy): the lattice stretched along x and y
    ir::ValueId edges;              // 0: distance to the points; otherwise to the edges
};

// distance: to the nearest point or edge; index: the first of the point's two integer
// coordinates; aux0: the second; genU, genV: the two generators' continuous index fields
// (the point in the basis the pattern repeats by), with their gradients (LayerFields).
LayerFields latticeFields(ir::Builder& b, LatticeKind kind, const LatticeInputs& in);

// The builder of a lattice family for the registry: its arguments are (scale = (sx, sy),
// edges), as stdlib/families.moire declares them.
FamilyBuilder latticeBuilder(LatticeKind kind);

} // namespace moire::lower
