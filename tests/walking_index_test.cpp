// The walking-family solver's searched index, its strided scan, the single-precision JIT
// and degenerate parameters; see walking_test.cpp for the other claims and the references.
#include "tests/support/WalkingHarness.h"

using namespace moire;
using namespace moire::walktest;

TEST_CASE("walking: the searched index is integral on members and continuous between them") {
    // Settings where members do not cross: drift m = 0.3 s and turns small enough that
    // |theta| r stays well under s - m, so h_p(n) is strictly decreasing in n at every point
    // probed. Then a point between members n0 and n0 + 1 (h(n0) >= 0 > h(n0 + 1)) must have
    // floor(index) = n0, the reference's nearest member is n0 or n0 + 1, a point on member n
    // has index n, and the index moves continuously as the point does, including where the
    // nearest member changes hands half way between two members.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    long onMembers = 0, between = 0, steps = 0;
    for (int n : {0, 3, 4, 6, 5})
        for (double turn : {0.0, 0.3 * kDeg, -0.3 * kDeg})
            for (double f : {0.0, 0.3}) {
                Setting st;
                st.w.facets = n;
                st.w.spacing = 10.0;
                st.w.phase = f == 0.0 ? 0.0 : 3.0;
                st.w.turn = turn;
                st.zoom = 4.0;
                st.stroke = 0.5;
                setDrift(st.w, f, 2 * kPi * unit(rng));
                SHOW(n, turn, f);
                for (int j = 0; j < 30; ++j) { // on member m: index m
                    int64_t m = 1 + static_cast<int64_t>(unit(rng) * 14);
                    double x, y;
                    onMember(st.w, m, 2 * kPi * unit(rng), 0.0, x, y);
                    SHOW(m, x, y);
                    REQUIRE(std::fabs(reference::residual(st.w, x, y, m)) <
                            1e-9 * (1.0 + std::hypot(x, y)));
                    CHECK(solve(st, x, y).index ==
                          doctest::Approx(static_cast<double>(m)).epsilon(1e-9));
                    ++onMembers;
                }
                for (int j = 0; j < 30; ++j) { // between members
                    double r = 150.0 * std::sqrt(unit(rng)), a = 2 * kPi * unit(rng);
                    double x = r * std::cos(a), y = r * std::sin(a);
                    if (reference::residual(st.w, x, y, 0) < 0.0) continue; // inside member 0
                    int64_t n0 = 0;
                    while (reference::residual(st.w, x, y, n0 + 1) >= 0.0) ++n0;
                    reference::Nearest ref = reference::nearest(st.w, x, y, st.guard());
                    double index = solve(st, x, y).index;
                    SHOW(x, y, index, n0, ref.argmin);
                    CHECK(std::floor(index) == static_cast<double>(n0));
                    CHECK((ref.argmin == n0 || ref.argmin == n0 + 1));
                    ++between;
                }
                // A straight walk of three spacings in steps of s / 200: the index gradient is
                // at most about 1 / (s - m) per world unit, so a step moves it by < 0.01.
                double a = 2 * kPi * unit(rng), r0 = 20.0 + 100.0 * unit(rng),
                       dir = 2 * kPi * unit(rng);
                double x = r0 * std::cos(a), y = r0 * std::sin(a), last = solve(st, x, y).index;
                for (int k = 0; k < 600; ++k) {
                    x += 0.05 * std::cos(dir), y += 0.05 * std::sin(dir);
                    double index = solve(st, x, y).index;
                    SHOW(x, y, last, index);
                    CHECK(std::fabs(index - last) < 0.03);
                    last = index;
                    ++steps;
                }
            }
    REPORT("index field: ", onMembers, " points on members, ", between, " between, ", steps,
           " steps");
}

