// The mean filter's union of fine layers (docs/filtering.md, "Fine layers together"). Each
// layer's footprint mean (Prefilter.h) laid over the others is the union of the means: right
// where the layers' phases are independent across the pixel, wrong where two fine families are
// correlated, as they are wherever their beat D (for a pair swept together, D = f1 - f2, or
// f1 + f2 for a sum beat) runs slowly across the pixel while their members do not. There the
// pixel holds Phi(D), the fringe law's mean ink of the pair at offset D (§4.1, Eq. 7), which
// is the envelope's sweep (Envelope.h, sweptInk): the stack's ink averaged over one period of
// every layer's index advanced together. Its departure from the union of the layers' own
// swept means is the stack's correlation, and it is added to the union of the footprint means
// with the weight the pixel's footprint leaves it (FineUnion.cpp): the moiré of two families
// that neither are resolved shows as the box-filtered field shows it.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/Envelope.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

#include <vector>

namespace moire::lower {

// Taps of the sweep (Envelope.h's M) for the union: the envelope view's default.
constexpr double kUnionTaps = 24;

// One layer of a run of fine layers: as the envelope sweeps it, and as the mean filter
// measures it (its index gradient, its first member).
struct FineLayer {
    EnvelopeLayer sweep;
    Footprint footprint;
};

// Whether a layer can join a run: a phase family with a footprint and a one-index phase
// sample (lattices, morphs, walking and distance families are laid over on their own).
bool joinsFineUnion(const Footprint& footprint, const PhaseSample& sample);

// The transfer of a pixel's footprint to the fundamental of a periodic ink whose index spans
// `along` and `across` units over the pixel's two sides: the square pixel's mean of
// cos(2 pi index) is sinc(along) sinc(across) times its value at the centre, sinc(x) =
// sin(pi x) / (pi x). Each factor is held at 0 past its first zero (x >= 1), where a side
// spans a whole period: the remaining lobes are small and of either sign. Written once as a
// template: over IR values in the kernel, over double in the tests.
template <class T>
T footprintTransfer(T along, T across) {
    using ir::literal;
    using std::max;
    using std::min;
    using std::sin;
    auto sinc = [&](T x) {
        T t = min(max(x, literal(x, 1e-4)), literal(x, 1.0));
        return sin(t * 3.14159265358979323846) / (t * 3.14159265358979323846);
    };
    return sinc(along) * sinc(across);
}

// The run's pixel: `under` is the ink beneath the run (premultiplied), `independent` the run's
// layers' inks laid over it one by one (the union of their means). Returns the pixel with the
// run's correlation added where the footprint leaves it (a run of one layer: `independent`).
// Computed behind a branch: a pixel where fewer than two of the run's layers are past the
// unresolved threshold (kCrowdFrom) pays a handful of instructions.
Ink fineUnion(ir::Builder& b, const Ink& under, const Ink& independent,
              const std::vector<FineLayer>& run, const PixelFootprint& pixel);

} // namespace moire::lower
