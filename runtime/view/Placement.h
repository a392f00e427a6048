// What `p` prints in the viewer: the view's camera and each moved or turned layer as .moire
// text to paste back into the scene, so that a placement found by hand becomes part of the
// document.
//
// A value the scene writes as a literal is printed as the combined number. A value it writes
// as an expression (a ramp of a timing, anything in t) keeps the scene's own text with the
// view's adjustment applied on top: a looping parameter is written at the value its cycle
// departs from, not wherever the clock happened to carry it (spec §8.4), so the instant `p`
// was pressed at never leaks into the file.
#pragma once

#include "runtime/view/ViewCamera.h"

#include <string>

namespace moire {

struct SceneProgram;

namespace view {

// A number as the placement writes it: up to seven significant digits, no trailing zeros,
// never "-0".
std::string formatNumber(double v);

// The placement as .moire text: a `camera { ... }` block, then `layer NAME { origin = ...;
// rotation = ... }` for each layer the view moves or turns. `program` must be the program
// the view adjusts (its checked AST points at the source the text is taken from).
// These are the values to set in the scene's blocks, not blocks to paste beside them (a
// second camera block, or a second layer of the same name, is an error).
std::string placementText(const SceneProgram& program, const ViewAdjust& view);

// The scene's own text with the placement written into it (the viewer's `w`): the camera
// block's center and zoom, and each moved layer's origin and rotation, replaced where the
// scene writes them and added to the block where it does not (a camera block is added when
// there is none); every other byte, comments and layout included, is kept. False, with the
// reason, when a layer's origin is an expression the language cannot turn.
bool placedSource(const SceneProgram& program, const ViewAdjust& view, std::string& out,
                  std::string& why);

} // namespace view
} // namespace moire
