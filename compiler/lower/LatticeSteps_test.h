// A lattice's two steps in the pixels of a random test (HoneycombInPixel_test,
// TriangleInPixel_test), and the gradients of its generators (u, v) they give.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

namespace moire::lower {

// Steps `length` pixels long at 0 and 60 degrees, stretched by k along the direction b (the
// component along b grows by k) and turned by a.
struct LatticeSteps {
    std::array<double, 2> e1, e2;
    // The generators' gradients, the inverse of the steps' matrix.
    std::array<double, 2> gu, gv;
};
inline LatticeSteps latticeSteps(double length, double a, double b, double k) {
    auto step = [&](double angle) {
        double x = length * std::cos(angle), y = length * std::sin(angle);
        const double along = x * std::cos(b) + y * std::sin(b);
        x += (k - 1.0) * along * std::cos(b);
        y += (k - 1.0) * along * std::sin(b);
        return std::array<double, 2>{x * std::cos(a) - y * std::sin(a),
                                     x * std::sin(a) + y * std::cos(a)};
    };
    LatticeSteps out{step(0.0), step(std::numbers::pi / 3.0), {}, {}};
    const auto &e1 = out.e1, &e2 = out.e2;
    const double det = e1[0] * e2[1] - e2[0] * e1[1];
    out.gu = {e2[1] / det, -e2[0] / det};
    out.gv = {-e1[1] / det, e1[0] / det};
    return out;
}

} // namespace moire::lower
