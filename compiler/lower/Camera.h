// The camera's lowering: the frame's settings (image size, the camera as the scene sets it),
// and the world point of the pixel (CameraModel.h instantiated over IR values), which
// everything downstream is differentiated with respect to.
#pragma once

#include "compiler/lower/SceneContext.h"

namespace moire::lower {

// Sets ctx.world to the pixel's world point and outputs the camera's settings (from
// `settingsBase`, numbered as in OutputLayout). Returns the world size of one pixel.
ir::ValueId lowerCamera(SceneContext& ctx, int settingsBase);

} // namespace moire::lower
