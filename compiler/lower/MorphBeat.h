// The beat of a morph's two families over a crowded pixel (docs/filtering.md, "Morphs across
// kinds"). Where the members crowd, the morph's crowded form (MorphFamily.cpp) takes the two
// families' distances as independent over the pixel, each distributed as its family's share
// of the plane within a distance, and the pixel's ink as the chance that their blend
// D = (1 - w) d1 + w d2 is within the stroke. They are not independent where a line of one
// family runs along a line of the other: a grid morphing to circles beside the axes through
// the circles' centre, lines to a grid that holds them. There the two lines beat, and the
// pixel holds the moiré of the morph's own that the exact field draws; this is that beat.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

#include <functional>
#include <vector>

namespace moire::lower {

// The crowded pixel's ink of the blend of `fields[from]` (weight 1 - w) and `fields[to]`
// (weight w), `independent` as the crowded form reads it, with the beat of the two families'
// lines whose beat the pixel attenuates least added (MorphBeat.cpp); `independent` where the
// families have no lines (a lattice's points, a family without an index) or every pair beats
// faster than the pixel. `pick(which, values)` is the value of family `which` (a run-time
// index) among one per family. A family's lines are a phase family's one, its index, or a
// square or triangle lattice's edges, its strands, where it draws them.
ir::ValueId
morphBeat(ir::Builder& b, const std::vector<LayerFields>& fields, ir::ValueId from, ir::ValueId to,
          ir::ValueId w, ir::ValueId halfWidth, const PixelFootprint& pixel,
          const std::function<ir::ValueId(ir::ValueId, const std::vector<ir::ValueId>&)>& pick,
          ir::ValueId independent);

} // namespace moire::lower
