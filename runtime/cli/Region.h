// What `moire render --region` reads from its command line: a window of the full frame.
#pragma once

#include <optional>
#include <string>

namespace moire::cli {

// A window of the full frame in its pixels, X1 and Y1 excluded.
struct Region {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

// --region: "X0,Y0,X1,Y1", four whole numbers of pixels from 0, X1 above X0 and Y1 above Y0.
// nullopt with `error` set (the sentence after "--region ") when it is not.
std::optional<Region> parseRegion(const std::string& text, std::string& error);

// Why `region` is not a window of a width x height frame, or "" when it is.
std::string regionProblem(const Region& region, int width, int height);

} // namespace moire::cli
