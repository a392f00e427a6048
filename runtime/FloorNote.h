// The note a point-sampled render gives where a layer's stroke is thinner than the stroke
// floor at the frame's pixel size (docs/filtering.md): there the stroke is drawn 2.3 pixels
// wide (half-width kStrokeFloorPixels, spec Eq. 35), darker than the stroke written, and
// the mean filter is what keeps its tone.
#pragma once

#include "compiler/Compile.h"
#include "compiler/sema/Views.h"

#include <optional>
#include <string>

namespace moire {

// The notes, rendered as diagnostics (`file:line:col: note: ...`, the source line and a
// caret under the stroke's value), one for each layer drawn on the floor: empty unless the
// scene is drawn with `filter = point` (`filter` replacing the scene's when given). Only a
// stroke written as a plain number is judged; `pixelSize` is the world size of one pixel
// as drawn (FrameValues::pixelSize, the camera's zoom included).
std::string strokeFloorNotes(const SceneProgram& program,
                             const std::optional<sema::FilterMode>& filter, double pixelSize);

} // namespace moire
