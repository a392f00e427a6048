// Points and turns of the plane, written once as templates over the number type: instantiated
// with double by the runtime (the viewer's camera, placement) and with ir::BuiltValue by the
// lowering, so the kernel and the tools that must agree with it share one formula.
#pragma once

#include <cmath>

namespace moire::ir {

template <class T>
struct Vec2T {
    T x, y;
};

// Rot(angle) p, given the angle's cosine c and sine s.
template <class T>
inline Vec2T<T> rotate(Vec2T<T> p, T c, T s) {
    T x = c * p.x - s * p.y;
    T y = s * p.x + c * p.y;
    return {x, y};
}
template <class T>
inline Vec2T<T> rotate(Vec2T<T> p, T angle) {
    using std::cos, std::sin; // and BuiltValue's, by argument-dependent lookup
    T c = cos(angle);
    T s = sin(angle);
    return rotate(p, c, s);
}
// Rot(-angle) p, the inverse turn, given the angle's cosine c and sine s.
template <class T>
inline Vec2T<T> unrotate(Vec2T<T> p, T c, T s) {
    T x = c * p.x + s * p.y;
    T y = c * p.y - s * p.x;
    return {x, y};
}

} // namespace moire::ir
