#include "tests/reference/WalkingSweep.h"

#include <algorithm>
#include <cmath>

namespace moire::reference {

namespace {
// Rounding as the IR's `round` does it, half up: floor(x + 1/2).
double roundHalfUp(double x) {
    return std::floor(x + 0.5);
}
} // namespace

SweepResult sweep(const Walking& w, double px, double py, double guard, int neighbours,
                  int newtonSteps) {
    const double seed = roundHalfUp((radius(w.facets, px, py) - w.phase) / w.spacing);
    double best = guard;
    double argmin = std::max(0.0, seed);
    // The seed's radius, then every slot of the window: members that do not exist (n < 0)
    // are paid for all the same, as a fixed-trip loop pays for them.
    SweepResult out;
    out.evaluations = 1 + 2 * neighbours + 1;
    for (double n = std::max(0.0, seed - neighbours); n <= seed + neighbours; ++n) {
        double v = std::fabs(residual(w, px, py, static_cast<int64_t>(n)));
        if (v < best) best = v, argmin = n;
    }
    // Newton on h(n) = 0 from the best member, with a central-difference slope; the refined
    // member is looked at too.
    double n = argmin;
    for (int step = 0; step < newtonSteps; ++step) {
        const double k = roundHalfUp(n);
        const auto at = [&](double m) {
            return residual(w, px, py, static_cast<int64_t>(std::max(0.0, m)));
        };
        const double h0 = at(k), slope = 0.5 * (at(k + 1) - at(k - 1));
        out.evaluations += 4;
        if (slope == 0) break;
        n = std::max(0.0, n - h0 / slope);
        best = std::min(best, std::fabs(at(roundHalfUp(n))));
    }
    out.distance = std::min(best, guard);
    return out;
}

} // namespace moire::reference
