// The walking solver's budget, and the variants of the solver the experiments compare it
// with. Apart from WalkingFamily.h so that the options structs can name a variant without
// the solver's builder.
#pragma once

namespace moire::lower {

constexpr double kWalkBudget = 1024; // B: evaluations the scan may spend (spec §7.6)

// The solver as the experiments vary it (spec §9.1, §9.4, §9.6). The default is the shipped
// solver; nothing a scene or the command line says reaches the other settings, which only
// the programs under experiments/ and bench/ build (CompileOptions::walking).
struct WalkingVariant {
    enum class Solver {
        Window, // the shipped method: Theorem 4's interval with the exact drift constant
        Loose, // the same interval with ||delta|| in place of rho(-delta) (Table 6's "exact drift")
        Sweep, // no certificate: seed at rho(p)/s, a fixed neighbourhood, Newton refinement
    };
    Solver solver = Solver::Window;
    double budget = kWalkBudget; // B: past it the scan strides
    bool latticeAnchored = true; // false: the stride anchored at n_lo (Fig. 17, centre)
    int sweepNeighbours = 100;   // Sweep: members looked at either side of the seed
    // Table 6: each false removes one mechanism.
    bool lipschitzSkip = true;     // §7.4: skip members the Lipschitz bound rules out
    bool supportFastPaths = true;  // §6: the circle and polygon support forms without a loop
    bool polygonClosedForm = true; // §7.5: translated polygons answered in closed form
    bool carriedRotation = true;   // §7.4: the member's turn carried by angle addition
    bool acceptEarlyExit = true;   // §7.1: stop once a member is inside the stroke
    bool operator==(const WalkingVariant&) const = default;
};

} // namespace moire::lower
