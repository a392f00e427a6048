// The fidelity sweep of spec §9.3 for the walking-family solver (compiler/lower/WalkingFamily):
// shapes x spacings x drifts (the offset, sized by the drift constant m = rho(-delta) against
// the spacing, aimed at a facet, at a vertex or in between) x turns x zooms, each probed at
// seeded points on the exact (double) interpreter and held against the independent brute
// force of tests/reference/WalkingReference. The claims under test (§9.3, §9.6):
//  - wherever Theorem 4's interval fits the budget (span <= B = 1024, read from the solver's
//    own aux outputs), the clamped distance is the reference's, or both are inked solid;
//  - nowhere does the solver invent ink: it minimises over a subset of the members, so its
//    distance is never below the reference's (where the reference is complete).
// Outside the budget nothing is claimed; the figures there are counted and, with
// MOIRE_WALKING_REPORT=1, printed (docs/families.md, "Walking families", quotes them).
#include "tests/support/WalkingHarness.h"

using namespace moire;
using namespace moire::walktest;

namespace {

// The reference's cost at a point: it stops at the first n past which Eq. 28 proves every
// member outside the guard, or never at m = s.
double referenceMembers(const Setting& st, double x, double y) {
    const double r = std::hypot(x, y), m = reference::drift(st.w), s = st.w.spacing, g = st.guard();
    if (m < s) return std::max(0.0, (r - st.w.phase + g) / (s - m));
    if (m > s) return std::max(0.0, (r + st.w.phase + g) / (m - s));
    return r - st.w.phase + g < 0.0 || -r - st.w.phase > g ? 0.0 : INFINITY;
}

// Turn 0 with a circle, or with a whole-sided polygon whose drift is at most the spacing:
// the solver answers in closed form (§7.5), exactly whatever the interval's width.
bool closedForm(const Setting& st) {
    return st.w.turn == 0.0 && (st.w.facets == 0 || reference::drift(st.w) <= st.w.spacing + 1e-4);
}

struct Tally {
    long settings = 0, points = 0, compared = 0, invented = 0, unreferenced = 0;
    // Points whose interval fits the budget; those of them not inked solid; disagreements.
    long fit = 0, fitValued = 0, fitDisagree = 0;
    long closedOut = 0, closedOutDisagree = 0;                 // outside it, closed form
    long stridedOut = 0, stridedCompared = 0, stridedLost = 0; // outside it, scanned
    long settingsOut = 0, settingsStridedOut = 0;
    double stridedLoss = 0.0, stridedWorst = 0.0; // coverage lost against the reference
    double stridedInk = 0.0;                      // the reference's coverage there
};

} // namespace

