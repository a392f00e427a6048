// The excess of two layers of lines that each run three ways (MeetingBeat.h,
// meetingHarmonic) against brute force: the mean over the torus of the first layer's two
// free indices (the third held by the meeting sum c) of the pairs' papers' product, and of
// the first layer's own papers' product, against the pairs' means multiplied plus the
// harmonics' sum.
#include "compiler/lower/MeetingBeat.h"

#include <cmath>
#include <doctest/doctest.h>

namespace moire::lower {
namespace {

// Within a stroke of half-width h about the whole numbers shifted by `about`.
bool within(double t, double about, double h) {
    const double d = t - about;
    return std::abs(d - std::round(d)) < h;
}

struct Line {
    double half, partnerHalf, offset, sigma;
};

// The paper of line k and its partner at index t.
double pairPaper(const Line& k, double t) {
    return within(t, 0.0, k.half) || within(t, k.offset, k.partnerHalf) ? 0.0 : 1.0;
}

// A pair's mean paper over one period of its index, by midpoints.
double pairMean(const Line& k) {
    constexpr int n = 1 << 16;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += pairPaper(k, (i + 0.5) / n);
    return sum / n;
}

struct Means {
    double paired, alone;
};

// Over an n x n grid of midpoints of the torus (t1, t2): i_1 = t1, i_2 = t2 and
// i_3 = sigma_3 (c - t1 - sigma_2 t2), so that sum sigma_k i_k = c.
Means torusMeans(double c, const std::array<Line, 3>& l) {
    constexpr int n = 1024;
    double paired = 0.0, alone = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double t1 = (i + 0.5) / n, t2 = (j + 0.5) / n;
            const double index[3] = {t1, t2, l[2].sigma * (c - t1 - l[1].sigma * t2)};
            double p = 1.0, a = 1.0;
            for (int k = 0; k < 3; ++k) {
                p *= pairPaper(l[k], index[k]);
                a *= within(index[k], 0.0, l[k].half) ? 0.0 : 1.0;
            }
            paired += p;
            alone += a;
        }
    return {paired / (double(n) * n), alone / (double(n) * n)};
}

} // namespace

TEST_CASE("meetingHarmonic: two layers' lines three ways, against the torus") {
    struct Case {
        double c;
        std::array<Line, 3> lines;
    };
    // Strokes a fifth of the spacing (half 0.1) and others; partners in step, half a period
    // off, part way, wide enough to wrap past the next whole number, and none.
    const Case kCases[] = {
        {0.0, {{{0.1, 0.1, 0.0, 1}, {0.1, 0.1, 0.0, -1}, {0.1, 0.1, 0.0, 1}}}},
        {0.0, {{{0.1, 0.1, 0.3, 1}, {0.1, 0.1, -0.2, -1}, {0.1, 0.1, 0.45, 1}}}},
        {0.3, {{{0.1, 0.12, 0.05, 1}, {0.08, 0.1, 0.5, 1}, {0.15, 0.1, -0.1, -1}}}},
        {0.5, {{{0.2, 0.35, 0.4, 1}, {0.3, 0.25, 0.9, -1}, {0.1, 0.45, -0.7, -1}}}},
        {0.2, {{{0.1, 0.0, 0.0, 1}, {0.15, 0.0, 0.0, 1}, {0.1, 0.0, 0.0, -1}}}},
    };
    for (const Case& k : kCases) {
        CAPTURE(k.c);
        CAPTURE(k.lines[1].offset);
        std::array<MeetingLine<double>, 3> lines;
        double product = 1.0, own = 1.0;
        for (int i = 0; i < 3; ++i) {
            const Line& l = k.lines[i];
            lines[i] = {l.half, l.partnerHalf, l.offset, l.sigma};
            product *= pairMean(l);
            own *= 1.0 - 2.0 * l.half;
        }
        double paired = 0.0, alone = 0.0;
        for (int m = 1; m <= kMeetingHarmonics; ++m) {
            const MeetingHarmonic<double> h = meetingHarmonic(double(m), k.c, 0.0, 0.0, lines);
            paired += h.paired;
            alone += h.alone;
        }
        const Means want = torusMeans(k.c, k.lines);
        // The harmonics past the eighth, and the torus's grid, leave under 0.0015.
        CHECK(std::abs(product + paired - want.paired) < 1.5e-3);
        CHECK(std::abs(own + alone - want.alone) < 1.5e-3);
        // And the excess is there to find: partners in step through the meeting points, where
        // the pairs' means alone miss it.
        if (&k == &kCases[0]) CHECK(std::abs(product - want.paired) > 3e-3);
    }
}

} // namespace moire::lower
