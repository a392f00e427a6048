// The mean ink of a lattice whose points or edges are finer than the pixel (docs/filtering.md,
// "Lattices finer than a pixel"). A lattice gives the distance to its nearest point or edge
// alone, so the mean filter's distance form counts one member a pixel: where they crowd that
// is a fraction of the ink. In the limit of many cells a pixel the ink is the share of a cell
// the strokes cover, a closed form of the lattice's geometry: the compose step hands the
// nearest member's mean over to it by members per pixel (a CrowdEstimate), as the walking
// solver hands its strided scan over to its crowd.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LatticeFamily.h"
#include "compiler/lower/LayerPipeline.h"

namespace moire::lower {

struct LatticeCrowdInputs {
    ir::ValueId spacing;   // between neighbouring points (the hexagons' side for hex_lattice)
    ir::ValueId sx, sy;    // the stretch along x and y
    ir::ValueId stroke;    // the stroke's width as written, in world units
    ir::ValueId pixel;     // the pixel's side in world units
    ir::ValueId drawEdges; // a bool: the edges, else the points
    // The generators' index fields and their gradients (LayerFields::genU ...): the square
    // and triangle lattices' edges are whole lines, families of the index u, v (and u + v).
    ir::ValueId genU = ir::kNoValue, genUX = ir::kNoValue, genUY = ir::kNoValue;
    ir::ValueId genV = ir::kNoValue, genVX = ir::kNoValue, genVY = ir::kNoValue;
    ir::ValueId cosTurn = ir::kNoValue, sinTurn = ir::kNoValue; // the camera's turn
};

// `engaged` from 0 where the densest rows of members stand kCrowdFrom pixels apart or more, to
// 1 at kCrowdFull; `mean` the share of the plane the strokes cover. The square and triangle
// lattices' edges are whole lines, two or three phase families of the generators: there
// `engaged` is 1 and `mean` their periodic means over the square pixel laid over one another
// (exact at every scale for one family, and for the square's two over a pixel facing them).
CrowdEstimate latticeCrowd(ir::Builder& b, LatticeKind kind, const LatticeCrowdInputs& in);

} // namespace moire::lower
