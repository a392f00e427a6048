// The walking families' solver (WalkingFamily.h), shared by the files that build it: the
// search in WalkingFamily.cpp, the crowd under the mean filter in WalkingCrowd.cpp and its
// density in WalkingDensity.cpp. One object per layer and pixel program; every method emits IR
// into the builder, so every backend runs what is written here once.
#pragma once

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/Prefilter.h"
#include "compiler/lower/WalkingChains.h"
#include "compiler/lower/WalkingFamily.h"

#include <array>
#include <span>
#include <utility>
#include <vector>

namespace moire::lower::walking {

using ir::BuiltValue;
using ir::Op;
using ir::ValueId;
using Vals = std::vector<ValueId>;

// A distance no member reaches: larger than any guard, finite in single precision.
constexpr double kFar = 1e30;
// The argmin recorded for the flat tail of a marginal drift, which no finite index attains.
constexpr double kFarIndex = 1e7;

class Solver {
  public:
    Solver(ir::Builder& b, const WalkingInputs& in, const RadiusFn& rho)
        : b_(b), in_(in), rho_(rho) {}

    LayerFields run();

  private:
    ValueId c(double v) { return b_.constF(v); }
    ValueId both(ValueId a, ValueId b) { return b_.emit(Op::And, {a, b}); }
    ValueId eq(ValueId a, ValueId b) { return b_.emit(Op::Eq, {a, b}); }
    ValueId ceil(ValueId v) { return b_.neg(b_.floor(b_.neg(v))); }

    const WalkingVariant& variant() const { return in_.variant; }
    bool resolving() const;

    // The residual and its pieces (WalkingFamily.cpp).
    ValueId radius(ValueId qx, ValueId qy);
    ValueId facetRadius(ValueId qx, ValueId qy);
    ValueId facetLoop(ValueId qx, ValueId qy);
    void countEvaluations(int count);
    std::pair<ValueId, ValueId> unturn(ValueId angle);
    std::pair<ValueId, ValueId> unturn(BuiltValue cs, BuiltValue sn, ValueId x, ValueId y);
    ValueId residual(ValueId n);
    ValueId residualAt(ValueId n, ValueId turnedX, ValueId turnedY);
    void consider(ValueId& best, ValueId& argmin, ValueId n, ValueId value);
    ValueId member(ValueId n) { return b_.max(n, c(0.0)); } // members start at n = 0
    // The solver's argmin as a member's index: at most the flat tail's kFarIndex, 0 for NaN.
    ValueId answerIndex(ValueId argmin) { return b_.denan(b_.min(argmin, c(kFarIndex)), c(0.0)); }
    std::pair<ValueId, ValueId> compose(std::pair<ValueId, ValueId> a,
                                        std::pair<ValueId, ValueId> b);

    // The search: its set-up, Theorem 4's interval, the closed forms (§7.5) and the scan of
    // Algorithm 1 (WalkingFamily.cpp). Each returns the nearest member's |h_p| and index (and,
    // under the mean filter, the ink of the members beside it).
    void setUp();
    std::pair<ValueId, ValueId> interval(ValueId guard);
    Vals concentric();
    Vals translatedCircle();
    Vals translatedPolygon();
    Vals scan();

