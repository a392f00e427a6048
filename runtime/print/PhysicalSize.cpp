#include "runtime/print/PhysicalSize.h"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <string_view>

namespace moire::print {

namespace {

struct Unit {
    const char* name;
    double mm; // millimetres in one
};
constexpr Unit kUnits[] = {{"mm", 1.0}, {"cm", 10.0}, {"in", kMmPerInch}};
constexpr double kMostMm = 100000.0; // 100 m: past any printer's roll

const Unit* unitOf(std::string_view text) {
    for (const Unit& u : kUnits)
        if (text.size() > 2 && text.substr(text.size() - 2) == u.name) return &u;
    return nullptr;
}

// A plain decimal: digits with at most one point (no sign, exponent or space).
bool parseLength(std::string_view t, double& v) {
    if (t.empty() || t.front() == '.' || t.back() == '.') return false;
    int points = 0;
    for (char c : t) {
        if (c == '.')
            ++points;
        else if (c < '0' || c > '9')
            return false;
    }
    if (points > 1) return false;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size();
}

} // namespace

bool hasLengthUnit(const std::string& text) {
    return unitOf(text) != nullptr;
}

bool parsePhysicalSize(const std::string& text, PaperSize& out, std::string& error) {
    const Unit* unit = unitOf(text);
    const std::string_view all(text);
    const std::string_view sides = unit ? all.substr(0, all.size() - 2) : all;
    const size_t x = sides.find_first_of("xX");
    double w = 0.0, h = 0.0;
    if (!unit || x == std::string_view::npos || !parseLength(sides.substr(0, x), w) ||
        !parseLength(sides.substr(x + 1), h)) {
        error = fmt::format("'{}' is not a size on paper: write WIDTHxHEIGHT and a unit, mm, cm "
                            "or in (as 610x406mm)",
                            text);
        return false;
    }
    w *= unit->mm;
    h *= unit->mm;
    if (!(w > 0.0 && h > 0.0 && w <= kMostMm && h <= kMostMm)) {
        error = fmt::format("'{}' is not a size on paper: each side must be above 0 and at most "
                            "100 m",
                            text);
        return false;
    }
    out = {w, h};
    return true;
}

long long pixelsFor(double mm, double dpi) {
    return static_cast<long long>(std::llround(mm / kMmPerInch * dpi));
}

bool sizeInPixels(const std::string& text, double dpi, int maxSide, std::string& pixels,
                  std::string& error) {
    if (!hasLengthUnit(text)) {
        pixels = text;
        return true;
    }
    if (!(dpi > 0)) {
        error = fmt::format("--size {} is a size on paper: it needs --dpi, the dots per inch to "
                            "render it at",
                            text);
        return false;
    }
    PaperSize s;
    if (!parsePhysicalSize(text, s, error)) {
        error = "--size: " + error;
        return false;
    }
    const long long w = pixelsFor(s.widthMm, dpi), h = pixelsFor(s.heightMm, dpi);
    if (w < 1 || h < 1 || w > maxSide || h > maxSide) {
        error = fmt::format("--size {} at {:g} dpi is {}x{} pixels; each side must be 1 to {}",
                            text, dpi, w, h, maxSide);
        return false;
    }
    pixels = fmt::format("{}x{}", w, h);
    return true;
}

} // namespace moire::print
