// Per-frame evaluation: runs a scene's frame program (in double precision, on the reference
// interpreter) for one instant of the clock, giving the kernel's uniforms and the frame
// settings. Nothing carries over from one frame to the next.
#pragma once

#include "compiler/Compile.h"
#include "compiler/lower/ClipClock.h" // TimingValues

#include <array>
#include <string>
#include <vector>

namespace moire {

struct FrameValues {
    std::vector<double> uniforms;
    int width = 0, height = 0;
    double zoom = 1.0;
    double centerX = 0.0, centerY = 0.0, turn = 0.0; // the scene's camera (turn in radians)
    // The scene's own `size`: the frame it shows. An image of another size shows the same
    // frame, fitted: one pixel is max(sceneWidth / width, sceneHeight / height) / zoom
    // world units.
    double sceneWidth = 0.0, sceneHeight = 0.0;
    // The world size of one pixel as drawn: fitted, or FrameRequest::pixelSize.
    double pixelSize = 0.0;
    std::vector<TimingValues> timings;
    // Each param's value at this instant (SceneProgram::parameters' order; a colour's four
    // components, a vector's two, else one, the rest 0): what a slider shows.
    std::vector<std::array<double, 4>> parameters;
};

constexpr int kMaxImageSide = 32768;

struct FrameRequest {
    double time = 0.0;
    int width = 0, height = 0; // when non-zero, replaces the scene's size
    // When above 0, the world size of one pixel (the camera's zoom included), in place of
    // the scene's frame fitted to the image: the scale and the canvas set apart (`moire
    // print`). Needs a program compiled with CompileOptions::pixelSize, which otherwise
    // draws the fitted frame, as any render.
    double pixelSize = 0.0;
    // When set, replaces the program's literal table (same length): the viewer's adjustments.
    const std::vector<double>* literals = nullptr;
};

// Evaluates the frame at `request.time`. A value that cannot be rendered (an image size out
// of range, a zero zoom) is a user error: the rendered diagnostic goes to `diagnostics` (and
// one by one to `located`, when given) and the function returns false.
bool evaluateFrame(const SceneProgram& program, const FrameRequest& request, FrameValues& out,
                   std::string& diagnostics, std::vector<LocatedDiagnostic>* located = nullptr);

} // namespace moire