    // The footprint mean of one member's stroke as written (half-width t / 2, no floor) at
    // residual `value` from the pixel's centre, for scan()'s union: distanceMeanInk over a box of
    // the pixel's side (the member's own normal is not known inside the scan; the nearest
    // member's is, and the compose step draws that one across it). In residual units, as
    // the solver works: the band's antialias half-width is 0.7 pixel in them (strokeBand), so
    // the pixel is a / 0.7, and the ratio of the stroke, the distance and the footprint is
    // what the mean reads.
    ValueId memberPixel() { return b_.div(in_.band.a, c(kAntialiasPixels)); }
    ValueId memberHalf() { return b_.mul(in_.stroke, c(0.5)); }
    // The residual past which no member's stroke reaches the pixel, however its normal faces:
    // half the stroke and half the pixel's diagonal.
    ValueId strokeReach() { return b_.add(memberHalf(), b_.mul(memberPixel(), c(kHalfDiagonal))); }
    ValueId memberMean(ValueId value) { return bandMean(value, memberHalf()); }
    // The square pixel's extents across a member's normal, in residual units: the spans of its
    // two sides along the normal (distanceMeanInk's `along` and `across`).
    struct Across {
        ValueId along, across;
    };
    // A box of the pixel's side facing the member, where its normal is not known.
    Across facing() { return {memberPixel(), c(0.0)}; }
    Across across(ValueId gradX, ValueId gradY);
    // The footprint mean of a band of residuals `half` either side of `centre`.
    ValueId bandMean(ValueId centre, ValueId half) { return bandMean(centre, half, facing()); }
    ValueId bandMean(ValueId centre, ValueId half, const Across& foot);
    ValueId paperLeft(ValueId paper, ValueId run);
    ValueId overlapMean(ValueId a, ValueId bv);
    // Past t / 2 + s1 a member's mean is 0 (distanceMeanInk), s1 the footprint's half-span
    // (about 0.52 pixel for the box, 0.71 at most for the square across a diagonal). That is
    // below the guard (h + a, with h >= max(t / 2, 1.15 pixel) and a = 0.7 pixel), so Theorem
    // 4's interval holds every member within it.
    ValueId memberReach() { return memberReach(facing()); }
    ValueId memberReach(const Across& foot);
    Vals sweep();
    template <class PowerFn>
    std::pair<ValueId, ValueId> stridesTurn(ValueId k, const PowerFn& power);
    PhaseSample phaseSample(ValueId distance, ValueId argmin);

    // The crowd under the mean filter: its hand-over, the closed forms' windows and the chains
    // drawn member by member (WalkingCrowd.cpp).
    CrowdEstimate crowd(ValueId nearest, ValueId argmin, ValueId gradX, ValueId gradY);
    std::pair<ValueId, ValueId> closedWindow(ValueId nearest, ValueId argmin, const Across& foot);
    ValueId closedCrowding(ValueId argmin, const Across& foot);
    Vals chains(const TurnPeriod& period, ValueId lo, ValueId end, const Across& foot,
                ValueId picked, ValueId split);
    ChainInputs pointAccess();
    std::pair<ValueId, ValueId> toPixelFrame(ValueId x, ValueId y);
    ValueId farMembersFrom(ValueId end);

    // The crowd's density where it is estimated: few turns' crossings, many turns' arcsine
    // average, its near field and the members that fall on one another (WalkingDensity.cpp).
    Vals crowdDensity(ValueId span);
    // 1 where h < 0, else 0: a sign read with 0 among the positives, so that a residual of
    // exactly 0 (a point on a facet) still makes a sign change with a negative neighbour (a
    // zero product missed that crossing and drew a light line along the facet).
    ValueId negative(ValueId h) { return b_.select(b_.lt(h, c(0.0)), c(1.0), c(0.0)); }
    ValueId changesSign(ValueId h0, ValueId h1);
    ValueId perResidual(ValueId dh);
    // Few turns' members drawn over the pixel's cells (WalkingTurns.cpp).
    static constexpr int kCellsPerSide = 3;
    static constexpr int kCells = kCellsPerSide * kCellsPerSide;
    struct CellFrame {
        std::array<ValueId, kCells> shift; // each cell's centre, in residual from the pixel's
        ValueId side;                      // a cell's side, in residual
    };
    CellFrame cellFrame(ValueId n);
    Vals addToCells(const CellFrame& f, std::span<const ValueId> unions, ValueId before, ValueId h,
                    ValueId reach);
    ValueId memberResidual(ValueId n);
    Vals windowCells(ValueId centre, ValueId left, ValueId right, ValueId floor, ValueId steps,
                     ValueId sigma, ValueId d, ValueId width);
    Vals turnsDrawn(ValueId lo, ValueId hi, ValueId width, ValueId samples);
    ValueId phaseAveraged(ValueId a, ValueId b);
    ValueId countedCrossings(ValueId lo, ValueId hi, ValueId fade);
    ValueId nearDensity(ValueId lo, ValueId hi, ValueId b);
    ValueId branchesInk(ValueId width, ValueId density, ValueId share, ValueId r);
    ValueId arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r);
    ValueId arcsineDensity(ValueId na, ValueId nb, ValueId k, ValueId r, ValueId lo, ValueId hi);
    ValueId vertexChange(ValueId na, ValueId nb, ValueId k, ValueId r);
    ValueId crowdCoincidence(ValueId a, ValueId b, ValueId k, ValueId r, double turns);

