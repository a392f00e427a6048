// The mean filter's strokes laid over each other within a pixel (docs/filtering.md, "Strokes
// that meet within a pixel"). Each layer's footprint mean (Prefilter.h) laid over the others
// takes the layers' inks as independent across the pixel: the pixel's mean of a product read
// as the product of the means. Two resolved strokes that cross at a wide angle are near enough
// to that; two that run nearly parallel through the pixel are not: laid on one another the
// pixel holds one stroke's ink, not the union of two, and side by side it holds both whole.
// That is where a moiré's fringes are (two families nearly parallel where their beat is slow),
// so the error sits on every fringe's edge.
//
// Over a pixel, laying inks of coverage k_i A_i in turn gives a multilinear polynomial in the
// A_i; its mean departs from the polynomial of the means, to second order, by
//   sum over pairs i < j of  k_i k_j cov(A_i, A_j) (acc_{i-1} - c_i) prod_{i<l<j} (1 - k_l a_l)
// times the layers above j, where acc_{i-1} is the ink beneath layer i and c_i its colour
// (premultiplied, alpha 1): the second derivative of the running "over" in the two layers'
// coverages. The compose step keeps, for each layer laid, its pending factor and adds the
// term as each later layer is laid (Compose.cpp); this file gives cov(A_i, A_j) for the two
// layers' nearest strokes (stripCovariance) and reads each layer's stroke in the pixel's frame
// (strokeAcross).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/Prefilter.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace moire::lower {

// The mean of max(x', 0) over x' in [x - span/2, x + span/2] (span > 0; `half` is span / 2
// and `inverse` 1 / (2 span), shared by a sum of ramps over one span): x past the span's half,
// 0 short of it, and between the two (x + span/2)^2 / (2 span), the ramp's integral over the
// part above 0. Written with selects rather than as a difference of squares over span, which
// float rounding would spoil as span -> 0.
template <class T>
T meanRamp(T x, T half, T inverse) {
    using ir::literal;
    const T rise = x + half;
    const T within = rise * rise * inverse;
    return ir::select(ir::lessThan(x, half),
                      ir::select(ir::lessThan(rise, literal(x, 0.0)), literal(x, 0.0), within), x);
}

// The mean, over centres m in [m0 - span/2, m0 + span/2], of the length [lo, hi] shares with
// [m - r, m + r]. As a function of m that length is the two boxes' convolution, a trapezoid,
// which is four ramps: max(m - lo + r, 0) - max(m - hi + r, 0) - max(m - lo - r, 0) +
// max(m - hi - r, 0) (lo <= hi; lo = hi gives 0).
template <class T>
T meanShared(T lo, T hi, T m0, T r, T span) {
    const T half = span * 0.5;
    const T inverse = ir::literal(span, 0.5) / span;
    return meanRamp(m0 - lo + r, half, inverse) - meanRamp(m0 - hi + r, half, inverse) -
           meanRamp(m0 - lo - r, half, inverse) + meanRamp(m0 - hi - r, half, inverse);
}

// Least |cos| between two strokes' normals the covariance divides by, and least drift across
// the pixel it averages over: past them the strokes are crossing (the covariance is near 0 by
// the construction below, whatever the clamp) or parallel (the drift's mean is the value at
// its centre).
constexpr double kLeastCrossingCos = 0.05;
constexpr double kLeastDrift = 1e-4;
// How far (pixels) the second nearest of a lattice's dots must stand behind the nearest for the
// nearest's stroke to count whole in a pair (strokeAcross).
constexpr double kTieBand = 0.1;

