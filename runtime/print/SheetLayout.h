// Where everything lies on a print sheet (docs/print.md draws it): the trim (the paper's own
// size), the bleed around it (the artwork carried past the trim at the same scale, to be cut
// off), and, with marks, a margin around the bleed that carries the crop and registration
// marks. All in whole pixels at the sheet's resolution, the trim centred on the sheet.
#pragma once

#include "runtime/print/PhysicalSize.h"

#include <string>

namespace moire::print {

// "A0" to "A6" (ISO 216), "letter", "legal", "tabloid" (any case), or a size on paper
// ("420x297mm", PhysicalSize.h). Named papers are portrait. On failure returns false with the
// reason in `error`.
bool parsePaper(const std::string& text, PaperSize& out, std::string& error);
// The named papers, for messages and --help.
const char* paperNames();

enum class Orientation { Auto, Portrait, Landscape };

// The width of the margin that carries the marks, in millimetres, and the marks' measures
// (Marks.h draws them).
constexpr double kMarkMarginMm = 12.0;
constexpr double kMarkGapMm = 2.0;      // from the bleed's edge to a crop mark's inner end
constexpr double kMarkLineMm = 0.25;    // the width of every line of a mark
constexpr double kTargetRadiusMm = 3.5; // a registration target's circle
constexpr double kTargetArmMm = 5.0;    // and its cross, from the centre to each end

struct SheetRequest {
    PaperSize paper;
    Orientation orientation = Orientation::Auto;
    double dpi = 0.0;     // above 0
    double bleedMm = 0.0; // 0 or more
    bool marks = false;
    // World units per millimetre of paper; 0: the scene's frame fitted to the trim.
    double scale = 0.0;
    // The scene's frame (its `size`) and the camera's zoom, for the orientation and the fit.
    double sceneWidth = 0.0, sceneHeight = 0.0, zoom = 1.0;
};

// A half-open rectangle of pixels.
struct PixelBox {
    long long x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    long long width() const { return x1 - x0; }
    long long height() const { return y1 - y0; }
    bool contains(long long x, long long y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

struct SheetLayout {
    long long width = 0, height = 0; // the whole sheet, in pixels
    PixelBox trim;                   // the paper's size: what is left after cutting
    PixelBox art;                    // the trim and its bleed: what the scene draws
    long long bleed = 0, margin = 0; // their widths in pixels (margin 0 without marks)
    bool landscape = false;          // the paper turned so that its long side lies across
    double paperWidthMm = 0.0, paperHeightMm = 0.0; // the trim as oriented
    double pixelSize = 0.0; // the world size of one pixel (FrameRequest::pixelSize)
};

// The sheet for a request (its values already checked: dpi above 0, bleed 0 or more, scale 0
// or above 0). The orientation, unless told: the paper's long side along the scene frame's
// long side; a square frame leaves the paper as given.
SheetLayout layoutSheet(const SheetRequest& request);

} // namespace moire::print