    // The index field of §4.1 and its gradient (WalkingFamily.cpp).
    void searchedIndex(ValueId argmin, LayerFields& out);

    ir::Builder& b_;
    const WalkingInputs& in_;
    const RadiusFn& rho_;
    ValueId s_, guard_, accept_, r_, len_, round_, drift_, kappa_;
    ValueId still_, quadratic_, closedPolygon_, wholePolygon_;
    ValueId facetCos_ = ir::kNoValue, facetSin_ = ir::kNoValue; // Rot(2 pi / N), no fast paths
    ValueId nLo_, nHiRaw_;
    ValueId crowdLo_, crowdHiRaw_; // the interval of the pattern's own guard (setUp)
    bool counting_ = true;         // the radius's evaluations go to the tally (countEvaluations)
    // Jumps of up to 2^kCarriedPowers - 1 strides keep the rotation. Most skips are short:
    // on the walking examples 7 and 15 measured alike, 63 slower (a deeper product).
    static constexpr int kCarriedPowers = 3;
    // Convergents of theta / 2 pi the crowd estimate looks through for a period of the turn:
    // their denominators at least double every two steps, so 24 reach past the span cap.
    static constexpr int kCrowdConvergents = 24;
    // Near members counted one by one (countedCrossings); beyond, the phase average.
    static constexpr double kNearCounted = 256;
    // Picked chains (ChainSelection.h): the near members drawn one by one, at most, and how
    // far past n ||delta|| sin(pi / N) = r the far members are taken to start.
    static constexpr double kNearDrawn = 256;
    static constexpr double kFarForm = 1.5;
    // Half a square's diagonal over its side: the farthest its footprint reaches.
    // The rest of the near field: members and angles of its phase average (phaseAveraged).
    static constexpr double kPhaseNodes = 12;
    static constexpr double kPhaseAngles = 24;
    // Members over which the counted crossings hand over to the phase average (nearDensity).
    static constexpr double kSeamFade = 16;
    // The size of a closed form's residual terms, in pixels, up to which its crowd is drawn
    // (closedCrowding): 2^12.
    static constexpr double kFloatReach = 4096;
    // Few turns: h sampled at this many members over the interval at least, and at this many a
    // turn (a polygon: a facet) (turnsDrawn); the arcsine average taking over from kFewTurns
    // to twice as many turns.
    static constexpr double kCrossingSamples = 64;
    static constexpr double kCrossingSamplesPerTurn = 12, kCrossingSamplesPerFacet = 6;
    static constexpr double kFewTurns = 8;
    // A crossing's members drawn either side of it, and up to how many within reach they are
    // drawn rather than taken as a comb (windowCells).
    static constexpr double kCrossingRun = 4;
    // Members drawn either side of the one where h turns within reach of 0 (windowCells).
    static constexpr double kApproachRun = 8;
    std::array<std::pair<ValueId, ValueId>, kCarriedPowers> turnPowers_;
};

} // namespace moire::lower::walking