TEST_CASE("walking: past the budget the scan samples the global lattice of its stride") {
    // Near the marginal drift and zoomed out, the certified interval is wider than B = 1024
    // and the scan strides by the least power of two sigma with sigma B >= span (span capped
    // at 2^16). Anchored to multiples of sigma rather than to n_lo, the members it can see
    // are exactly {n = 0 mod sigma} in the interval, for every pixel, so neighbouring pixels
    // agree on which members exist (§7.4, §9.6). The Lipschitz skip only drops members that
    // cannot beat the best, so the answer is exactly min(G, min |h_p(n)| over that lattice),
    // which is computed here with the reference's residual. The pixel-anchored lattice
    // {n_lo + k sigma} gives a different answer at many of these points, so the check tells
    // the two apart.
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    long strided = 0, telling = 0;
    for (int n : {0, 3, 4, 6})
        for (double f : {0.97, 1.03}) {
            Setting st;
            st.w.facets = n;
            st.w.spacing = 6.0;
            st.w.phase = 1.0;
            st.w.turn = 0.25 * kDeg;
            st.zoom = 0.2;
            setDrift(st.w, f, 2 * kPi * unit(rng));
            for (int j = 0; j < 40; ++j) {
                double r = 3000.0 * std::sqrt(unit(rng)), a = 2 * kPi * unit(rng);
                double x = r * std::cos(a), y = r * std::sin(a);
                Out o = solve(st, x, y);
                double hi = std::min(o.hi, o.lo + 65535.0), span = hi - o.lo + 1.0;
                if (span <= 1024.0) continue;
                double sigma = 1.0;
                while (sigma * 1024.0 < span) sigma *= 2.0;
                auto latticeMin = [&](double first) {
                    double best = st.guard();
                    for (double m = first; m <= hi; m += sigma)
                        best = std::min(best, std::fabs(reference::residual(
                                                  st.w, x, y, static_cast<int64_t>(m))));
                    return best;
                };
                double anchored = latticeMin(sigma * std::ceil(o.lo / sigma));
                SHOW(n, f, x, y, o.lo, o.hi, sigma, o.distance, anchored);
                CHECK(agrees(st, o.distance, anchored, x, y));
                ++strided;
                if (!agrees(st, latticeMin(o.lo), anchored, x, y)) ++telling;
            }
        }
    REPORT("strided pixels: ", strided, "; where anchoring at n_lo would differ: ", telling);
    CHECK(strided >= 150);
    CHECK(telling >= strided / 10);
}

