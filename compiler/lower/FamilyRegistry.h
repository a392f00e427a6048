// The families the compiler builds itself, by name. A `builtin family` of the standard library
// (stdlib/families.moire) is built by the entry of its name; a layer that walks (`offset` or
// `turn` on a family with facets) by the entry kWalking. Adding one is a new file with its
// builder and one line in FamilyRegistry.cpp (docs/recipes-lowering.md).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/WalkingVariant.h"

#include <functional>
#include <string_view>
#include <vector>

namespace moire::lower {

// A family's phase (a walking family's radius) at the point (qx, qy) of the layer's frame,
// emitted at the builder's current position.
using PhaseFn = std::function<ir::ValueId(ir::Builder&, ir::ValueId qx, ir::ValueId qy)>;

// A field encoded into a layer (§10.1): the phase becomes phi - gain s f.
struct Encoding {
    ir::ValueId field = ir::kNoValue, gain = ir::kNoValue;
};

// Where a layer's family is evaluated: its own frame, q = Rot(-rotation) (p - origin).
struct LayerFrame {
    ir::ValueId qx, qy; // the point in the layer's frame
    ir::ValueId dx, dy; // p - origin, in world axes
    ir::ValueId spacing, phase;
    // The angle the layer's frame turns from the world's (its rotation and the viewer's turn):
    // a world offset o moves q by Rot(-turn) o. kNoValue: it does not turn.
    ir::ValueId turn = ir::kNoValue;
};

// What a compiler-built family is given.
struct FamilyInputs {
    LayerFrame at;            // the pixel in the layer's frame
    std::vector<Vals> params; // the family's arguments, lowered, in declaration order
    StrokeBand band;
    Encoding enc;
    bool wantIndex = false;      // also the index field (the layer's fields are output)
    bool tally = false;          // count the evaluations of the phase (LowerOptions::tally)
    WalkingVariant walking = {}; // the walking solver's variant (LowerOptions::walking)
    // The view sweeps the layers' indices (sema::viewSweeps): the family also gives its phase
    // sample (LayerFields::sample).
    bool sweeps = false;
    // The mean filter is drawn: a family that can estimate its crowd of members where it cannot
    // resolve them gives it (LayerFields::crowd).
    bool crowd = false;
    // With crowd: the camera's turn, which takes the world's axes to the pixel's sides (the
    // pixel's footprint across a member's normal, Prefilter.h: onPixelSides).
    ir::ValueId cosTurn = ir::kNoValue, sinTurn = ir::kNoValue;
    // For the families that evaluate their phase elsewhere than at the pixel (walking).
    PhaseFn phaseAt;
    ir::ValueId facets = ir::kNoValue; // a shape's side count (0: a circle), for walking
    // Another property of the layer, written or its default.
    std::function<Vals(std::string_view)> layerProp;
};

using FamilyBuilder = std::function<LayerFields(ir::Builder&, const FamilyInputs&)>;

struct RegisteredFamily {
    const char* name;
    FamilyBuilder build;
};

// The name the walking solver is registered under.
constexpr const char kWalking[] = "walking";

// Every registered family, in registration order.
const std::vector<RegisteredFamily>& registeredFamilies();
// The builder registered as `name`; an internal error when there is none (the standard
// library declares a builtin family that nothing builds: a bug in moire).
const FamilyBuilder& familyBuilder(std::string_view name);

} // namespace moire::lower
