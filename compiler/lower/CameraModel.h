// The camera, written once as a template over the number type (as compiler/ir/Semantics.h
// writes the ops): the lowering instantiates it with ir::BuiltValue to build the kernel's
// camera (Camera.cpp), the viewer with double for its gestures and previews
// (runtime/view/ViewCamera.cpp), and the benchmarks to find the world point of a pixel.
//
// Pixel p of a W x H image, continuous with pixel centres at i + 0.5 and y down, lies at
//     world = C + Rot(turn) (px - W/2, H/2 - py) * pixel
//     pixel = fit / zoom,   fit = max(sceneWidth / W, sceneHeight / H)
// with y up in the world. The scene's `size` frames the picture; rendering at another size
// shows the same frame at that resolution (fitted if the aspect differs), so a print-size
// render is the same picture with more pixels.
#pragma once

#include "compiler/ir/Plane.h"

#include <algorithm>

namespace moire::lower {

template <class T>
struct CameraT {
    ir::Vec2T<T> center; // C: the world point at the middle of the image
    T cosTurn, sinTurn;  // of the camera's turn
    T pixel;             // the world size of one pixel
    T width, height;     // the image, in pixels
    bool turned = true;  // false: no turn, and the lowering builds no rotation
    bool centred = true; // false: C is the origin, and the lowering adds nothing
};

// How many world units of the scene's frame one pixel of a W x H image covers, at zoom 1.
template <class T>
inline T fitScale(T sceneWidth, T sceneHeight, T width, T height) {
    using std::max;
    T across = sceneWidth / width;
    T down = sceneHeight / height;
    return max(across, down);
}

// The pixel p as seen from the image's middle, y up.
template <class T>
inline ir::Vec2T<T> fromMiddle(const CameraT<T>& cam, ir::Vec2T<T> p) {
    T x = p.x - cam.width * 0.5;
    T y = cam.height * 0.5 - p.y;
    return {x, y};
}

// The world point under pixel p.
template <class T>
inline ir::Vec2T<T> toWorld(const CameraT<T>& cam, ir::Vec2T<T> p) {
    ir::Vec2T<T> s = fromMiddle(cam, p);
    ir::Vec2T<T> r = cam.turned ? ir::rotate(s, cam.cosTurn, cam.sinTurn) : s;
    T x = r.x * cam.pixel;
    T y = r.y * cam.pixel;
    if (!cam.centred) return {x, y};
    x = cam.center.x + x;
    y = cam.center.y + y;
    return {x, y};
}

// The pixel over a world point: toWorld's inverse.
template <class T>
inline ir::Vec2T<T> toPixel(const CameraT<T>& cam, ir::Vec2T<T> world) {
    ir::Vec2T<T> r = {world.x, world.y};
    if (cam.centred) r = {world.x - cam.center.x, world.y - cam.center.y};
    r = {r.x / cam.pixel, r.y / cam.pixel};
    ir::Vec2T<T> s = cam.turned ? ir::unrotate(r, cam.cosTurn, cam.sinTurn) : r;
    T x = s.x + cam.width * 0.5;
    T y = cam.height * 0.5 - s.y;
    return {x, y};
}

// A displacement on screen, in pixels (y down), as a displacement in the world.
template <class T>
inline ir::Vec2T<T> deltaToWorld(const CameraT<T>& cam, ir::Vec2T<T> d) {
    ir::Vec2T<T> up = {d.x, -d.y};
    ir::Vec2T<T> r = cam.turned ? ir::rotate(up, cam.cosTurn, cam.sinTurn) : up;
    T x = r.x * cam.pixel;
    T y = r.y * cam.pixel;
    return {x, y};
}

} // namespace moire::lower