// The covariance over a pixel of two straight strokes' inks (each 1 inside its stroke, 0
// outside), in pixel units, in the frame of the first stroke's normal: u along it, v across,
// the pixel the box [-1/2, 1/2]^2. Stroke 1 inks |u + s1| < h1; stroke 2, whose unit normal is
// (cosA, sinA) in that frame, inks |cosA u + sinA v + s2| < h2. At a given v stroke 2 inks
// the u within h2 / |cosA| of m(v) = -(sinA v + s2) / cosA, a centre that drifts over
// |sinA / cosA| as v crosses the pixel; the means over the pixel are then
//   E[A1 A2] = mean over the drift of the length [lo, hi] shares with stroke 2 (meanShared),
//   E[A1] = hi - lo, E[A2] = the same mean with [lo, hi] = [-1/2, 1/2],
// with [lo, hi] stroke 1's span within the pixel, and the covariance E[A1 A2] - E[A1] E[A2].
// Exact for strokes that are parallel (no drift): two coinciding strokes give a - a^2, two
// apart -a1 a2. At right angles stroke 2's span grows as fast as its drift and the covariance
// goes to 0, the independence the compose step already assumes. It takes the pixel as a box
// in the first stroke's frame, the square turned to face it: what it leaves out is the
// square's corners, a second-order share (docs/filtering.md gives the measure).
template <class T>
T stripCovariance(T s1, T h1, T s2, T h2, T cosA, T sinA) {
    using ir::literal;
    using std::abs;
    using std::max;
    using std::min;
    const T zero = literal(s1, 0.0);
    const T half = literal(s1, 0.5);
    const T w1 = max(h1, zero), w2 = max(h2, zero);
    // Past a stroke's reach of the pixel (half its diagonal) the covariance is 0; holding the
    // offsets there keeps a far member (or none: kNoMember) from swamping the sums.
    const T near1 = min(max(s1, -(w1 + 1.0)), w1 + 1.0);
    const T lo = max(-near1 - w1, -half);
    const T hi = max(min(-near1 + w1, half), lo);
    // Stroke 2 read with its normal turned to face the first's (cosA >= 0): the same stroke.
    const T c = max(abs(cosA), literal(s1, kLeastCrossingCos));
    const T facing = ir::select(ir::lessThan(cosA, zero), literal(s1, -1.0), literal(s1, 1.0));
    const T near2 = min(max(s2 * facing, -(w2 + 1.0)), w2 + 1.0);
    const T m0 = -near2 / c;
    const T r = w2 / c;
    const T drift = max(abs(sinA) / c, literal(s1, kLeastDrift));
    const T both = meanShared(lo, hi, m0, r, drift);
    const T second = meanShared(-half, half, m0, r, drift);
    return both - (hi - lo) * second;
}