TEST_CASE(
    "walking sweep: exact wherever the certified interval fits the budget, never inventing ink") {
    const int shapes[] = {0, 3, 4, 6, 5, 9};
    const double spacings[] = {1.0, 3.0, 8.0, 20.0, 45.0, 80.0};
    const double drifts[] = {0.0, 0.3, 0.8, 0.97, 1.0, 1.4}; // m / s
    const double turns[] = {0.0, 0.4 * kDeg, 6.0 * kDeg};
    const double zooms[] = {2.0, 1.0, 0.2};
    const int kPoints = 36;
    const double kMaxReference = 50000; // members the reference may scan for one point
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Tally t;
    for (int shape : shapes)
        for (double s : spacings)
            for (double f : drifts)
                for (double turn : turns)
                    for (double zoom : zooms) {
                        Setting st;
                        st.w.facets = shape;
                        st.w.spacing = s;
                        st.w.turn = (unit(rng) < 0.5 ? -1 : 1) * turn;
                        st.w.phase = s * std::vector<double>{0.0, 0.37, 1.6, -0.2}[t.settings % 4];
                        st.zoom = zoom;
                        st.stroke = t.settings % 3 == 0 ? 0.2 * s : 1.5;
                        // -delta at a facet normal, at a vertex (half way between two), or
                        // anywhere, sized so that m = rho(-delta) = f s.
                        const int kind = t.settings % 3, sides = std::max(shape, 1);
                        const double facet = 2 * kPi * std::floor(unit(rng) * sides) / sides;
                        const double dir = kind == 0   ? facet
                                           : kind == 1 ? facet + kPi / sides
                                                       : 2 * kPi * unit(rng);
                        const double len =
                            f * s / reference::radius(shape, std::cos(dir), std::sin(dir));
                        st.w.offsetX = -len * std::cos(dir);
                        st.w.offsetY = -len * std::sin(dir);
                        ++t.settings;
                        const double extent = 650.0 / zoom; // the frame of a 1200 x 800 view
                        bool out = false, stridedOut = false;
                        for (int i = 0; i < kPoints; ++i) {
                            double x, y; // half uniform over the frame, half on or near members
                            if (i % 2 == 0)
                                inDisc(extent, rng, x, y);
                            else
                                nearMember(st, extent, rng, x, y);
                            Out o = solve(st, x, y);
                            ++t.points;
                            REQUIRE(std::isfinite(o.distance));
                            const bool fits = o.hi - o.lo + 1.0 <= 1024.0;
                            const bool closed = !fits && closedForm(st);
                            out |= !fits;
                            stridedOut |= !fits && !closed;
                            t.fit += fits, t.closedOut += closed, t.stridedOut += !fits && !closed;
                            INFO(describe(st));
                            SHOW(shape, s, f, zoom, x, y, o.distance, o.lo, o.hi);
                            if (referenceMembers(st, x, y) > kMaxReference) {
                                // Only where the interval is wide: a fitting one bounds the scan.
                                CHECK_FALSE(fits);
                                ++t.unreferenced;
                                continue;
                            }
                            reference::Nearest ref =
                                reference::nearest(st.w, x, y, st.guard(), kMaxReference + 1);
                            REQUIRE(ref.complete);
                            SHOW(ref.distance, ref.argmin);
                            ++t.compared;
                            const double tol = 1e-10 * (1.0 + std::hypot(x, y) + s);
                            // A minimum over a subset of the members is never below the minimum.
                            t.invented += o.distance < ref.distance - tol;
                            CHECK(o.distance >= ref.distance - tol);
                            const bool same =
                                std::fabs(o.distance - ref.distance) <= tol ||
                                (o.distance <= st.accept() && ref.distance <= st.accept());
                            if (fits || closed) {
                                (fits ? t.fitDisagree : t.closedOutDisagree) += !same;
                                t.fitValued += fits && ref.distance > st.accept();
                                CHECK(same);
                            } else {
                                double loss = st.coverage(ref.distance) - st.coverage(o.distance);
                                ++t.stridedCompared;
                                t.stridedLost += loss > 0.5;
                                t.stridedLoss += loss;
                                t.stridedInk += st.coverage(ref.distance);
                                t.stridedWorst = std::max(t.stridedWorst, loss);
                            }
                        }
                        t.settingsOut += out;
                        t.settingsStridedOut += stridedOut;
                    }
    REPORT("walking sweep: ", t.settings, " settings, ", t.points, " points, ", t.compared,
           " compared with the reference (", t.unreferenced,
           " too costly for it); invented ink at ", t.invented);
    REPORT("  interval fits the budget: ", t.fit, " points (", t.fitValued,
           " of them not inked solid), ", t.fitDisagree, " disagree");
    REPORT("  outside it: ", t.fit == t.points ? 0 : t.points - t.fit, " points in ", t.settingsOut,
           " settings; closed form ", t.closedOut, " points (", t.closedOutDisagree,
           " disagree); scanned with a stride ", t.stridedOut, " points in ", t.settingsStridedOut,
           " settings, ", t.stridedCompared, " compared: ", t.stridedLost,
           " lost ink (coverage down > 0.5), mean loss ",
           t.stridedCompared ? t.stridedLoss / t.stridedCompared : 0.0, ", worst ", t.stridedWorst,
           "; the reference's mean coverage there ",
           t.stridedCompared ? t.stridedInk / t.stridedCompared : 0.0);
    CHECK(t.settings >= 1000);
    CHECK(t.fit >= t.points / 2);
}
