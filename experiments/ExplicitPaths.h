// The members of five Table 2 pairs as explicit geometry (spec §9.5): the scene a pair
// compiles to, the path each sample's nearest member belongs to, those paths stroked by
// Cairo, and what explicit_geometry measures on the images (blur, mean and spread).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace moire::exp {

enum class PairKind { LinesRotated, LinesPitch, Circles, Hexagons, Hyperbolas };

struct PairSpec {
    const char* name;
    PairKind kind;
};
const std::vector<PairSpec>& pairSpecs();

// One setting of a pair: both families at `spacing` (world units), strokes `stroke` wide,
// and the second family moved from the first by one of: its line normal turned by
// `rotation` (LinesRotated), its hexagons turned by `rotation` about the origin (Hexagons), a
// spacing of its own (LinesPitch, Hyperbolas), or the circles' centres at (-shift, 0) and
// (shift, 0) (Circles).
// Lines and hexagons are both turned by kBaseTurn besides, so that no edge lies along the
// sampling grid (a family aligned with it, at a spacing commensurate with the samples'
// pitch, would alias in the 144-sample coverage).
struct Geometry {
    PairKind kind;
    double spacing[2];
    double stroke = 0;
    double rotation = 0, shift = 0;
};
constexpr double kBaseTurn = 0.3; // radians

// The scene: `width` pixels square at camera zoom `zoom`, both layers black on white.
std::string sceneText(const Geometry& g, double zoom, int width);
// What sets the second family apart, for the table ("6.0deg", "s 8.32", "+-40").
std::string secondLabel(const Geometry& g);

// The path through the member nearest a sample of layer `layer` with index `index` at world
// point (x, y): the member's number, and for a hyperbola which of its four branches (one
// path each, as a path renderer draws them).
int64_t memberKey(const Geometry& g, int layer, double index, double x, double y);
// How many members (integers n, from the family's first) have their level in [lo, hi].
long memberCount(const Geometry& g, int layer, double lo, double hi);

// The samples of one pixel that each path covers, combined as a path renderer does.
class MemberTally {
  public:
    void add(int64_t key);
    // 1 - prod_i (1 - alpha_i), alpha_i = (path i's samples) / samples.
    double over(double samples) const;

  private:
    std::vector<std::pair<int64_t, int>> counts_;
};

// Every member path that meets the frame, stroked by Cairo at CAIRO_ANTIALIAS_BEST with
// OVER, black on white, on a width x height ARGB32 image of the same frame: the ink
// (1 - the red channel) of each pixel, row by row.
std::vector<double> drawWithCairo(const Geometry& g, double zoom, int width, int height);

// A square image's mean and standard deviation, `margin` pixels in from each side.
struct Stats {
    double mean, std;
};
Stats frameStats(const std::vector<double>& image, int width, int margin);
// A separable Gaussian blur of a square image (sigma in pixels, clamped at the edges).
std::vector<double> gaussianBlur(const std::vector<double>& image, int width, double sigma);

} // namespace moire::exp