// The covariance over a pixel of a layer's periodic strokes and another layer's one stroke,
// in pixel units, the pixel the square [-1/2, 1/2]^2: the stroke inks |nu u + nv v + s| < h
// (where `disc` > 0, the disc of radius h about the point s from the pixel's centre against
// the normal, a lattice's dot),
// and the periodic layer, whose members stand at the whole numbers of an index running gu
// steps a pixel along u and gv along v from `index` at the pixel's centre, inks within w of
// each whole number (w in index units). The stroke's span across the square (its part within
// the square's reach along the normal) is cut into kStripeSlices slices, each read as a box:
// its width across the stroke by the square's chord through its middle, placed where that
// chord's middle is. Then
//   E[A1 A2] = sum over the slices of its area x the periodic layer's mean over it
//              (squareMeanInk of the box),
//   E[A1] = the slices' areas summed, E[A2] = the periodic layer's mean over the square,
// and the covariance E[A1 A2] - E[A1] E[A2]. Exact for a stroke along the pixel's sides or
// parallel to the members however many a pixel holds; 0 where the members cross the stroke
// many times over each slice, as the union of the means takes it. Against the covariance
// sampled 256 x 256 over the square (StrokePairs_test.cpp) it keeps 5% of independence's
// error where the members run nearly along the stroke and 16% where they cross it; one box
// for the whole span, facing the stroke, kept 18% and 43%, and 4 slices 18% and 30%, their
// error in the square's corners, which the slices' boxes cut square.
constexpr int kStripeSlices = 8;
// Slice k (0 to kStripeSlices - 1, a number or a loop's counter) of stripesCovariance, below:
// its box's area and that area times the periodic layer's mean over it.
template <class T>
std::pair<T, T> stripeSlice(T index, T gu, T gv, T w, T nu, T nv, T s, T h, T disc, T k) {
    using ir::literal;
    using std::abs;
    using std::max;
    using std::min;
    using std::sqrt;
    const T zero = literal(s, 0.0);
    const T a = gu * nu + gv * nv; // steps a pixel across the stroke
    const T b = gv * nu - gu * nv; // and along it, t = (-nv, nu)
    const T reach = (abs(nu) + abs(nv)) * 0.5;
    const T hw = max(h, zero);
    const T near = min(max(s, -(hw + 1.0)), hw + 1.0);
    const T lo = max(-near - hw, -reach);
    const T hi = max(min(-near + hw, reach), lo);
    const T du = (hi - lo) * (1.0 / kStripeSlices);
    // The square's chord along t at u: |u n_c + v t_c| <= 1/2 for both sides c, an interval of
    // v about -u n_c / t_c, 1 / (2 |t_c|) either side (t_c held off 0: a side the stroke runs
    // along bounds nothing, or everything where u passes it).
    auto chord = [&](T u, T n, T t) {
        const T size = max(abs(t), literal(s, 1e-4));
        const T centre = -(u * n) / ir::select(ir::lessThan(t, zero), -size, size);
        const T half = literal(s, 0.5) / size;
        return std::pair{centre - half, centre + half};
    };
    const T u = lo + du * (k + 0.5);
    const auto [lu, hu] = chord(u, nu, -nv);
    const auto [lv, hv] = chord(u, nv, nu);
    // A disc's chord, about its centre's line through the pixel's centre (v = 0).
    const T off = u + s;
    const T round = ir::select(ir::lessThan(zero, disc), sqrt(max(hw * hw - off * off, zero)),
                               literal(s, 1e30));
    const T from = max(max(lu, lv), -round);
    const T length = max(min(min(hu, hv), round), from) - from;
    const T middle = from + length * 0.5;
    const T box = du * length;
    return {box, box * squareMeanInk(index + a * u + b * middle, abs(a) * du, abs(b) * length, w)};
}
// The sum over the slices, in double (the kernel's is a loop: stripesCovarianceOf below).
inline double stripesCovariance(double index, double gu, double gv, double w, double nu, double nv,
                                double s, double h, double disc) {
    double inBand = 0, area = 0;
    for (int k = 0; k < kStripeSlices; ++k) {
        const auto [box, ink] = stripeSlice(index, gu, gv, w, nu, nv, s, h, disc, double(k));
        inBand += ink;
        area += box;
    }
    return inBand - area * squareMeanInk(index, std::abs(gu), std::abs(gv), w);
}
// The same in the kernel, its slices one loop (the IR of a slice written once): every pair of
// layers reads it where their strokes meet, and unrolled it was most of a four-layer scene's
// kernel.
ir::ValueId stripesCovarianceOf(ir::Builder& b, ir::ValueId index, ir::ValueId gu, ir::ValueId gv,
                                ir::ValueId w, ir::ValueId nu, ir::ValueId nv, ir::ValueId s,
                                ir::ValueId h, ir::ValueId disc);

// A layer's nearest stroke in the pixel's frame, in pixel units: the unit normal (nu, nv)
// along the pixel's sides, the pixel's centre standing `s` from the member's centre line along
// it, and the half-width h; `weight`, how far the nearest member alone is the layer's ink in
// the pixel (1 but where its members crowd closer than the pixel and the mean is of many);
// `touches`, whether the stroke reaches into the pixel at all (|s| < h + half the pixel's
// diagonal), without which its covariance with any stroke is 0.
struct StrokeAcross {
    ir::ValueId nu, nv, s, h, weight, touches;
    // A phase family's members read as periodic strokes (stripesCovariance), where they crowd
    // past the nearest's reading, or a family's given by its distance by the index they run
    // by where they crowd running one way: the index at the pixel's centre, its steps a pixel
    // along the pixel's sides (gu, gv), the half-width in index units, and how far the members
    // are past being resolved (FineUnion.h, `unresolved`); kNoValue for any other layer.
    ir::ValueId index = ir::kNoValue, gu = ir::kNoValue, gv = ir::kNoValue, w = ir::kNoValue,
                unresolved = ir::kNoValue;
    // 1 where the stroke stands for a lattice's dot (a disc of radius h, its centre s from
    // the pixel's centre against the normal), 0 where it is a band; kNoValue: always a band.
    ir::ValueId disc = ir::kNoValue;
    // Pixels between the nearest member and the next ones either side along the normal, where
    // the members run parallel (a phase family's, the pencil's by its index): the pair reads
    // those two as well (strokeCovariance). kNoValue: the nearest stroke alone.
    ir::ValueId pitch = ir::kNoValue;
};