TEST_CASE("walking: the single-precision JIT draws what the exact interpreter draws") {
    // Rendered coverage (checkJitDrawsLikeInterpreter). The scenes cover each branch, a
    // zoomed-out strided scan, the marginal drift, and large indices.
    const std::vector<std::pair<std::string, std::string>> scenes = {
        {"rotated triangles", "camera { zoom = 1 }\nlayer { family = triangles; spacing = 8; "
                              "offset = (1.5, 0.5); turn = 1.5deg; stroke = 1.5 }"},
        {"rotated triangles, far out",
         "camera { zoom = 1; center = (3000, 2000) }\nlayer { family = triangles; spacing = 8; "
         "offset = (1.5, 0.5); turn = 1.5deg; stroke = 1.5 }"},
        {"translated circles",
         "camera { zoom = 0.7 }\nlayer { family = circles; spacing = 6; phase = 2; offset = (4, "
         "3); stroke = 1.2 }\n"
         "layer { family = circles; spacing = 5; offset = (-9, 4); stroke = 1 }"},
        {"translated circles, far out",
         "camera { zoom = 1; center = (4000, 3500) }\nlayer { family = circles; spacing = 6; phase "
         "= 2; offset = (4, 3); stroke = 1.2 }"},
        {"translated hexagons near m = s, squares at it",
         "camera { zoom = 0.5 }\nlayer { family = hexagons; spacing = 10; offset = (-9.99, 0); "
         "stroke = 2 }\n"
         "layer { family = squares; spacing = 7; offset = (-7, 3); stroke = 1.5 }"},
        {"strided scan (span ~6000, stride 8)",
         "camera { zoom = 0.5; center = (3000, 0) }\nlayer { family = hexagons; spacing = 10; "
         "offset = (9.5, 0); turn = 0.2deg; stroke = 1 }"},
        {"zoomed out, turned circles", "camera { zoom = 0.2 }\nlayer { family = circles; spacing = "
                                       "12; offset = (2, -3); turn = 0.7deg; stroke = 2 }"},
        // Just off the marginal drift, far from the origin, where the zeros sit at indices of
        // 1e4-1e7 and the members are packed 2e-4 apart: solid ink, which single precision
        // used to lose in stripes (the candidates' residuals cancelled; see the solver).
        {"squares just off m = s, far out",
         "camera { zoom = 0.5; center = (2000, 500) }\nlayer { family = squares; spacing = 7; "
         "offset = (-6.9998, 3); stroke = 1.5 }"},
        {"circles just past L = s, far out",
         "camera { zoom = 0.5; center = (-2000, 500) }\nlayer { family = circles; spacing = 7; "
         "offset = (-7.0002, 0); stroke = 1.5 }"},
        {"circles just past L = s, no real roots",
         "camera { zoom = 0.5; center = (0, 3000) }\nlayer { family = circles; spacing = 7; offset "
         "= (-7.0002, 0); stroke = 1.5 }"},
        {"rotated nonagons", "camera { zoom = 1; center = (400, -300) }\nlayer { family = ngon; "
                             "sides = 9; spacing = 9; turn = 2deg; stroke = 1 }"},
    };
    checkJitDrawsLikeInterpreter(scenes, 240, 160);
}

TEST_CASE("walking: degenerate parameters give finite outputs") {
    // Nothing a slider or a typo can reach may turn into NaN or infinity: a zero or negative
    // spacing (held at a tiny pitch, as the phase families do: solid ink rather than 0/0),
    // phases beyond the spacing or negative, offsets far larger than the spacing, exactly
    // marginal drifts, whole turns, side counts below 3 or fractional, extreme zooms, and
    // points on the centre and on the walk's line.
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double spacings[] = {0.0, -4.0, 1e-4, 8.0};
    const double phases[] = {0.0, 30.0, -5.0};
    const std::pair<double, double> offsets[] = {{0, 0}, {8, 0}, {-8, 0}, {1e5, -3e4}, {0, -8}};
    const double turns[] = {0.0, 2 * kPi, -0.7, 1e-9};
    const double sides[] = {-1.0, 0.0, 1.0, 2.0, 2.5, 3.0, 24.0, 100.0}; // -1: circles
    long probes = 0;
    for (double s : spacings)
        for (double phase : phases)
            for (auto [ox, oy] : offsets)
                for (double turn : turns)
                    for (double n : sides) {
                        Setting st;
                        st.w.spacing = s;
                        st.w.phase = phase;
                        st.w.offsetX = ox, st.w.offsetY = oy;
                        st.w.turn = turn;
                        st.sides = n;
                        st.zoom = std::vector<double>{1e-3, 1.0, 1e3}[probes % 3];
                        for (auto [x, y] :
                             {std::pair{0.0, 0.0}, std::pair{8.0, 0.0}, std::pair{-40.0, 0.0},
                              std::pair{300.0 * unit(rng) - 150.0, 300.0 * unit(rng) - 150.0}}) {
                            Out o = solve(st, x, y);
                            SHOW(s, phase, ox, oy, turn, n, x, y);
                            CHECK(std::isfinite(o.distance));
                            CHECK(o.distance >= 0.0);
                            CHECK(std::isfinite(o.index));
                            CHECK(std::isfinite(o.lo));
                            CHECK(!std::isnan(o.hi));
                            ++probes;
                        }
                    }
    REPORT("degenerate settings probed: ", probes);
}
