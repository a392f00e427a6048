#include "runtime/print/SheetLayout.h"

#include "compiler/lower/CameraModel.h"

#include <algorithm>
#include <cctype>
#include <fmt/format.h>
#include <string_view>
#include <utility>

namespace moire::print {

namespace {

struct NamedPaper {
    const char* name;
    double widthMm, heightMm;
};
// ISO 216's A series, and the North American sizes (exactly their inches in millimetres).
constexpr NamedPaper kPapers[] = {
    {"a0", 841, 1189},       {"a1", 594, 841},          {"a2", 420, 594}, {"a3", 297, 420},
    {"a4", 210, 297},        {"a5", 148, 210},          {"a6", 105, 148}, {"letter", 215.9, 279.4},
    {"legal", 215.9, 355.6}, {"tabloid", 279.4, 431.8},
};

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

} // namespace

const char* paperNames() {
    return "A0 to A6, letter, legal, tabloid";
}

bool parsePaper(const std::string& text, PaperSize& out, std::string& error) {
    const std::string key = lower(text);
    for (const NamedPaper& p : kPapers)
        if (key == p.name) {
            out = {p.widthMm, p.heightMm};
            return true;
        }
    if (hasLengthUnit(key)) return parsePhysicalSize(key, out, error);
    error = fmt::format("unknown paper '{}'; the papers are {}, or a size such as 610x406mm (mm, "
                        "cm or in)",
                        text, paperNames());
    return false;
}

SheetLayout layoutSheet(const SheetRequest& r) {
    SheetLayout s;
    double w = r.paper.widthMm, h = r.paper.heightMm;
    bool turn = false;
    switch (r.orientation) {
    case Orientation::Portrait:
        turn = w > h;
        break;
    case Orientation::Landscape:
        turn = w < h;
        break;
    case Orientation::Auto:
        // Turned when the frame and the paper are long in different directions.
        turn = (r.sceneWidth > r.sceneHeight && w < h) || (r.sceneWidth < r.sceneHeight && w > h);
        break;
    }
    if (turn) std::swap(w, h);
    s.landscape = w > h;
    s.paperWidthMm = w;
    s.paperHeightMm = h;
    const long long tw = pixelsFor(w, r.dpi), th = pixelsFor(h, r.dpi);
    s.bleed = pixelsFor(r.bleedMm, r.dpi);
    s.margin = r.marks ? pixelsFor(kMarkMarginMm, r.dpi) : 0;
    const long long border = s.bleed + s.margin;
    s.width = tw + 2 * border;
    s.height = th + 2 * border;
    s.trim = {border, border, border + tw, border + th};
    s.art = {s.margin, s.margin, s.width - s.margin, s.height - s.margin};
    // The trim's middle is the sheet's, so the camera's centre lands on it either way.
    if (r.scale > 0)
        s.pixelSize = r.scale * kMmPerInch / r.dpi;
    else
        s.pixelSize = lower::fitScale<double>(r.sceneWidth, r.sceneHeight,
                                              static_cast<double>(std::max(tw, 1LL)),
                                              static_cast<double>(std::max(th, 1LL))) /
                      r.zoom;
    return s;
}

} // namespace moire::print
