// What every step of the scene's lowering shares: the checked scene, the options, the
// builder and expression lowering, the timings, and the two frames expressions are lowered
// in (the pixel's world point, and the constant frame of the scene's settings).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/LowerScene.h"
#include "compiler/lower/Timings.h"
#include "compiler/sema/Sema.h"

namespace moire::lower {

struct SceneContext {
    const sema::CheckedScene& scene;
    const LowerOptions& options;
    ir::Builder& b;
    ExprLowering& exprs;
    TimingLowering& timings;
    int probeSlot = -1, viewSlot = -1; // as in LoweredScene
    Frame world;                       // x and y: the pixel's world point (set by the camera)
    Frame constantFrame;               // scene settings cannot use x or y (checked)
    int pixelSlot = -1;                // as in LoweredScene
    // The camera's turn, where it has one: the pixel's sides run along the world's axes turned
    // by it (the mean filter's footprint, Prefilter.h). kNoValue: no turn.
    ir::ValueId cosTurn = ir::kNoValue, sinTurn = ir::kNoValue;

    bool interactive() const { return viewSlot >= 0; }
    // A literal slot of interactive mode (ViewSlots).
    ir::ValueId viewParam(int slot) { return b.param(viewSlot + slot); }
    // A scene or camera setting (`block` may be null), written or its default.
    Vals setting(const ast::Decl* block, const std::vector<sema::PropertySpec>& table,
                 std::string_view name) {
        return exprs.property(block, table, name, constantFrame);
    }
    // A layer's property at the pixel, written or its default.
    Vals layerProp(const sema::CheckedLayer& layer, std::string_view name) {
        return exprs.property(layer.decl, sema::layerProperties(), name, world);
    }
};

} // namespace moire::lower
