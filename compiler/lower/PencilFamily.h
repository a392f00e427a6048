// The radial pencil (spec §3.6, Eq. 6): N straight lines through the layer's origin, at angles
// k pi / N, with an open disc of radius `start` about the crossing point. Built by the compiler
// rather than written in the stdlib because the views that sweep need more than its distance:
// its members are the integer level sets of the winding index theta N / pi (spec §5: the
// pencil is a pure winding field), which advances by a rotation, and whose gap grows with the
// radius; the disc is a floor that does not turn with the lines.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/FamilyRegistry.h"
#include "compiler/lower/LayerPipeline.h"

namespace moire::lower {

// distance: Eq. 6, max(r |sin wrap(theta, pi / N)|, start - r); index: the angular sector
// floor(theta N / pi); smooth: theta N / pi, with its gradient in gradX, gradY; the phase
// sample of the fractional index (Eq. 14), the disc as its floor.
LayerFields pencilFields(ir::Builder& b, ir::ValueId qx, ir::ValueId qy, ir::ValueId lines,
                         ir::ValueId start);

// The builder for the registry: its arguments are (lines, start), as stdlib/families.moire
// declares them.
FamilyBuilder pencilBuilder();

} // namespace moire::lower
