// The printer's marks of a sheet (SheetLayout.h), all in the margin outside the bleed, never
// over the artwork: at each corner of the trim two crop marks, lines continuing the trim's
// edges outwards, and at the middle of each side a registration target, a circle and a
// cross centred in the margin on the trim's middle line. Black, antialiased, and the same on
// every sheet of a print, so that stacked sheets register.
#pragma once

#include "runtime/print/SheetLayout.h"

#include <cstddef>
#include <vector>

namespace moire::print {

// A line from (x0, y0) to (x1, y1), or a circle about (x0, y0) of radius `radius`, in pixels
// of the sheet (pixel i covers [i, i + 1)), drawn `halfWidth` either side of its centre line.
struct MarkShape {
    bool circle = false;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0, radius = 0;
    double halfWidth = 0.5;
};

// The marks of a sheet laid out with marks (none without). `dpi` gives their measures.
std::vector<MarkShape> sheetMarks(const SheetLayout& layout, double dpi);

// The ink of the marks over pixel (x, y) of the sheet: 0 to 1, about the area of the pixel
// the thickest mark there covers; 0 over the artwork (the trim and its bleed), always.
float markCoverage(const SheetLayout& layout, const std::vector<MarkShape>& marks, long long x,
                   long long y);

// Finishes rows [y, y + count) of the sheet as the renderer gives them (`channels` floats a
// pixel, straight sRGB RGBA first, `stride` floats a row): what lies outside the artwork
// (the margin) becomes `margin` (straight RGBA), and the marks are laid over it in black with
// `over` (markCoverage's ink). The artwork's pixels are left as they are.
void finishRows(const SheetLayout& layout, const std::vector<MarkShape>& marks,
                const float margin[4], long long y, int count, float* rows, size_t stride,
                int channels);

} // namespace moire::print
