#pragma once
// Two layers of lines that each run three ways (families given by their distance read as a
// grid's three ways, DistanceGrid.h) laid over one another where both crowd: the part of
// their correlation that the pairs of lines, taken as independent of one another
// (FineUnion.cpp, strandCorrelation), miss where each layer's three lines meet.
//
// Over a fine pixel the first layer's three indices i_k run fast, but not independently:
// their sum c = sum sigma_k i_k (the senses sigma_k = +-1 taken so that the gradients nearly
// cancel) runs as slowly as the beat. Line k of the first layer is paired with the second
// layer's line whose beat with it runs slowest, which as a function of i_k is a stroke about
// delta_k (mod 1), so the pair's paper is g_k(i_k) = (1 - X_k(i_k)) (1 - Y_k(i_k)), X_k the
// first's stroke (half-width a_k) about the integers and Y_k the second's (half-width b_k)
// about delta_k. Over the pixel, with i_1 and i_2 uniform and i_3 held by c,
//   E[prod_k g_k(i_k)] = sum_m e(m c) prod_k G_k(sigma_k m),   G_k the Fourier coefficients,
// whose term m = 0 is the product of the pairs' means, what the pairs' closed forms give
// (with the beat swept over the pixel), and the rest the excess this header adds. With
//   X^(m) = sin(2 pi m a) / (pi m),   Y^(m) = e(-m delta) sin(2 pi m b) / (pi m),
// and (XY)^(m) the coefficient of the strokes' overlap (an interval [l, r] within a period:
// e(-m (l + r) / 2) sin(pi m (r - l)) / (pi m)), G(m) = -X^(m) - Y^(m) + (XY)^(m) for m != 0,
// and G(-m) its conjugate (g is real). The layer alone, G(m) = -X^(m), gives its own papers'
// excess, the three lines' meeting points (DistanceGrid.h, tripleExcess, whose sign is the
// ink's). Each harmonic is averaged over the square pixel as tripleExcess's are, by
// sinc(m along) sinc(m across) with along and across c's change over the pixel's sides; the
// beats' own change over the pixel is left to the pairs' term m = 0.
#include "compiler/ir/Builder.h"
#include "compiler/lower/FineUnion.h"

#include <array>
#include <cmath>

namespace moire::lower {

// One line of the first layer and its partner, in the line's index units: the half-widths
// of the line's stroke and of the partner's (0 for none), the partner's offset delta (i_x -
// s i_y for the pair's sense s) and the line's sense sigma in the meeting sum (+-1).
template <class T>
struct MeetingLine {
    T half, partnerHalf, offset, sigma;
};

// Harmonic m (m >= 1, as a value so that a loop can carry it) of the papers' excess over
// the pixel: `paired` of the pairs' product, prod_k g_k, and `alone` of the first layer's own
// lines, prod_k (1 - X_k), both already doubled (the terms m and -m) and averaged over the
// pixel.
template <class T>
struct MeetingHarmonic {
    T paired, alone;
};

template <class T>
MeetingHarmonic<T> meetingHarmonic(T m, T c, T along, T across,
                                   const std::array<MeetingLine<T>, 3>& lines) {
    using ir::literal;
    using std::abs;
    using std::cos;
    using std::floor;
    using std::max;
    using std::min;
    using std::sin;
    constexpr double kPi = 3.14159265358979323846;
    const T zero = literal(c, 0.0), half = literal(c, 0.5);
    const T pm = m * kPi;
    auto sinc = [&](T x) {
        const T t = max(abs(x), literal(x, 1e-6)) * kPi;
        return sin(t) / t;
    };
    // The product of the three coefficients G_k(sigma_k m), and of the lines' own -X^(m).
    T re = literal(c, 1.0), im = zero, own = literal(c, 1.0);
    for (const MeetingLine<T>& k : lines) {
        const T a = min(max(k.half, zero), half), b = min(max(k.partnerHalf, zero), half);
        const T x = sin(pm * a * 2.0) / pm;
        const T y = sin(pm * b * 2.0) / pm;
        const T d = k.offset - floor(k.offset + 0.5);
        T gr = -x - y * cos(pm * d * 2.0), gi = y * sin(pm * d * 2.0);
        // The overlap of [-a, a] with the partner's stroke about d - 1, d and d + 1.
        for (double shift : {-1.0, 0.0, 1.0}) {
            const T l = max(-a, d + shift - b), r = min(a, d + shift + b);
            const T len = max(r - l, zero), mid = (l + r) * 0.5;
            const T o = sin(pm * len) / pm;
            gr = gr + o * cos(pm * mid * 2.0);
            gi = gi - o * sin(pm * mid * 2.0);
        }
        gi = gi * k.sigma;
        const T nr = re * gr - im * gi;
        im = re * gi + im * gr;
        re = nr;
        own = own * -x;
    }
    const T w = sinc(m * along) * sinc(m * across) * 2.0;
    const T cr = cos(pm * c * 2.0), ci = sin(pm * c * 2.0);
    return {(re * cr - im * ci) * w, own * cr * w};
}

// The harmonics meetingHarmonic sums, 1 to kMeetingHarmonics (each falls as 1 / m^3, as
// tripleExcess's do).
constexpr int kMeetingHarmonics = 8;

// One layer's three lines as the meeting sum reads them: each line's index, its change
// along and across the pixel's sides, its stroke's half-width in index units, and its
// partner's index, half-width and sense (the pair's s).
struct MeetingSide {
    struct Line {
        ir::ValueId index, u, v, half;                // u, v: the index's change over a pixel side
        ir::ValueId partnerIndex, partnerHalf, sense; // unused on the second side
    };
    std::array<Line, 3> lines;
};

// The covariance of the two layers' papers that the pairs taken as independent miss:
//   sum_m paired_m - alone1 (1 - m)_2 - alone2 (1 - m)_1 - alone1 alone2,
// with alone1 and alone2 each layer's own excess (the meeting points its mean holds), and
// (1 - m)_j the product of layer j's lines' blank shares. `blank1` and `blank2` are those
// products.
ir::ValueId meetingCovariance(ir::Builder& b, const MeetingSide& first, const MeetingSide& second,
                              ir::ValueId blank1, ir::ValueId blank2);

} // namespace moire::lower
