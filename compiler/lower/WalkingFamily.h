// The walking families (spec §6-7): a concentric support-function family whose member n is
// moved by n * offset and turned by n * turn. No formula in p has these members as level
// sets, so the nearest member is searched for, with a certificate: the interval of
// Theorem 4, the Lipschitz skip of Algorithm 1, and closed forms where they exist. Built
// once as IR, so every backend runs the same solver.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/FamilyRegistry.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/WalkingVariant.h"

#include <functional>

namespace moire::lower {

struct WalkingInputs {
    ir::ValueId px, py;           // the point, in the layer's frame
    ir::ValueId spacing, phase;   // s, and the inradius of member 0
    ir::ValueId offsetX, offsetY; // delta: member n's centre is Rot(n turn)(n delta)
    ir::ValueId turn;             // theta
    ir::ValueId facets;           // side count N of the shape; 0 for a circle
    StrokeBand band;              // the stroke, for the guard and the accept threshold
    // Views that read the flanking members measure a full pitch out: G = max(h + a, s)
    // rather than max(h + a, 3/4 s).
    bool flankGuard = false;
    // Also compute the searched index field (nearest index plus the fractional residual of
    // §4.1), at the price of two more evaluations of the radius.
    bool wantIndex = false;
    // Count every evaluation of the radius with `tally [0]` (the interpreter's counting mode).
    bool tally = false;
    // Also estimate the crowd of members where the scan strides (LayerFields::crowd), for the
    // mean filter.
    bool crowd = false;
    ir::ValueId stroke = ir::kNoValue; // with crowd: the stroke's width as written (residual units)
    // With crowd: the camera's turn (FamilyInputs::cosTurn), for the pixel's footprint across
    // a member's normal.
    ir::ValueId cosTurn = ir::kNoValue, sinTurn = ir::kNoValue;
    WalkingVariant variant = {};
};

// Evaluates the family's radius rho (its support function: the phase) at the point (qx, qy)
// of the family's own frame, emitting the IR at the builder's current position.
using RadiusFn = PhaseFn;

// The guard (Eq. 26): past max(h + a, 3/4 s) a member draws nothing, so the search may stop
// there (a full pitch, s, for views that read the flanking members: WalkingInputs::flankGuard).
// Written once as a template (instantiated over IR values here, over double by the
// walking benchmark's reference).
constexpr double kWalkGuardPitches = 0.75;
template <class T>
inline T walkGuard(const StrokeBandT<T>& band, T spacing, double pitches = kWalkGuardPitches) {
    using std::max;
    T reach = band.h + band.a;
    T least = spacing * pitches;
    return max(reach, least);
}

// The solver's constants (spec §7.6); the budget B is kWalkBudget (WalkingVariant.h).
constexpr double kWalkSpanCap = 65536; // 2^16: widest interval the scan considers
constexpr double kWalkReanchor = 32;   // carried rotation re-anchored this often
constexpr double kWalkMarginal = 1e-4; // drift within this of s reads as marginal
constexpr double kWalkMaxFacets = 24;  // larger side counts are scanned

// The tally counter the solver counts radius evaluations in.
constexpr int kRadiusTally = 0;

// Distance (clamped at the guard) and, with wantIndex, the searched index; aux0 and aux1
// are the certified interval [n_lo, n_hi] of Theorem 4 (before the span cap).
LayerFields walkingFamilyFields(ir::Builder& b, const WalkingInputs& in, const RadiusFn& rho);

// The walking solver as the registry's kWalking: a layer's frame, its `offset` and `turn`
// (reduced to one turn), its encoded field, and the family's radius (FamilyInputs::phaseAt)
// and side count (FamilyInputs::facets).
LayerFields walkingLayerFields(ir::Builder& b, const FamilyInputs& in);

} // namespace moire::lower
