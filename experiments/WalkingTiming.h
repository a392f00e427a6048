// What the solver experiments (Table 3, Table 6) share: one walking scene compiled under a
// variant of the solver (lower::WalkingVariant), its JIT frame time on one thread, its
// evaluations of the radius counted by the interpreter, and its picture.
#pragma once

#include "compiler/lower/WalkingVariant.h"
#include "runtime/Image.h"

#include <string>

namespace moire::exp {

// One full-frame walking layer: the body of a scene (layers and camera; the size is given
// per run), with a name for the table.
struct WalkingScene {
    std::string name;
    std::string body;
};

// `size` then the body: the scene's size is the frame's, so the camera fits it at one world
// unit a pixel, and the zoom says how many a pixel.
std::string walkingSceneText(const WalkingScene& s, int w, int h);

// CPU seconds for the JIT to render one w x h frame on one thread (`lanes` pixels a step; 1:
// scalar), the fastest of `repeat` (of more, up to half a second's worth, when `repeat` > 1). Exits
// with a message when the scene does not compile.
double jitSeconds(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h, int lanes,
                  int repeat);

// The JIT's own lane count on this machine (its default).
int jitLanes();

// Evaluations of the radius per pixel, counted by the interpreter on every `step`-th pixel
// of every `step`-th row.
double evaluationsPerPixel(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h,
                           int step);

// The JIT's picture of the frame.
Image jitImage(const WalkingScene& s, const lower::WalkingVariant& v, int w, int h);

// The share of samples (every channel of every pixel) of a and b that differ by more than
// `tolerance`; 1 when the sizes differ.
double shareDiffering(const Image& a, const Image& b, double tolerance);

// The share of ink: the mean of 1 - v over the colour channels (black ink on white paper).
double inkOf(const Image& img);

// "2.03x", "101.2x".
std::string ratio(double r);

} // namespace moire::exp
