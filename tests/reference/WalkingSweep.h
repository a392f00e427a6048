// Sweep, the walking-family baseline without a certificate (spec §9.1), in double precision:
// the benchmark's and the tests' copy, written apart from the IR one in
// compiler/lower/WalkingFamily.cpp so that each can judge the other. Seed at the member whose
// radius matches rho(p), look at a fixed neighbourhood either side, refine the best with
// Newton steps on the index. Only the neighbourhood's size is shared (WalkingVariant.h).
#pragma once

#include "tests/reference/WalkingReference.h"

namespace moire::reference {

struct SweepResult {
    double distance = 0.0; // min |h_p(n)| over the members looked at, clamped at the guard
    int evaluations = 0;   // evaluations of rho, counting every slot of the fixed window
};

// `neighbours` members either side of the seed (lower::kSweepNeighbours in the shipped
// variant), then `newtonSteps` refinements of four evaluations each.
SweepResult sweep(const Walking& w, double px, double py, double guard, int neighbours,
                  int newtonSteps = 2);

} // namespace moire::reference
