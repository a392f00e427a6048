// An independent reference for the walking families, in double precision, for tests and
// benchmarks. It shares nothing with the shipped solver (compiler/lower/WalkingFamily.cpp)
// but the definition of the family: it scans every member n = 0, 1, 2, ... at stride 1,
// with no interval and no skipping, and stops only when the drift bound (Eq. 28 of the
// spec: rho(q_n) <= r + n m) proves that every further member is farther than the guard.
#pragma once

#include <cstdint>
#include <vector>

namespace moire::reference {

// A walking family in its own frame (spec Eqs. 22-25).
struct Walking {
    int facets = 0;        // 0: circle; otherwise a regular polygon, a facet facing +x
    double spacing = 10.0; // s
    double phase = 0.0;    // inradius of member 0
    double offsetX = 0.0, offsetY = 0.0; // delta
    double turn = 0.0;                   // theta, radians
};

// The support-function radius of the shape at q (Eqs. 17-20; the N-gon form for any N).
double radius(int facets, double qx, double qy);

// h_p(n) = rho(Rot(-n theta) p - n delta) - (n s + phase) (Eq. 24).
double residual(const Walking& w, double px, double py, int64_t n);

struct Nearest {
    double distance = 0.0; // min over scanned n of |h_p(n)|, clamped at the guard
    int64_t argmin = -1;   // the member attaining it (-1: none came under the guard)
    int64_t evaluations = 0;
    bool complete = true; // false when the scan hit `maxMembers` before the bound closed
};

// The exhaustive scan, clamped at `guard`. Members beyond `maxMembers` are not looked at
// (needed only at the marginal drift m = s, where the bound never closes).
Nearest nearest(const Walking& w, double px, double py, double guard, int64_t maxMembers = 2000000);

// Every member whose residual at p is under `reach`, in index order. The residual is
// 1-Lipschitz in p (rho is a support-function radius), so the members that can come within
// a stroke's half-width h of any point of a disc of radius R about p are those within
// h + R of p: one scan serves all of a pixel's samples.
std::vector<int64_t> membersWithin(const Walking& w, double px, double py, double reach,
                                   int64_t maxMembers = 2000000);

// The drift constant m = rho(-delta) (Eq. 29).
double drift(const Walking& w);

} // namespace moire::reference
