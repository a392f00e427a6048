#include "runtime/cli/Region.h"

#include <algorithm>
#include <charconv>
#include <fmt/format.h>
#include <string_view>

namespace moire::cli {

namespace {

// Decimal digits only (no sign or space), read without wrapping.
bool parseCoordinate(std::string_view t, int& v) {
    if (t.empty() || t.size() > 9 ||
        !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size();
}

} // namespace

std::optional<Region> parseRegion(const std::string& text, std::string& error) {
    int v[4] = {};
    std::string_view rest(text);
    for (int i = 0; i < 4; ++i) {
        const size_t comma = i < 3 ? rest.find(',') : std::string_view::npos;
        if ((i < 3 && comma == std::string_view::npos) ||
            !parseCoordinate(rest.substr(0, comma), v[i])) {
            error = fmt::format("must be X0,Y0,X1,Y1: four whole numbers of pixels of the full "
                                "frame, X1 and Y1 excluded; not '{}'",
                                text);
            return std::nullopt;
        }
        if (i < 3) rest.remove_prefix(comma + 1);
    }
    const Region r{v[0], v[1], v[2], v[3]};
    if (r.x1 <= r.x0 || r.y1 <= r.y0) {
        error = fmt::format("'{}' is empty: X1 must be above X0 and Y1 above Y0 (X1 and Y1 are "
                            "excluded)",
                            text);
        return std::nullopt;
    }
    return r;
}

std::string regionProblem(const Region& r, int width, int height) {
    if (r.x1 <= width && r.y1 <= height) return "";
    return fmt::format("{},{},{},{} reaches past the {}x{} frame (X1 at most {}, Y1 at most {})",
                       r.x0, r.y0, r.x1, r.y1, width, height, width, height);
}

} // namespace moire::cli
