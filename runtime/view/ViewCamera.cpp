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
    const double c = std::cos(turn), s = std::sin(turn);
    return {c * p.x - s * p.y + dx, s * p.x + c * p.y + dy};
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

ViewCamera::ViewCamera(const SceneCamera& scene, const ViewAdjust& view, int width, int height)
    : w_(std::max(width, 1)), h_(std::max(height, 1)), cx_(scene.centerX + view.panX),
      cy_(scene.centerY + view.panY), cos_(std::cos(scene.turn)), sin_(std::sin(scene.turn)) {
    const double fit = std::max(scene.sceneWidth / w_, scene.sceneHeight / h_);
    pixel_ = fit / (scene.zoom * view.zoomFactor);
}

Vec2 ViewCamera::toWorld(Vec2 p) const {
    const double sx = p.x - 0.5 * w_, sy = 0.5 * h_ - p.y;
    return {cx_ + (cos_ * sx - sin_ * sy) * pixel_, cy_ + (sin_ * sx + cos_ * sy) * pixel_};
}

Vec2 ViewCamera::toPixel(Vec2 world) const {
    const double rx = (world.x - cx_) / pixel_, ry = (world.y - cy_) / pixel_;
    // Rot(-turn) undoes the camera's turn.
    const double sx = cos_ * rx + sin_ * ry, sy = -sin_ * rx + cos_ * ry;
    return {sx + 0.5 * w_, 0.5 * h_ - sy};
}

Vec2 ViewCamera::deltaToWorld(Vec2 d) const {
    // Screen y points down, world y up.
    return {(cos_ * d.x + sin_ * d.y) * pixel_, (sin_ * d.x - cos_ * d.y) * pixel_};
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
    const double c = std::cos(angle), s = std::sin(angle);
    const double dx = c * m.dx - s * m.dy, dy = s * m.dx + c * m.dy;
    m.dx = dx;
    m.dy = dy;
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
    const double fit = std::max(scene.sceneWidth / p.width, scene.sceneHeight / p.height);
    p.view.zoomFactor = fit / (scene.zoom * d * full.pixelSize());
    // ... and its corner sits on the full frame's corner: the centre moves by the overhang.
    const double ox = 0.5 * (p.width * d - width), oy = 0.5 * (p.height * d - height);
    const Vec2 shift = full.deltaToWorld({ox, oy});
    p.view.panX += shift.x;
    p.view.panY += shift.y;
    return p;
}

} // namespace moire::view
