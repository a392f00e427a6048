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

// The largest side of an image: 2^20 = 1,048,576 pixels. render streams its file band by
// band (ImageStream.h), so memory does not bound it; what does: pixel coordinates reach the
// kernel as f32, and a pixel's centre (x + 0.5) is exact only below 2^23; a band of the
// widest image is 2^20 x 64 x 4 floats (1 GiB), still a band; pixel counts (2^40) and
// byte counts of whole images (2^44 floats) stay far inside size_t and int64. TIFF (BigTIFF)
// and EXR take such sides; JPEG and PNG have lower limits of their own (ImageIO.h).
constexpr int kMaxImageSide = 1 << 20;
// The largest side of a frame held whole in memory (view, serve, watch, clip, export): its
// float pixels alone are 17 GB at 32768 x 32768.
constexpr int kMaxFrameSide = 32768;

struct FrameRequest {
    double time = 0.0;
    int width = 0, height = 0; // when non-zero, replaces the scene's size
    // When set, replaces the program's literal table (same length): the viewer's adjustments.
    const std::vector<double>* literals = nullptr;
    // The largest side the frame rendered may have: kMaxFrameSide for a command that holds
    // the frame whole. (The scene's own size is checked against kMaxImageSide either way.)
    int maxSide = kMaxImageSide;
    // When above 0, the world size of one pixel (the camera's zoom included), in place of
    // the scene's frame fitted to the image: the scale and the canvas set apart (`moire
    // print`). Needs a program compiled with CompileOptions::pixelSize, which otherwise
    // draws the fitted frame, as any render.
    double pixelSize = 0.0;
};

// Evaluates the frame at `request.time`. A value that cannot be rendered (an image size out
// of range, a zero zoom) is a user error: the rendered diagnostic goes to `diagnostics` (and
// one by one to `located`, when given) and the function returns false.
bool evaluateFrame(const SceneProgram& program, const FrameRequest& request, FrameValues& out,
                   std::string& diagnostics, std::vector<LocatedDiagnostic>* located = nullptr);

} // namespace moire
