// Lengths on paper: "610x406mm", "61x40.6cm", "24x16in", and how many pixels they are at a
// resolution. `moire render --size 610x406mm --dpi 300` and `moire print --paper 610x406mm`
// read them here, so the two commands agree on the units and the rounding.
#pragma once

#include <string>

namespace moire::print {

constexpr double kMmPerInch = 25.4;

// A width and a height in millimetres.
struct PaperSize {
    double widthMm = 0.0, heightMm = 0.0;
};

// True when `text` ends in a unit of length (mm, cm or in), so that it asks for a physical
// size rather than pixels.
bool hasLengthUnit(const std::string& text);

// "WxH" followed by mm, cm or in (decimals allowed, each side above 0 and at most 100 m).
// On failure returns false and says why in `error` (a sentence that names the text).
bool parsePhysicalSize(const std::string& text, PaperSize& out, std::string& error);

// The pixels `mm` spans at `dpi`: round(mm / 25.4 * dpi), half away from zero.
long long pixelsFor(double mm, double dpi);

// `render --size`: a size on paper ("610x406mm") at `dpi` as "WxH" in pixels, each side 1 to
// `maxSide`; a size in pixels comes back as it is. On failure returns false with the reason
// in `error` (a size on paper without a resolution, one that is not a size, one that makes
// less than a pixel or more than `maxSide`).
bool sizeInPixels(const std::string& text, double dpi, int maxSide, std::string& pixels,
                  std::string& error);

} // namespace moire::print
