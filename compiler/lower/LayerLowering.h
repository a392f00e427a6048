// One layer's fields at the pixel: the layer's frame (origin, rotation, the viewer's motion),
// its family bound to its arguments, and the fields by the kind of family: a phase family
// (Eq. 5), a distance family, a compiler-built family (FamilyRegistry), or a morph between
// families (MorphFamily).
#pragma once

#include "compiler/lower/FamilyRegistry.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"
#include "compiler/lower/SceneContext.h"

#include <functional>
#include <optional>
#include <utility>

namespace moire::lower {

// One family with a layer's arguments lowered, ready to be evaluated at any point of the
// layer's frame. Null for a layer that writes its phase itself.
struct BoundFamily {
    const sema::CheckedFamily* family = nullptr;
    std::vector<Vals> params;
};

class LayerLowering {
  public:
    explicit LayerLowering(SceneContext& ctx) : ctx_(ctx) {}

    Encoding encoding(const sema::CheckedLayer& layer);
    // gain s |grad f|, whose reciprocal is the fringe spacing in carrier pitches.
    ir::ValueId sampling(const sema::CheckedLayer& layer, const Encoding& enc);
    // The fields of one layer: its family's, or a morph's blend of its families'.
    LayerFields fields(const sema::CheckedLayer& layer, const StrokeBand& band, const Encoding& enc,
                       bool wantIndex);

    // The pieces a morph (MorphFamily.cpp) is made of.
    SceneContext& context() { return ctx_; }
    BoundFamily bind(const sema::CheckedFamily* family, const std::vector<const ast::Expr*>& args);
    // The family's expressions at a point of its frame.
    Frame frameAt(const BoundFamily& bf, const LayerFrame& lf, ir::ValueId x, ir::ValueId y);
    ir::ValueId phaseAt(const sema::CheckedLayer& layer, const BoundFamily& bf,
                        const LayerFrame& lf, ir::ValueId x, ir::ValueId y);
    // Whether the layer draws this family by the walking solver.
    static bool walks(const sema::CheckedLayer& layer, const sema::CheckedFamily* family);
    LayerFields familyFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                             const BoundFamily& bf, const StrokeBand& band, const Encoding& enc,
                             bool wantIndex);
    LayerFields phaseFields(const sema::CheckedLayer& layer, const LayerFrame& lf, ir::ValueId phi,
                            std::optional<int> first, const Encoding& enc,
                            ir::ValueId near = ir::kNoValue);
    // Under the mean filter, where a phase family's index folds or bends within the pixel, the
    // pixel read in parts (Prefilter.h: bentIndexMean), the phase read by `phiAt` at points of
    // the layer's frame, less the field the layer encodes (read at each part too):
    // fields.footprint's `bent` and `bentMean`.
    using PhaseAtPoint = std::function<ir::ValueId(ir::ValueId x, ir::ValueId y)>;
    void readWhereBent(LayerFields& fields, const sema::CheckedLayer& layer, const LayerFrame& lf,
                       const StrokeBand& band, std::optional<int> first, const Encoding& enc,
                       const PhaseAtPoint& phiAt);
    // Under the mean filter, where the footprint of a family with a first member reaches
    // below it or its index bends, the pixel read in parts (Prefilter.h: belowFirstMean):
    // fields.footprint's `belowMean`, `bent` and `bentMean`. `phases` gives a part's phase (at
    // the world offset from the pixel's point), the phase off a fold through it and the
    // members' level there, as phaseFamilyFields takes them.
    struct PartPhase {
        ir::ValueId phi, near, level;
    };
    using PhasesAt = std::function<PartPhase(ir::Builder& b, ir::ValueId ox, ir::ValueId oy)>;
    void readBelowFirst(LayerFields& fields, const LayerFrame& lf, const StrokeBand& band,
                        ir::ValueId halfWidth, int first, const PhasesAt& phases,
                        const IndexAt& indexAt);
    // What a registered builder is given for this layer (FamilyInputs), with `phaseAt` and
    // `facets` left for the caller.
    FamilyInputs inputs(const sema::CheckedLayer& layer, const LayerFrame& lf,
                        const BoundFamily& bf, const StrokeBand& band, const Encoding& enc,
                        bool wantIndex);

  private:
    static std::pair<ir::ValueId, ir::ValueId> movedBy(ir::Builder& b, const LayerFrame& lf,
                                                       ir::ValueId ox, ir::ValueId oy);
    PixelFootprint pixelOf(const StrokeBand& band);
    ir::ValueId fieldAt(const sema::CheckedLayer& layer, ir::ValueId ox, ir::ValueId oy);
    static ir::ValueId levelOf(ir::Builder& b, const LayerFrame& lf, const Encoding& enc,
                               ir::ValueId field);
    static std::pair<ir::ValueId, ir::ValueId> offFold(ir::Builder& b, ir::ValueId x,
                                                       ir::ValueId y);
    SceneContext& ctx_;
};

} // namespace moire::lower
