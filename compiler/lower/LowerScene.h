// Lowers a checked scene to one IR function evaluated per pixel: the camera, every layer's
// fields and coverage, and the composite. Outputs: RGBA (slots 0-3), optionally each layer's
// index, distance and index gradient, then the frame settings (image width and height, camera
// zoom, and each timing the scene uses: its period, delay and mode).
#pragma once

#include "compiler/ir/IR.h"
#include "compiler/lower/WalkingVariant.h"
#include "compiler/sema/Sema.h"
#include "compiler/sema/Views.h"

#include <optional>
#include <string>
#include <vector>

namespace moire::lower {

// Where the camera's inputs come from, besides the scene.
enum class LowerMode {
    Render, // the scene's camera as written
    // Probe: the camera centre is read from two literal slots appended to the table
    // (LoweredScene::probeSlot), so that the pixel of a 1x1 image sits on any chosen world
    // point.
    Probe,
    // Interactive (the viewer): the view's own adjustments are read from literal slots
    // appended to the table (LoweredScene::viewSlot, see ViewSlots), so panning, zooming or
    // dragging a layer changes uniforms, never the kernel.
    Interactive,
};

struct LowerOptions {
    LowerMode mode = LowerMode::Render;
    bool layerFields = false; // also output each layer's index, distance and index gradient
    // Count the walking solver's radius evaluations with `tally` (the interpreter's
    // counting mode, for benchmarks).
    bool tally = false;
    // The view, the envelope's gain and its taps, replacing the scene's settings when set
    // (`moire render --view`, `--envelope-gain`, `--envelope-taps`).
    std::optional<sema::ViewMode> view = std::nullopt;
    std::optional<double> envelopeGain = std::nullopt, envelopeTaps = std::nullopt;
    // The fringe overlay, replacing the scene's `overlay` when set (`--overlay`, the viewer's o).
    std::optional<bool> overlay = std::nullopt;
    // The stroke filter, replacing the scene's `filter` when set (`--filter`): point-sampled,
    // or the mean over the pixel where members are finer than pixels (lower/Prefilter.h).
    std::optional<sema::FilterMode> filter = std::nullopt;
    // One print separation (`moire print --separate`): only the layer of this index is
    // lowered, over a transparent paper, so the pixel's colour is the layer's and its alpha
    // the layer's ink; drawn in the pattern view, without the overlay or the unresolved tint.
    std::optional<int> separate = std::nullopt;
    // The world size of a pixel read from a literal slot (LoweredScene::pixelSlot) instead of
    // fitted to the image, so that the scale and the canvas are set apart (`moire print`).
    bool pixelSlot = false;
    // The experiments' settings (experiments/, bench/): the walking solver's variant, and
    // the stroke floor of Eq. 35 (false: h = t/2 at every zoom, §8.2's "floor removed").
    WalkingVariant walking = {};
    bool strokeFloor = true;
};

// The literal slots of interactive mode, counted from LoweredScene::viewSlot. The camera's
// centre gains (panX, panY) and its zoom is multiplied by zoomFactor; layer i is carried by a
// rigid motion of the world: turned by `turn` about the world origin, then moved by (dx, dy).
struct ViewSlots {
    static constexpr int kPanX = 0, kPanY = 1, kZoomFactor = 2, kCamera = 3;
    static constexpr int kLayerDx = 0, kLayerDy = 1, kLayerTurn = 2, kPerLayer = 3;
    static int layer(int i, int field) { return kCamera + kPerLayer * i + field; }
    static int count(int numLayers) { return kCamera + kPerLayer * numLayers; }
};

// The range of values the renderers draw (docs/language.md, "Limits"). The JIT and Vulkan
// compute in single precision (largest float about 3.4e38), so a value that is finite in
// double can overflow there, and so can products the kernel forms from it (x^2 in a phase,
// stroke / 2 + the antialias band): past these limits the float backends would draw another
// picture than the interpreter. Lengths stay within +-1e12 so that a world coordinate's
// square stays far below the float range; the zoom keeps the view's extent (at most 2^20
// pixels times 1 / zoom: 1.05e12, its square still 1e14 times below the float range) about
// the same bound; a spacing finer than 1e-6 is solid ink at
// any zoom allowed, and is the pitch the kernel holds a non-positive spacing at.
constexpr double kMaxMagnitude = 1e12;
constexpr double kMinSpacing = 1e-6;
constexpr double kMinZoom = 1e-6, kMaxZoom = 1e6;

// A value the frame checks before it is drawn, located at the property it comes from. Each
// is one frame setting; one that depends on the pixel cannot be checked per frame (the
// frame split drops it and sets `perPixel`).
struct ValueCheck {
    enum Rule {
        Finite,   // within +-kMaxMagnitude
        Positive, // more than 0, at most kMaxMagnitude (stroke)
        Spacing,  // from kMinSpacing to kMaxMagnitude
        Unit,     // from 0 to 1 (opacity)
        Sides,    // a whole number of sides, 3 or more (a polygon family's facets)
        Range,    // from lo to hi: a param's declared range
    };
    Rule rule = Finite;
    std::string what;  // as the message names it: 'stroke'
    SourceRange where; // the value in the source
    bool angle = false;
    bool perPixel = false;
    double lo = 0.0, hi = 0.0; // Range
};

// Where things are in the scene function's outputs.
struct OutputLayout {
    int numKernelOutputs = 4; // RGBA, then kFieldsPerLayer per layer when layerFields is set
    int numLayers = 0;
    bool layerFields = false;
    static constexpr int kSettingWidth = 0; // settings are numbered from numKernelOutputs
    static constexpr int kSettingHeight = 1;
    static constexpr int kSettingZoom = 2;
    static constexpr int kSettingCenterX = 3; // the camera as the scene sets it (before the view)
    static constexpr int kSettingCenterY = 4;
    static constexpr int kSettingTurn = 5;
    static constexpr int kNumSettings = 6;    // and then kTimingSettings per timing used
    static constexpr int kTimingSettings = 3; // period, delay, mode (0 once, 1 loop, 2 pingpong)
    std::vector<std::string> timings;         // the timings the scene uses, in declaration order
    std::vector<SourceRange> timingPeriods;   // where each one's period is written
    std::vector<SourceRange> timingDelays;    // and its delay (the name, when it has none)
    std::vector<ValueCheck> checks;           // one setting each, after the timings'
    int firstCheckSetting() const {
        return kNumSettings + kTimingSettings * static_cast<int>(timings.size());
    }
    // Each param's value (compiler/Parameters.h), kParameterWidth settings each, after the
    // checks': what the tools show beside a slider when the default is an expression.
    static constexpr int kParameterWidth = 4;
    int numParameters = 0;
    int parameterSetting(int param) const {
        return firstCheckSetting() + static_cast<int>(checks.size()) + kParameterWidth * param;
    }
    int numSettings() const { return parameterSetting(numParameters); }
    int timingSetting(int timing) const { return kNumSettings + kTimingSettings * timing; }
    static constexpr int kFieldsPerLayer = 6;
    int indexSlot(int layer) const { return 4 + kFieldsPerLayer * layer; }
    int distanceSlot(int layer) const { return indexSlot(layer) + 1; }
    int gradXSlot(int layer) const { return indexSlot(layer) + 2; }
    int gradYSlot(int layer) const { return indexSlot(layer) + 3; }
    // Family diagnostics: the walking solver's certified interval [n_lo, n_hi].
    int aux0Slot(int layer) const { return indexSlot(layer) + 4; }
    int aux1Slot(int layer) const { return indexSlot(layer) + 5; }
};

struct LoweredScene {
    ir::Function function; // the scene function, verified
    OutputLayout layout;
    int probeSlot = -1; // LowerMode::Probe: the literal slots of the probe point (x, then y)
    int viewSlot = -1;  // LowerMode::Interactive: the first of ViewSlots' slots
    int pixelSlot = -1; // LowerOptions::pixelSlot: the slot of the pixel's world size
    sema::ViewMode view = sema::ViewMode::Pattern; // the view drawn
    bool overlay = false;                          // the fringe overlay drawn over it
    // The layers (by index) the view cannot draw: a sweeping view over a family that gives no
    // phase sample. The compiler reports them; the function is not to be run.
    std::vector<int> unsweepable;
};

// The stroke filter a scene is drawn with: `given` (the command line's), else the scene's
// `filter`, else the mean.
sema::FilterMode filterOf(const sema::CheckedScene& scene,
                          const std::optional<sema::FilterMode>& given);

// Lowers the checked scene. `literals` is the scene's literal table; the slots the mode reads
// are appended to it, set to the scene's own view (probe point at the origin; no pan, zoom
// factor 1, no layer moved or turned).
LoweredScene lowerScene(const sema::CheckedScene& scene, const LowerOptions& options,
                        std::vector<double>& literals);

} // namespace moire::lower
