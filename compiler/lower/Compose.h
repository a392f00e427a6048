// The compose step: the layers' fields at the pixel, in order, to the pixel's colour. How they
// combine is the view (sema/Views.h); the layers' lowering knows nothing of it, so another view
// of a moiré is another case here (docs/recipes-lowering.md, docs/views.md).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/Envelope.h"
#include "compiler/lower/FineUnion.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/Prefilter.h"
#include "compiler/lower/StrokePairs.h"
#include "compiler/sema/Views.h"

#include <functional>
#include <vector>

namespace moire::lower {

using sema::ViewMode;

// What the compose step is given of one layer.
struct LayerInk {
    LayerFields fields;
    StrokeBand band; // as drawn: the half-width held at the hairline floor (Eq. 35)
    ir::ValueId halfWidth = ir::kNoValue; // the stroke's own, for the views that average ink
    Vals color;                           // r, g, b, a
    ir::ValueId opacity;
    ir::ValueId spacing = ir::kNoValue; // the layer's nominal pitch
    // The pixel under the mean filter (lower/Prefilter.h): a phase family's ink is then
    // averaged over the pixel where its members are finer than pixels. Its size kNoValue: the
    // point filter.
    PixelFootprint pixel;
    // gain s |grad f| of a layer that encodes a field (LayerLowering::sampling), or kNoValue.
    ir::ValueId sampling = ir::kNoValue;
    SourceLoc where; // the layer, for the instructions built from it
};

class Compose {
  public:
    // Starts from the paper (straight RGBA). `envelope` is read by the views that show it.
    // With `overlayPixel` (the world size of a pixel), the fringe overlay is laid over the
    // view (RatioView.h).
    Compose(ir::Builder& b, ViewMode mode, const Vals& background,
            const EnvelopeSettings& envelope = {}, ir::ValueId overlayPixel = ir::kNoValue);

    // Adds the next layer, bottom to top.
    void layer(const LayerInk& ink);
    // Outputs the pixel's straight RGBA to slots 0-3. `unresolvedTint` gives the scene's
    // `unresolved` colour; it is lowered only when a layer encodes a field (and never when
    // the function is empty: a print separation).
    void output(const std::function<Vals()>& unresolvedTint);

  private:
    Ink envelope();
    Ink split();
    void closeRun(); // takes the union of the run of fine layers laid so far (FineUnion.h)
    // Under the mean filter, adds the covariance of the layer's nearest stroke with those laid
    // before it (StrokePairs.h); `cov` is its coverage, `under` the ink it was laid over.
    // A lattice's lines are met as strokes of their own (`strands`, StrokePairs.h).
    void meetStrokes(const LayerInk& ink, ir::ValueId cov, const Ink& under,
                     const std::vector<StrokeAcross>& strands);

    ir::Builder& b_;
    ViewMode mode_;
    Ink paper_;
    Ink acc_; // the pattern so far
    EnvelopeSettings settings_;
    std::vector<EnvelopeLayer> sweep_; // the layers as the envelope reads them
    std::vector<LayerFields> fields_;  // the layers as the characters read them
    ir::ValueId overlayPixel_;
    ir::ValueId zero_;
    ir::ValueId unresolved_; // the largest gain s |grad f| of the encoded layers
    // Under the mean filter, the phase families laid since the last other layer, the ink
    // beneath them, and the pixel (FineUnion.h).
    std::vector<FineLayer> run_;
    Ink runUnder_{};
    Ink lastUnder_{}; // the ink beneath the run's last layer, which a closed pair hands on
    PixelFootprint runPixel_;
    // Under the mean filter, the layers laid whose nearest stroke is known, each with what its
    // covariance with a later layer's stroke adds to the pixel per unit of that layer's
    // coverage: k_i (acc_{i-1} - c_i) times (1 - coverage) of every layer laid since
    // (StrokePairs.h).
    struct Laid {
        StrokeAcross stroke;
        Ink pending;
    };
    std::vector<Laid> laid_;
    bool laidAlike() const;
    Laid laidAt(ir::ValueId at);
};

} // namespace moire::lower
