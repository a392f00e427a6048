// The compose step: the layers' fields at the pixel, in order, to the pixel's colour. How they
// combine is the view mode; the layers' lowering knows nothing of it, so another view (the
// envelope, ratio or overlay of a moiré) is another mode here (docs/recipes-lowering.md).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerExpr.h"

#include <functional>

namespace moire::lower {

enum class ViewMode {
    Pattern, // the picture: each layer's strokes inked over the paper, in order (§3.4)
};

// What the compose step is given of one layer.
struct LayerInk {
    LayerFields fields;
    StrokeBand band;
    Vals color; // r, g, b, a
    ir::ValueId opacity;
    // gain s |grad f| of a layer that encodes a field (LayerLowering::sampling), or kNoValue.
    ir::ValueId sampling = ir::kNoValue;
    SourceLoc where; // the layer, for the instructions built from it
};

class Compose {
  public:
    // Starts from the paper (straight RGBA).
    Compose(ir::Builder& b, ViewMode mode, const Vals& background);

    // Adds the next layer, bottom to top.
    void layer(const LayerInk& ink);
    // Outputs the pixel's straight RGBA to slots 0-3. `unresolvedTint` gives the scene's
    // `unresolved` colour; it is lowered only when a layer encodes a field.
    void output(const std::function<Vals()>& unresolvedTint);

  private:
    ir::Builder& b_;
    ViewMode mode_;
    Ink acc_;
    ir::ValueId zero_;
    ir::ValueId unresolved_; // the largest gain s |grad f| of the encoded layers
};

} // namespace moire::lower
