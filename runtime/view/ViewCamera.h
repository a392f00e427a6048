// The viewer's camera maths, with no window in sight: where a pixel of the window lies in the
// world, and how each gesture (wheel zoom, drag, layer drag, layer turn) changes the view's
// adjustments so that what was under the cursor stays under it.
//
// The kernel's camera (compiler/lower/CameraModel.h, the one template both instantiate) maps
// pixel (px, py) of a W x H image, px and py continuous with pixel centres at i + 0.5, to
//     world = C + Rot(turn) (px - W/2, H/2 - py) * pixel
//     pixel = max(sceneWidth / W, sceneHeight / H) / (zoom * zoomFactor)
//     C     = the scene's centre + (panX, panY)
// and layer i is carried by the rigid motion p -> Rot(a_i) p + d_i about the world origin.
// Everything here is that formula and its inverse; the tests hold it to a brute-force copy.
#pragma once

#include "compiler/lower/CameraModel.h"
#include "compiler/sema/Properties.h"

#include <vector>

namespace moire {

struct FrameValues;

namespace view {

struct Vec2 {
    double x = 0.0, y = 0.0;
};

// The camera as the scene sets it at one instant (FrameValues: it may move with the clock).
struct SceneCamera {
    double centerX = 0.0, centerY = 0.0;
    double turn = 0.0; // radians
    double zoom = 1.0;
    double sceneWidth = sema::kDefaultWidth, sceneHeight = sema::kDefaultHeight;
    static SceneCamera from(const FrameValues& frame);
};

// The rigid motion the viewer lays over one layer: p -> Rot(turn) p + (dx, dy).
struct LayerMotion {
    double dx = 0.0, dy = 0.0, turn = 0.0;
    bool identity() const { return dx == 0.0 && dy == 0.0 && turn == 0.0; }
    Vec2 apply(Vec2 p) const;
};

// The view's own adjustments, written into the literal slots of lower::ViewSlots. They are
// the viewer's state; the scene's camera stays the scene's.
struct ViewAdjust {
    double panX = 0.0, panY = 0.0, zoomFactor = 1.0;
    std::vector<LayerMotion> layers; // may be shorter than the scene's layer list

    void reset();
    bool cameraMoved() const { return panX != 0.0 || panY != 0.0 || zoomFactor != 1.0; }
    LayerMotion layer(int i) const;
    LayerMotion& layerRef(int i); // grows the list as needed
    // Writes the slots from `viewSlot` (SceneProgram::viewSlot) for `numLayers` layers.
    void write(std::vector<double>& literals, int viewSlot, int numLayers) const;
};

// The camera of one image: the scene's camera with the view's adjustments, at W x H pixels.
class ViewCamera {
  public:
    ViewCamera(const SceneCamera& scene, const ViewAdjust& view, int width, int height);

    double pixelSize() const { return cam_.pixel; }
    Vec2 center() const { return {cam_.center.x, cam_.center.y}; }
    // `p` in pixels from the image's top-left corner (a pixel centre is at i + 0.5).
    Vec2 toWorld(Vec2 p) const;
    Vec2 toPixel(Vec2 world) const;
    // A displacement on screen, in pixels (y down), as a displacement in the world.
    Vec2 deltaToWorld(Vec2 d) const;

  private:
    lower::CameraT<double> cam_;
};

// The gestures. Each takes the scene's camera and the image size the cursor positions are in
// (framebuffer pixels), and edits `view`.

// Multiplies the zoom by `factor`, keeping the world point under `at` where it is.
void zoomAbout(const SceneCamera& scene, ViewAdjust& view, int width, int height, Vec2 at,
               double factor);
// Pans so that the world point that was under `from` is under `to`.
void panDrag(const SceneCamera& scene, ViewAdjust& view, int width, int height, Vec2 from, Vec2 to);
// Moves layer `layer` so that its point that was under `from` is under `to`.
void moveLayer(const SceneCamera& scene, ViewAdjust& view, int width, int height, int layer,
               Vec2 from, Vec2 to);
// Turns layer `layer` about the world origin by the angle the cursor swept around the
// origin's place on screen going from `from` to `to` (its offset turns with it).
void turnLayer(const SceneCamera& scene, ViewAdjust& view, int width, int height, int layer,
               Vec2 from, Vec2 to);

// A coarse preview of a W x H frame: `divisor` times fewer pixels each way, each preview pixel
// exactly covering a divisor x divisor block of the full frame (the last row and column of
// blocks may hang over its edge), so that a preview scaled up by `divisor` lines up with the
// full frame that follows it.
struct Preview {
    int width = 0, height = 0;
    ViewAdjust view; // the adjustments that make the preview's camera
};
Preview previewOf(const SceneCamera& scene, const ViewAdjust& view, int width, int height,
                  int divisor);

} // namespace view
} // namespace moire
