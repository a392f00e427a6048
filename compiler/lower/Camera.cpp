#include "compiler/lower/Camera.h"

#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/CameraModel.h"

namespace moire::lower {

using ir::BuiltValue;
using ir::Op;
using ir::ValueId;

ValueId lowerCamera(SceneContext& ctx, int settingsBase) {
    ir::Builder& b = ctx.b;
    const ast::Decl* camera = ctx.scene.camera;
    auto built = [&](ValueId v) { return BuiltValue(b, v); };

    Vals size = ctx.setting(ctx.scene.scene, sema::sceneProperties(), "size");
    b.output(settingsBase + OutputLayout::kSettingWidth, size[0]);
    b.output(settingsBase + OutputLayout::kSettingHeight, size[1]);

    const bool probe = ctx.probeSlot >= 0;
    Vals center = ctx.setting(camera, sema::cameraProperties(), "center");
    if (probe) center = {b.param(ctx.probeSlot), b.param(ctx.probeSlot + 1)};
    ValueId zoom = ctx.setting(camera, sema::cameraProperties(), "zoom")[0];
    const bool turned = camera && camera->prop("rotation");
    ValueId turn = ctx.setting(camera, sema::cameraProperties(), "rotation")[0];
    b.output(settingsBase + OutputLayout::kSettingZoom, zoom);
    b.output(settingsBase + OutputLayout::kSettingCenterX, center[0]);
    b.output(settingsBase + OutputLayout::kSettingCenterY, center[1]);
    b.output(settingsBase + OutputLayout::kSettingTurn, turn);
    if (ctx.interactive()) {
        center = {b.add(center[0], ctx.viewParam(ViewSlots::kPanX)),
                  b.add(center[1], ctx.viewParam(ViewSlots::kPanY))};
        zoom = b.mul(zoom, ctx.viewParam(ViewSlots::kZoomFactor));
    }
    b.setLoc({});
    CameraT<BuiltValue> cam;
    cam.width = built(b.leaf(Op::ImageW));
    cam.height = built(b.leaf(Op::ImageH));
    // A probe's image is one pixel on the chosen point: its pixel is the world's unit.
    BuiltValue fit = probe ? built(b.constF(1.0))
                           : fitScale(built(size[0]), built(size[1]), cam.width, cam.height);
    cam.pixel = fit / built(zoom);
    // A pixel size set from outside (`moire print`: a physical scale on a canvas of its own)
    // is the world size of a pixel as it stands, the camera's zoom included.
    if (ctx.pixelSlot >= 0) cam.pixel = built(b.param(ctx.pixelSlot));
    cam.turned = turned;
    if (turned) {
        cam.cosTurn = cos(built(turn));
        cam.sinTurn = sin(built(turn));
        ctx.cosTurn = cam.cosTurn.id;
        ctx.sinTurn = cam.sinTurn.id;
    }
    // The default centre is the origin; adding 0 would cost two ops per pixel.
    cam.centred = ctx.interactive() || probe || (camera && camera->prop("center"));
    cam.center = {built(center[0]), built(center[1])};
    ir::Vec2T<BuiltValue> w =
        toWorld(cam, ir::Vec2T<BuiltValue>{built(b.leaf(Op::PixelX)), built(b.leaf(Op::PixelY))});
    // Everything downstream is differentiated with respect to these two values.
    ctx.world.x = b.emit(Op::Indep, {w.x.id}, 0.0, 0);
    ctx.world.y = b.emit(Op::Indep, {w.y.id}, 0.0, 1);
    return cam.pixel.id;
}

} // namespace moire::lower