// The layer's nearest stroke under the mean filter: a phase family's from its index (the
// residual over the gradient, its weight falling as its members crowd: kCrowdFrom to
// kCrowdFull members a pixel); any other family's from its distance along the member's normal
// (memberNormal), on the side the distance's gradient says, or where the normal is the index
// gradient (the walking solver's) the side its fractional index says. None where no normal is
// known (a lattice): such a layer is laid as independent. A family that estimates its crowd
// weighs its stroke by how far the crowd is not engaged.
std::optional<StrokeAcross> strokeAcross(ir::Builder& b, const LayerFields& fields,
                                         ir::ValueId halfWidth, const PixelFootprint& pixel);

// stripCovariance of two layers' strokes, times both their weights (not checked for
// `touches`: the caller branches on it). Where a layer's members stand a known pitch apart its
// ink is the nearest member's stroke and the next one's either side, each cut to half the pitch
// (overlapping strokes are one band of ink): a pixel between two members of one layer holds
// both their strokes' edges once the members are less than about 2 pixels apart, and the
// nearest alone took the pair's covariance from one edge. Members that do not overlap add
// their inks, so the covariance is the sum over the pairs of members whose strokes reach the
// pixel, up to 3 x 3; the rest stand past its reach wherever a pitch is a pixel or more (the
// nearest stroke's weight is 0 closer than that).
ir::ValueId strokeCovariance(ir::Builder& b, const StrokeAcross& first, const StrokeAcross& second);

// The covariance of `periodic`'s members, read as periodic strokes, with `stroke`'s nearest
// stroke (stripesCovariance), where the first crowds past the hand-over and the second does
// not: its weight is how far `periodic` is past being resolved beyond `stroke`. The nearest
// strokes' covariance (strokeCovariance) holds where both are resolved and the union of fine
// layers where both crowd; between them a crowded layer's strokes met a resolved layer's as
// independent. 0 where `periodic` has no periodic reading; the caller branches on
// `stroke.touches` and on mixedWeight > 0.
ir::ValueId mixedWeight(ir::Builder& b, const StrokeAcross& periodic, const StrokeAcross& stroke);
ir::ValueId mixedCovariance(ir::Builder& b, const StrokeAcross& periodic,
                            const StrokeAcross& stroke);
// Both ways of mixedCovariance for a pair of strokes, each behind its branch (one branch and
// one stripes loop where both layers can be read as periodic strokes).
ir::ValueId mixedPairCovariance(ir::Builder& b, const StrokeAcross& first,
                                const StrokeAcross& second);

// A lattice's strands (CrowdEstimate::strands: its edges' whole lines, each a phase family)
// as strokes: each the nearest line of its family, held to weight 0 where the lattice draws
// its points. Empty for any other layer.
std::vector<StrokeAcross> strandStrokes(ir::Builder& b, const CrowdEstimate& crowd,
                                        ir::ValueId halfWidth, const PixelFootprint& pixel);

// What the union of the triangle lattice's three lines laid as independent inks (its
// footprint mean, 1 - prod(1 - m_i)) misses where they cross within the pixel, to be added
// to it: by inclusion and exclusion the union is sum m_i - sum E[x_i x_j] + E[x_1 x_2 x_3],
// and the independent product reads E[x_i x_j] as m_i m_j and E[x_1 x_2 x_3] as m_1 m_2 m_3,
// so the difference is -sum cov_ij (strokeCovariance of the nearest lines) plus
// E[x_1 x_2 x_3] - m_1 m_2 m_3, where the lines are resolved (the least of the strokes'
// weights; past it LatticeCrowd.cpp's closed form). The three lines all cross at the
// lattice's points, and three strokes of one width at 60 degrees share a hexagon three
// quarters of each pair's rhombus: E[x_1 x_2 x_3] is taken from the least pair's E[x_i x_j].
// 0 for the square lattice's two lines, which cross at right angles: over a pixel facing them
// they are independent, and the strip covariance's box (above) was further off than none.
ir::ValueId strandCrossings(ir::Builder& b, const std::vector<StrokeAcross>& strokes,
                            const std::vector<ir::ValueId>& means);

} // namespace moire::lower
