// The walking solver's budget, and the variants of the solver the experiments compare it
// with. Apart from WalkingFamily.h so that the options structs can name a variant without
// the solver's builder.
#pragma once

namespace moire::lower {

constexpr double kWalkBudget = 1024; // B: evaluations the scan may spend (spec §7.6)
// Sweep's fixed neighbourhood: members looked at either side of its seed, 2K + 1 in all, the
// budget such a renderer pays at every pixel (spec §9.1; Table 4's Sweep column is ~190 to
// 360 evaluations a pixel). Shared by the IR Sweep and the double one of tests/reference.
constexpr int kSweepNeighbours = 96;
// Sweep's Newton refinement after the neighbourhood: steps, and evaluations each (h at the
// rounded index and its two neighbours for a central slope, then h at the refined index).
constexpr int kSweepNewtonSteps = 2;
constexpr int kSweepNewtonEvaluations = 4;

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
    double budget = kWalkBudget;            // B: past it the scan strides
    bool latticeAnchored = true;            // false: the stride anchored at n_lo (Fig. 17, centre)
    int sweepNeighbours = kSweepNeighbours; // Sweep: members looked at either side of the seed
    // Table 6: each false removes one mechanism and leaves the picture as it was (only the
    // time changes), except where the scan that replaces the closed form meets the span cap.
    bool lipschitzSkip = true;     // §7.4: false visits every stride of the interval
    bool supportFastPaths = true;  // §6: false evaluates a polygon's radius as the maximum
                                   // over its N facet normals, in a loop (circles unchanged)
    bool polygonClosedForm = true; // §7.5: false scans translated polygons too
    bool carriedRotation = true;   // §7.4: false takes a cosine and a sine at every member
    bool acceptEarlyExit = true;   // §7.1: false scans on once a member is inside the stroke
    bool operator==(const WalkingVariant&) const = default;
};

} // namespace moire::lower
