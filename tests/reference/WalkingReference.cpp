#include "tests/reference/WalkingReference.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace moire::reference {

double radius(int facets, double qx, double qy) {
    if (facets == 0) return std::hypot(qx, qy);
    // max over the N unit facet normals u_k = (cos 2 pi k / N, sin 2 pi k / N) of <q, u_k>:
    // the definition (Eq. 16), not the folded forms the standard library writes.
    double best = -INFINITY;
    for (int k = 0; k < facets; ++k) {
        double a = 2.0 * std::numbers::pi * k / facets;
        best = std::max(best, qx * std::cos(a) + qy * std::sin(a));
    }
    return best;
}

double residual(const Walking& w, double px, double py, int64_t n) {
    double a = static_cast<double>(n) * w.turn;
    double c = std::cos(a), s = std::sin(a);
    double qx = c * px + s * py - n * w.offsetX;
    double qy = -s * px + c * py - n * w.offsetY;
    return radius(w.facets, qx, qy) - (n * w.spacing + w.phase);
}

double drift(const Walking& w) {
    return radius(w.facets, -w.offsetX, -w.offsetY);
}

namespace {

// Every member n = 0, 1, 2, ... whose residual at p may be under `reach`, in order, each
// given to `visit(n, |h_p(n)|)`; returns false when `maxMembers` cut the scan short.
template <class Visit>
bool scan(const Walking& w, double px, double py, double reach, int64_t maxMembers, Visit visit) {
    const double r = std::hypot(px, py);
    const double m = drift(w);
    const double s = w.spacing;
    for (int64_t n = 0;; ++n) {
        // Eq. 28 bounds the residual on both sides by lines in n: h(n) <= r + n m - n s - phase
        // and h(n) >= n m - r - n s - phase. Once the upper line is below -reach (m < s) or
        // the lower line above +reach (m > s), it stays there for every larger n. Each test
        // is a proof only in its own direction: with m > s the upper line rises again (with
        // phase > r it starts below -reach, and the scan used to stop at n = 0, missing the
        // members that drift back over p), and with m < s the lower line falls.
        const double upper = r + n * (m - s) - w.phase;
        const double lower = n * (m - s) - r - w.phase;
        if ((m <= s && upper < -reach) || (m >= s && lower > reach)) return true;
        if (n >= maxMembers) return false;
        visit(n, std::fabs(residual(w, px, py, n)));
    }
}

} // namespace

Nearest nearest(const Walking& w, double px, double py, double guard, int64_t maxMembers) {
    Nearest out;
    out.distance = guard;
    out.complete = scan(w, px, py, guard, maxMembers, [&](int64_t n, double v) {
        ++out.evaluations;
        if (v < out.distance) {
            out.distance = v;
            out.argmin = n;
        }
    });
    return out;
}

std::vector<int64_t> membersWithin(const Walking& w, double px, double py, double reach,
                                   int64_t maxMembers) {
    std::vector<int64_t> out;
    scan(w, px, py, reach, maxMembers, [&](int64_t n, double v) {
        if (v < reach) out.push_back(n);
    });
    return out;
}

} // namespace moire::reference
