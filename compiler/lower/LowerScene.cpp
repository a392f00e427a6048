// The scene's lowering, in order: the slots the mode reads, the camera, each layer's fields
// composed into the pixel, then the settings the frame reads (timings, checked values).
#include "compiler/lower/LowerScene.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/lower/Camera.h"
#include "compiler/lower/Compose.h"
#include "compiler/lower/LayerLowering.h"
#include "compiler/lower/SceneContext.h"
#include "compiler/lower/ValueChecks.h"

namespace moire::lower {

namespace {

// Appends the literal slots the mode reads to the table, set to the scene's own view.
void reserveSlots(const LowerOptions& options, int numLayers, std::vector<double>& literals,
                  LoweredScene& out) {
    const LowerMode mode = options.mode;
    const int first = static_cast<int>(literals.size());
    if (options.pixelSlot) {
        MOIRE_CHECK(mode == LowerMode::Render, "a pixel size slot outside render mode");
        out.pixelSlot = first;
        literals.push_back(1.0); // evaluateFrame sets it for each frame
    }
    if (mode == LowerMode::Probe) {
        out.probeSlot = first;
        literals.resize(literals.size() + 2, 0.0); // the probe point: the origin
    }
    if (mode == LowerMode::Interactive) {
        // The identity view: no pan, zoom factor 1, no layer moved or turned.
        out.viewSlot = first;
        literals.resize(literals.size() + ViewSlots::count(numLayers), 0.0);
        literals[out.viewSlot + ViewSlots::kZoomFactor] = 1.0;
    }
}

// A scene setting written as a name: the options' when they set it, else the scene's
// property `prop` read by `named`, else `fallback`.
template <class T, class Named>
T namedSetting(const sema::CheckedScene& scene, const char* prop, const std::optional<T>& given,
               T fallback, Named named) {
    if (given) return *given;
    const ast::Property* p = scene.scene ? scene.scene->prop(prop) : nullptr;
    if (!p) return fallback;
    std::optional<T> value = named(p->value->name);
    MOIRE_CHECK(value, "a name that is not one of the setting's survived checking");
    return *value;
}

// The view: the options', else the scene's `view`, else the pattern.
sema::ViewMode viewOf(const sema::CheckedScene& scene, const LowerOptions& options) {
    return namedSetting(scene, "view", options.view, sema::ViewMode::Pattern, sema::viewNamed);
}

// The fringe overlay: the options', else the scene's `overlay`, else off.
bool overlayOf(const sema::CheckedScene& scene, const LowerOptions& options) {
    return namedSetting(scene, "overlay", options.overlay, false, sema::switchNamed);
}

} // namespace

sema::FilterMode filterOf(const sema::CheckedScene& scene,
                          const std::optional<sema::FilterMode>& given) {
    return namedSetting(scene, "filter", given, sema::FilterMode::Mean, sema::filterNamed);
}

LoweredScene lowerScene(const sema::CheckedScene& scene, const LowerOptions& options,
                        std::vector<double>& literals) {
    LoweredScene out;
    OutputLayout& layout = out.layout;
    layout.numLayers = static_cast<int>(scene.layers.size());
    layout.layerFields = options.layerFields;
    layout.numKernelOutputs =
        4 + (options.layerFields ? OutputLayout::kFieldsPerLayer * layout.numLayers : 0);
    reserveSlots(options, layout.numLayers, literals, out);

    out.function.name = "scene";
    ir::Builder b(out.function);
    ExprLowering exprs(b);
    TimingLowering timings(b, exprs, scene);
    exprs.setTimings([&](const ast::Decl* timing) { return timings.progress(timing); });
    // The options with the view settled (the scene's, unless the options name one), so that
    // every step of the lowering reads the view drawn.
    LowerOptions settled = options;
    settled.view = out.view = viewOf(scene, options);
    settled.overlay = out.overlay = overlayOf(scene, options);
    const bool separation = options.separate.has_value();
    if (separation) { // a print separation is the layer's ink alone
        MOIRE_CHECK(!options.layerFields && *options.separate >= 0 &&
                        *options.separate < layout.numLayers,
                    "a separation of a layer the scene does not have");
        settled.view = out.view = sema::ViewMode::Pattern;
        settled.overlay = out.overlay = false;
    }
    const sema::FilterMode filter = filterOf(scene, options.filter);
    // The ratio view and the overlay read every layer's index field and its gradient, and the
    // envelope's sweep reads the gradients (a walking layer has them only with its index); so
    // does the mean filter, across a walking layer's members (distanceInk), in every view, so
    // that the pattern a view draws beside another is the pattern view's.
    const bool wantIndex = layout.layerFields || out.overlay ||
                           sema::viewReadsCharacters(out.view) || sema::viewSweeps(out.view) ||
                           filter == sema::FilterMode::Mean;
    settled.filter = filter;
    SceneContext ctx{scene, settled, b, exprs, timings, out.probeSlot, out.viewSlot, {}, {}};
    ctx.pixelSlot = out.pixelSlot;

    // 1. The frame's size and camera; the pixel's world point.
    const ir::ValueId pixel = lowerCamera(ctx, layout.numKernelOutputs);

    // 2. Each layer's fields, composed over the paper by the view.
    auto sceneNumber = [&](const char* name, std::optional<double> given) {
        if (given) return b.constF(*given);
        return ctx.setting(scene.scene, sema::sceneProperties(), name)[0];
    };
    EnvelopeSettings envelope;
    if (sema::viewSweeps(out.view)) {
        envelope.gain = sceneNumber("envelope_gain", options.envelopeGain);
        envelope.taps = sceneNumber("envelope_taps", options.envelopeTaps);
    }
    // A separation is laid on a transparent paper (docs/print.md: the paper's colour, then
    // each sheet over it, gives the whole picture back).
    const Vals paperColor = separation
                                ? Vals(4, b.constF(0.0))
                                : ctx.setting(scene.scene, sema::sceneProperties(), "background");
    Compose compose(b, out.view, paperColor, envelope, out.overlay ? pixel : ir::kNoValue);
    LayerLowering layers(ctx);
    ValueChecks checks(ctx);
    for (size_t i = 0; i < scene.layers.size(); ++i) {
        const sema::CheckedLayer& layer = scene.layers[i];
        if (separation && static_cast<int>(i) != *options.separate) {
            checks.layer(layer); // its values are checked as in the whole picture
            continue;
        }
        LayerInk ink;
        ink.color = ctx.layerProp(layer, "color");
        ir::ValueId stroke = ctx.layerProp(layer, "stroke")[0];
        ink.opacity = ctx.layerProp(layer, "opacity")[0];
        checks.layer(layer);
        ink.where = layer.decl->range.begin;
        b.setLoc(ink.where);
        ink.band = strokeBand(b, stroke, pixel, options.strokeFloor);
        ink.halfWidth = b.mul(stroke, b.constF(0.5));
        ink.spacing = ctx.layerProp(layer, "spacing")[0];
        if (filter == sema::FilterMode::Mean) ink.pixel = {pixel, ctx.cosTurn, ctx.sinTurn};
        Encoding enc = layers.encoding(layer);
        ink.fields = layers.fields(layer, ink.band, enc, wantIndex);
        if (enc.field != ir::kNoValue) ink.sampling = layers.sampling(layer, enc);
        if (sema::viewSweeps(out.view) && ink.fields.sample.z == ir::kNoValue)
            out.unsweepable.push_back(static_cast<int>(i));
        compose.layer(ink);
        if (layout.layerFields) {
            const int at = static_cast<int>(i);
            const LayerFields& f = ink.fields;
            auto orZero = [&](ir::ValueId v) { return v == ir::kNoValue ? b.constF(0.0) : v; };
            b.output(layout.indexSlot(at), f.index);
            b.output(layout.distanceSlot(at), f.distance);
            b.output(layout.gradXSlot(at), orZero(f.gradX));
            b.output(layout.gradYSlot(at), orZero(f.gradY));
            b.output(layout.aux0Slot(at), orZero(f.aux0));
            b.output(layout.aux1Slot(at), orZero(f.aux1));
        }
    }

    // 3. The pixel's colour.
    std::function<Vals()> unresolved;
    if (!separation)
        unresolved = [&] {
            return ctx.setting(scene.scene, sema::sceneProperties(), "unresolved");
        };
    compose.output(unresolved);

    // 4. The settings the frame reads: the timings used (clips' loop lengths, the frame's
    // checks), then the values the frame checks before drawing them (ValueCheck).
    timings.outputSettings(layout, layout.numKernelOutputs + OutputLayout::kNumSettings);
    checks.params(scene);
    checks.output(layout);
    out.function.numOutputs = layout.numKernelOutputs + layout.numSettings();
    ir::verify(out.function);
    return out;
}

} // namespace moire::lower
