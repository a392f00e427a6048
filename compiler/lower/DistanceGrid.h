// A crowd of members given by their distance that run two or three ways over the pixel, a grid's
// lines (docs/filtering.md, "A grid given by its distance"): read as two or three families of
// parallel lines, each by the index it runs by, and its mean in closed form. The distance is
// the nearest family's distance, so the stroke d < h is the union of the families' strokes;
// each family's mean is a phase family's (Prefilter.h, squareMeanInk) once its spacing and
// the pixel's place among its lines are known. Over a pixel that holds at least two of each,
// two families cross at every offset alike, so their union is that of independent inks; three
// do not: where their indices' gradients nearly cancel (a triangle lattice's lines), the sum
// of their indices is nearly constant and decides where the third family's lines pass the
// other two's crossings (tripleExcess).
//
// The directions come from the 4 x 4 parts (DistanceFamily.cpp reads them), each part's
// normal as a doubled angle (a normal and its opposite are one direction): the parts within
// 45 degrees of the pixel centre's normal are the first family's, the rest another's, split
// by the side of the first they turn to (three ways) or taken together (two ways), and each
// family's mean direction must stand for its parts (the length of their mean). A family's
// spacing is read from its part furthest from its own line, by probes along another family's
// lines (where that family's distance stays as it is) until one reads the next line of its
// own (a normal parallel to the part's, a foot further along it).
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/DistanceReading.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace moire::lower {

// The parts' directions, gathered over the parts as loop-carried values: how many parts are
// another family's than the first and their doubled angles' sums, the same for those turned
// to the first's left (doubled angles ahead of it), and the first family's, the left's and
// the right's parts furthest from their lines (each one's distance along its normal and its
// place in the pixel, world units along the pixel's sides).
class PartDirections {
  public:
    static constexpr size_t kCarried = 15;
    // `centre`: the pixel centre's reading, whose direction is the first family's.
    PartDirections(ir::Builder& b, const Reading& centre);
    std::vector<ir::ValueId> start() const;
    // A part at p: its distance along its normal `away`, its normal's doubled angle (cos2,
    // sin2), `some` where it has one. Returns the carried values with it counted.
    std::vector<ir::ValueId> add(std::span<const ir::ValueId> carried, ir::ValueId away,
                                 ir::ValueId cos2, ir::ValueId sin2, ir::ValueId some,
                                 PixelPoint p) const;

  private:
    ir::Builder& b_;
    ir::ValueId cos2_, sin2_;
};

// The grid's reading: `trust`, how far the parts run two or three ways and every family's
// spacing was found (0 to 1); `mean`, the pixel's mean ink in closed form; `members`, the
// sparsest family's lines a pixel (by which the caller hands over to the closed form); and
// each way's index as a phase family's (members at its integers): its value at the pixel's
// centre, its gradient's length and world components per world unit, and its mean ink over
// the pixel (with which the union of fine layers lets the grid beat with another layer, as a
// lattice's lines do), the third all 0 where the lines run two ways; `halfWidth`, the
// stroke's half-width across the lines in world units; `threeWays` 1 where they run three
// ways, else 0.
struct GridRead {
    ir::ValueId trust, mean, members;
    struct Way {
        ir::ValueId index, grad, gradX, gradY, mean;
    };
    Way ways[3];
    ir::ValueId halfWidth, threeWays;
};

// How far three families of lines crossing over a pixel depart from independent inks, in
// mean ink. Family k's paper is P_k(i_k), 1 where its index i_k is further than w_k / 2 from a
// whole number, whose Fourier coefficients are 1 - w_k at 0 and -sin(pi m w_k) / (pi m) at
// +-m. The union's paper is the product P_1 P_2 P_3; of its terms, those that vary over the
// pixel only as slowly as c = i_1 + i_2 + i_3 (the signs of the indices taken so that their
// gradients nearly cancel) are the product of the three's mean papers and the terms m = m_1 =
// m_2 = m_3, whose sum is the paper's excess over independent inks:
//   -2 sum_m prod_k (sin(pi m w_k) / (pi m)) cos(2 pi m c),
// each averaged over the square pixel by sinc(m along) sinc(m across) (sinc(x) = sin(pi x) /
// (pi x), along and across c's change over the pixel's two sides). The rest wave fast across
// the pixel (their frequencies are sums of crossing families'), and their mean is the
// independent inks' product of means. The ink's excess is the paper's with its sign turned:
// for three strokes a fifth of their spacing wide through common points, 0.022 of ink
// (0.510 against 0.488). The m-th term falls as 1 / m^3: kTripleHarmonics of them leave under
// 0.0005.
constexpr int kTripleHarmonics = 8;
// The senses that make three families' index gradients nearly cancel: the least of the four
// sums i_1 + s_2 i_2 + s_3 i_3, each gradient given by its change along and across the pixel's
// sides (u_k, v_k). Returns the senses, the sum c at the pixel's centre, and c's change along
// and across (signed). What tripleExcess reads c by, for a layer's own lines and for two
// layers' meeting points (MeetingBeat.h).
struct MeetingSum {
    ir::ValueId s2, s3, c, along, across;
};
MeetingSum meetingSum(ir::Builder& b, const std::array<ir::ValueId, 3>& index,
                      const std::array<ir::ValueId, 3>& u, const std::array<ir::ValueId, 3>& v);
template <class T>
T tripleExcess(T c, T w1, T w2, T w3, T along, T across) {
    using ir::literal;
    using std::abs;
    using std::cos;
    using std::max;
    using std::min;
    using std::sin;
    constexpr double kPi = 3.14159265358979323846;
    const T zero = literal(c, 0.0), one = literal(c, 1.0);
    auto width = [&](T w) { return min(max(w, zero), one); };
    const T a = width(w1), b = width(w2), d = width(w3);
    auto sinc = [&](T x) {
        const T t = max(abs(x), literal(x, 1e-6)) * kPi;
        return sin(t) / t;
    };
    T sum = zero;
    for (int m = 1; m <= kTripleHarmonics; ++m) {
        const double pm = kPi * m;
        const T term = sin(a * pm) * sin(b * pm) * sin(d * pm) * (1.0 / (pm * pm * pm));
        sum = sum + term * cos(c * (2.0 * pm)) * sinc(along * double(m)) * sinc(across * double(m));
    }
    return sum * 2.0;
}
// A point whose nearest member crosses the centre's (where `found`), taken as the second
// family's start where no part reads that family (the parts alias with the grid).
struct CrossingStart {
    ir::ValueId found;
    PixelPoint at;
};
// Whether a few points of the pixel away from the parts' lattice (kCrossingLooks of them,
// moved from pixel to pixel by pixelShift) read a member crossing the direction whose
// doubled angle is (cos2, sin2), the parts' axis: the first such point. The 4 x 4 parts
// stand a quarter of a pixel apart, and at zooms where that is nearly a whole number of a
// grid's lines they all read the same relative place, and one family.
CrossingStart crossingSeen(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                           ir::ValueId cos2, ir::ValueId sin2);

// `carried`: PartDirections' values after every part; (cos2, sin2) the sums of every part's
// doubled angle, `directed` how many have one. Read where `wanted` (else 0s).
GridRead gridRead(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                  ir::ValueId halfWidth, std::span<const ir::ValueId> carried, ir::ValueId cos2,
                  ir::ValueId sin2, ir::ValueId directed, ir::ValueId wanted,
                  const CrossingStart& crossing);

} // namespace moire::lower
