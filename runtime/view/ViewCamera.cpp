#include "runtime/view/ViewCamera.h"

#include "compiler/lower/LowerScene.h"
#include "runtime/FrameEval.h"

#include <algorithm>
#include <cmath>

namespace moire::view {

using lower::ViewSlots;

SceneCamera SceneCamera::from(const FrameValues& frame) {
    SceneCamera c;
    c.centerX = frame.centerX;
    c.centerY = frame.centerY;
    c.turn = frame.turn;
    c.zoom = frame.zoom;
    c.sceneWidth = frame.sceneWidth;
    c.sceneHeight = frame.sceneHeight;
    return c;
}

Vec2 LayerMotion::apply(Vec2 p) const {
    const ir::Vec2T<double> r = ir::rotate<double>({p.x, p.y}, turn);
    return {r.x + dx, r.y + dy};
}

void ViewAdjust::reset() {
    *this = ViewAdjust{};
}

LayerMotion ViewAdjust::layer(int i) const {
    return i >= 0 && i < static_cast<int>(layers.size()) ? layers[i] : LayerMotion{};
}

LayerMotion& ViewAdjust::layerRef(int i) {
    if (i >= static_cast<int>(layers.size())) layers.resize(i + 1);
    return layers[i];
}

void ViewAdjust::write(std::vector<double>& literals, int viewSlot, int numLayers) const {
    if (viewSlot < 0 || viewSlot + ViewSlots::count(numLayers) > static_cast<int>(literals.size()))
        return;
    literals[viewSlot + ViewSlots::kPanX] = panX;
    literals[viewSlot + ViewSlots::kPanY] = panY;
    literals[viewSlot + ViewSlots::kZoomFactor] = zoomFactor;
    for (int i = 0; i < numLayers; ++i) {
        const LayerMotion m = layer(i);
        literals[viewSlot + ViewSlots::layer(i, ViewSlots::kLayerDx)] = m.dx;
        literals[viewSlot + ViewSlots::layer(i, ViewSlots::kLayerDy)] = m.dy;
        literals[viewSlot + ViewSlots::layer(i, ViewSlots::kLayerTurn)] = m.turn;
    }
}

ViewCamera::ViewCamera(const SceneCamera& scene, const ViewAdjust& view, int width, int height) {
    cam_.width = std::max(width, 1);
    cam_.height = std::max(height, 1);
    cam_.center = {scene.centerX + view.panX, scene.centerY + view.panY};
    cam_.cosTurn = std::cos(scene.turn);
    cam_.sinTurn = std::sin(scene.turn);
    const double fit =
        lower::fitScale(scene.sceneWidth, scene.sceneHeight, cam_.width, cam_.height);
    cam_.pixel = fit / (scene.zoom * view.zoomFactor);
}

Vec2 ViewCamera::toWorld(Vec2 p) const {
    const ir::Vec2T<double> w = lower::toWorld(cam_, {p.x, p.y});
    return {w.x, w.y};
}

Vec2 ViewCamera::toPixel(Vec2 world) const {
    const ir::Vec2T<double> p = lower::toPixel(cam_, {world.x, world.y});
    return {p.x, p.y};
}

Vec2 ViewCamera::deltaToWorld(Vec2 d) const {
    const ir::Vec2T<double> w = lower::deltaToWorld(cam_, {d.x, d.y});
    return {w.x, w.y};
}

void zoomAbout(const SceneCamera& scene, ViewAdjust& view, int width, int height, Vec2 at,
               double factor) {
    if (!(factor > 0.0) || !std::isfinite(factor)) return;
    const Vec2 before = ViewCamera(scene, view, width, height).toWorld(at);
    view.zoomFactor *= factor;
    const Vec2 after = ViewCamera(scene, view, width, height).toWorld(at);
    // The centre moves by what the point under the cursor would otherwise have slid.
    view.panX += before.x - after.x;
    view.panY += before.y - after.y;
}

void panDrag(const SceneCamera& scene, ViewAdjust& view, int width, int height, Vec2 from,
             Vec2 to) {
    const Vec2 d =
        ViewCamera(scene, view, width, height).deltaToWorld({to.x - from.x, to.y - from.y});
    // Dragging the picture right moves the camera left over the world.
    view.panX -= d.x;
    view.panY -= d.y;
}

void moveLayer(const SceneCamera& scene, ViewAdjust& view, int width, int height, int layer,
               Vec2 from, Vec2 to) {
    if (layer < 0) return;
    const Vec2 d =
        ViewCamera(scene, view, width, height).deltaToWorld({to.x - from.x, to.y - from.y});
    // The motion's offset is applied after its turn, in world axes, so a world displacement
    // adds to it as it is: the layer follows the cursor whatever the layer's or camera's turn.
    LayerMotion& m = view.layerRef(layer);
    m.dx += d.x;
    m.dy += d.y;
}

void turnLayer(const SceneCamera& scene, ViewAdjust& view, int width, int height, int layer,
               Vec2 from, Vec2 to) {
    if (layer < 0) return;
    const ViewCamera cam(scene, view, width, height);
    // Angles measured in the world about the world origin: the camera's turn and the screen's
    // flipped y are then accounted for by toWorld.
    const Vec2 a = cam.toWorld(from), b = cam.toWorld(to);
    if ((a.x == 0.0 && a.y == 0.0) || (b.x == 0.0 && b.y == 0.0)) return;
    const double angle = std::atan2(a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y);
    // Rot(angle) applied after p -> Rot(turn) p + d gives Rot(turn + angle) p + Rot(angle) d.
    LayerMotion& m = view.layerRef(layer);
    const ir::Vec2T<double> d = ir::rotate<double>({m.dx, m.dy}, angle);
    m.dx = d.x;
    m.dy = d.y;
    m.turn += angle;
}

Preview previewOf(const SceneCamera& scene, const ViewAdjust& view, int width, int height,
                  int divisor) {
    Preview p;
    p.view = view;
    const int d = std::max(divisor, 1);
    p.width = (std::max(width, 1) + d - 1) / d;
    p.height = (std::max(height, 1) + d - 1) / d;
    const ViewCamera full(scene, view, width, height);
    // The preview's pixel is `d` full pixels wide...
    const double fit =
        lower::fitScale<double>(scene.sceneWidth, scene.sceneHeight, p.width, p.height);
    p.view.zoomFactor = fit / (scene.zoom * d * full.pixelSize());
    // ... and its corner sits on the full frame's corner: the centre moves by the overhang.
    const double ox = 0.5 * (p.width * d - width), oy = 0.5 * (p.height * d - height);
    const Vec2 shift = full.deltaToWorld({ox, oy});
    p.view.panX += shift.x;
    p.view.panY += shift.y;
    return p;
}

} // namespace moire::view
