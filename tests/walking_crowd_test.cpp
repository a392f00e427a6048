// The walking solver's crowd estimate under the mean filter (docs/filtering.md, "Walking
// families past the budget"): where Theorem 4's interval is wider than the budget the scan
// strides, and the filter draws min(1, 2 h density) from the family's estimate of its members'
// density instead. Judged against the independent exhaustive reference (tests/reference): a
// count of the members that pass near the point, and the pixel's box mean of the exact field;
// the JIT and Vulkan (where there is one) against the interpreter.
#include "runtime/output/Render.h"
#include "tests/support/WalkingHarness.h"

#include <array>

using namespace moire;
using namespace moire::walktest;

namespace {

constexpr int64_t kSpanCap = 65536; // the solver's widest interval (lower::kWalkSpanCap)

// The two strided settings: triangles whose drift rho(-delta) equals their spacing at a
// 0.5 degree turn, and circles offset 7.8 at spacing 8 at a 1 degree turn.
Setting triangles(double stroke) {
    Setting st;
    st.w.facets = 3, st.w.spacing = 10, st.w.offsetX = -10, st.w.turn = 0.5 * kDeg;
    st.stroke = stroke;
    return st;
}
// A polygon family of stroke 1.5, at `zoom`.
Setting polygon(int facets, double spacing, double offsetX, double offsetY, double turnDeg,
                double zoom = 1.0) {
    Setting st;
    st.zoom = zoom;
    st.w.facets = facets, st.w.spacing = spacing, st.w.offsetX = offsetX, st.w.offsetY = offsetY,
    st.w.turn = turnDeg * kDeg;
    return st;
}
Setting circles(double stroke) {
    Setting st;
    st.w.facets = 0, st.w.spacing = 8, st.w.offsetX = 7.8, st.w.turn = 1 * kDeg;
    st.stroke = stroke;
    return st;
}

// The ink the default (mean) filter draws at world point (x, y): 1 - red, black on white.
double drawnInk(Walker& k, const Setting& st, double x, double y) {
    Prober& p = *k.probe;
    probeOn(p, k, st, x, y);
    return 1.0 - p.at(x, y)[0];
}

Walker& walker(const Setting& st) {
    static std::map<std::string, std::unique_ptr<Walker>> compiled;
    std::unique_ptr<Walker>& k = compiled[familyOf(st)];
    if (!k) k = std::make_unique<Walker>(familyOf(st));
    return *k;
}

// The members of the solver's (capped) interval that pass within `reach` of (x, y), by the
// exhaustive definition h_p(n) (Eq. 24), per 2 reach of residual: members per unit length
// across their strokes, counted along each one's own normal. Members that ink as one are
// counted once: those whose |h| lies within `width` of a member already counted, at (x, y) and
// at two points a unit away across it (a line seen from its two sides, h against -h, is one
// stroke; so are members whose strokes nearly coincide).
double countedDensity(const Setting& st, double x, double y, double reach, int64_t lo,
                      double width) {
    std::vector<std::array<double, 3>> kept;
    for (int64_t n = lo; n < lo + kSpanCap; ++n) {
        const double h = reference::residual(st.w, x, y, n);
        if (std::fabs(h) >= reach) continue;
        const std::array<double, 3> key = {std::fabs(h),
                                           std::fabs(reference::residual(st.w, x + 1, y, n)),
                                           std::fabs(reference::residual(st.w, x, y + 1, n))};
        const bool same = std::any_of(kept.begin(), kept.end(), [&](const auto& k) {
            return std::fabs(k[0] - key[0]) <= width && std::fabs(k[1] - key[1]) <= width &&
                   std::fabs(k[2] - key[2]) <= width;
        });
        if (!same) kept.push_back(key);
    }
    return kept.size() / (2 * reach);
}

// The pixel's box mean of the exact field (k x k samples, the stroke as written, no floor)
// over the members the solver's capped interval holds. The members that can reach any sample
// are gathered once, at the pixel's middle (reference::membersWithin: the residual is
// 1-Lipschitz in p, so they are those within the half-width plus half the pixel's diagonal),
// and each sample looks at those alone: what reference::nearest would find at each sample.
double exactMean(const Setting& st, double x, double y, double pixel, int64_t lo, int k = 4) {
    const double half = st.stroke / 2;
    const std::vector<int64_t> near =
        reference::membersWithin(st.w, x, y, half + pixel * std::sqrt(0.5), lo + kSpanCap);
    int inked = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            const double sx = x + ((i + 0.5) / k - 0.5) * pixel;
            const double sy = y + ((j + 0.5) / k - 0.5) * pixel;
            inked += std::any_of(near.begin(), near.end(), [&](int64_t n) {
                return std::fabs(reference::residual(st.w, sx, sy, n)) < half;
            });
        }
    return double(inked) / (k * k);
}

// A point where the scan strides (the interval wider than the budget), and the solver's answer.
struct Strided {
    double x, y;
    Out out;
};
// Up to `want` strided points of the disc of `radius` pixels about the origin (at the
// setting's zoom), of `tries` points drawn from `seed`.
std::vector<Strided> stridedPoints(Walker& k, const Setting& st, double radius, int tries, int want,
                                   uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Strided> out;
    for (int i = 0; i < tries && static_cast<int>(out.size()) < want; ++i) {
        double x, y;
        inDisc(radius / st.zoom, rng, x, y);
        const Out o = solveOn(k, st, x, y);
        if (o.hi - o.lo + 1 > lower::kWalkBudget) out.push_back({x, y, o});
    }
    return out;
}

// How near a backend's picture must come to the interpreter's: within `within` at `share` of
// the pixels, and a mean difference under `mean`.
struct Bar {
    double within = 2.0 / 255, share = 0.99, mean = 1.0 / 255;
};

// Draws `text` on the interpreter, then on the JIT and the GPU (each skipped where it cannot
// run), and holds each to the interpreter's picture by `bar`.
void checkBackendsDrawAsInterpreter(const std::string& text, Bar bar = {}) {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    auto program = test::compileOk(text);
    const Image ref = test::renderScene(*program, *interp);
    for (const char* name : {"jit", "vulkan"}) {
        CAPTURE(name);
        CAPTURE(text);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        test::ImageDiff d =
            test::compareImages(ref, test::renderScene(*program, *backend), bar.within);
        REPORT(std::string(name), ": within ", bar.within * 255, "/255 ", d.fractionWithin(),
               ", mean |diff| ", d.meanAbs);
        CHECK(d.fractionWithin() >= bar.share);
        CHECK(d.meanAbs <= bar.mean);
    }
}

} // namespace

TEST_CASE("walking crowd: the density drawn is the members' count where the scan strides") {
    // A stroke thin enough that 2 h density stays under 1, so the drawn ink reads the density.
    struct Case {
        Setting st;
        double near, far; // radii where the scan strides
    };
    // The triangles turn by 1/720 of a turn, whose chains that reach a pixel are drawn
    // (ChainSelection.h), not estimated: the estimate is read at 0.49 degrees, whose period
    // (2204 members) is past the chains picked.
    // The circles are read 1300 and 1500 units out, where their intervals turn 18 times and more
    // (nearer, up to 8 turns, their members are drawn, not estimated: "several turns' members").
    Setting fine = triangles(0.004);
    fine.w.turn = 0.49 * kDeg;
    for (const Case& c : {Case{fine, 150, 300}, Case{circles(0.05), 1300, 1500}}) {
        const Setting& st = c.st;
        INFO(describe(st));
        Walker& k = walker(st);
        double worst = 0, drawnSum = 0, countedSum = 0;
        for (double radius : {c.near, c.far})
            for (double angle : {0.3, 1.9, 4.0}) {
                const double x = radius * std::cos(angle), y = radius * std::sin(angle);
                SHOW(x, y);
                const Out o = solveOn(k, st, x, y);
                REQUIRE(o.hi - o.lo + 1 > lower::kWalkBudget); // it strides
                const double drawn = drawnInk(k, st, x, y) / st.stroke;
                // Averaged over a short run of points across the pixel, as the mean is.
                double counted = 0;
                for (int i = -2; i <= 2; ++i)
                    counted += countedDensity(st, x + 0.2 * i, y + 0.13 * i, 4.0,
                                              static_cast<int64_t>(o.lo), st.stroke);
                counted /= 5;
                SHOW(drawn, counted);
                REPORT(describe(st), " at ", x, ", ", y, ": drawn density ", drawn, ", counted ",
                       counted);
                // The count is of a few dozen members a point, and the members cluster and thin
                // out across the frame about the average the estimate draws: within a factor
                // of 2 at each point, within 15% on average.
                CHECK(drawn == doctest::Approx(counted).epsilon(0.5));
                worst = std::max(worst, std::fabs(drawn / counted - 1));
                drawnSum += drawn, countedSum += counted;
            }
        REPORT("worst relative difference ", worst, ", of the averages ",
               drawnSum / countedSum - 1);
        CHECK(drawnSum == doctest::Approx(countedSum).epsilon(0.15));
    }
}

TEST_CASE("walking crowd: the filtered ink is the pixel's exact mean where the scan strides") {
    // The circles at the stroke of the experiments (1.5) and a finer one, at the default zoom
    // and zoomed out: within 0.12 of the exact mean's ink. The triangles at the marginal drift
    // turn by 1/720 of a turn, so their members repeat every 720 and stand a few pixels apart:
    // there the crowd's even grey is only nearer the exact mean than point sampling's thinned
    // lines (docs/filtering.md). Then three of walking_mean's strided polygons, within 0.05:
    // a translated square faster than its spacing (no turn: one chain, drawn member by
    // member), a hexagon drifting towards a vertex (two facets' far crossings), and a triangle
    // whose interval turns under once (the sampled crossings). In walking_mean, the estimate
    // that read one crossing and one cosine drew them 0.15, 0.09 and 0.08 from their exact ink.
    struct Case {
        Setting st;
        double zoom, tolerance; // tolerance < 0: nearer than point sampling only
    };
    for (const Case& c : {Case{circles(1.5), 1.0, 0.12}, Case{circles(1.5), 0.4, 0.12},
                          Case{circles(0.3), 1.0, 0.12}, Case{circles(0.3), 0.4, 0.12},
                          Case{triangles(1.5), 1.0, -1}, Case{polygon(4, 5, 7.5, 0, 0), 0.1, 0.05},
                          Case{polygon(6, 3, 2.07846, 1.2, 3), 0.15, 0.05},
                          Case{polygon(3, 1, 0.34641, 0.2, 0.05), 0.1, 0.05}}) {
        Setting st = c.st;
        st.zoom = c.zoom;
        INFO(describe(st));
        Walker& k = walker(st);
        double drawn = 0, exact = 0, pointed = 0;
        const std::vector<Strided> points = stridedPoints(k, st, 350, 80, 12, 7);
        for (const auto& [x, y, o] : points) {
            drawn += drawnInk(k, st, x, y);
            pointed += st.coverage(o.distance);
            exact += exactMean(st, x, y, 1 / st.zoom, static_cast<int64_t>(o.lo), 8);
        }
        const int n = static_cast<int>(points.size());
        REQUIRE(n >= 6);
        drawn /= n, exact /= n, pointed /= n;
        SHOW(drawn, exact, pointed);
        REPORT(describe(st), ": mean ink drawn ", drawn, ", exact ", exact, ", point-sampled ",
               pointed);
        if (c.tolerance > 0)
            CHECK(std::fabs(drawn - exact) <= c.tolerance);
        else
            CHECK(std::fabs(drawn - exact) < std::fabs(pointed - exact));
    }
}

namespace {
// The ink drawn at each of `points` against the pixel's exact box mean (16 x 16 samples):
// their means, the mean and the largest |drawn - exact|.
struct AgainstExact {
    double drawn = 0, exact = 0, error = 0, worst = 0;
    int n = 0;
};
AgainstExact againstExact(Walker& k, const Setting& st, const std::vector<Strided>& points) {
    AgainstExact out;
    for (const auto& [x, y, o] : points) {
        const double drawn = drawnInk(k, st, x, y);
        const double exact = exactMean(st, x, y, 1 / st.zoom, static_cast<int64_t>(o.lo), 16);
        SHOW(x, y, drawn, exact);
        out.drawn += drawn, out.exact += exact, out.error += std::fabs(drawn - exact);
        out.worst = std::max(out.worst, std::fabs(drawn - exact));
    }
    out.n = static_cast<int>(points.size());
    if (out.n > 0) out.drawn /= out.n, out.exact /= out.n, out.error /= out.n;
    REPORT(describe(st), ": mean ink drawn ", out.drawn, ", exact ", out.exact, ", mean |error| ",
           out.error, ", worst ", out.worst);
    return out;
}
} // namespace

TEST_CASE("walking crowd: a turn of a short period is drawn member by member, chain by chain") {
    // A turn of 10 degrees comes back after 36 members: the family is 36 chains of translated
    // shapes, each drawn with every member's own stroke (WalkingChains.cpp). At the
    // marginal drift with a zero phase every member passes through the origin, and a chain and
    // the one turned from it by a half turn draw the same far lines from their two sides. Three
    // of walking_mean's strided settings there (the estimate that averaged over the turn drew
    // them 11% dark, 9% light and 9% light), at 48 strided points each: the mean ink within
    // 0.02 of the exact box mean's, 0.05 on average a point, and 0.2 at any point (the chains
    // are laid over one another as independent inks, and the pixel as a box facing each
    // stroke: strokes that cross within one pixel are neither; 0.19 at worst, measured).
    for (const Setting& st : {polygon(6, 2, 2, 0, 10, 0.1), polygon(6, 8, 8, 0, 10, 1.0),
                              polygon(0, 20, 5.17638, 19.3185, 10, 0.4)}) {
        INFO(describe(st));
        Walker& k = walker(st);
        const AgainstExact got = againstExact(k, st, stridedPoints(k, st, 500, 160, 48, 5));
        REQUIRE(got.n >= 24);
        CHECK(got.worst <= 0.2);
        CHECK(got.error <= 0.05);
        CHECK(std::fabs(got.drawn - got.exact) <= 0.02);
    }
}

TEST_CASE("walking crowd: a few turns' crossings are drawn member by member where they stand "
          "apart") {
    // Where the interval turns a few times, the members that reach a pixel are those about the
    // residual's crossings of zero. Where a crossing's members stand a pixel or more apart
    // they are drawn, each stroke at its own residual across its own normal; an even comb of
    // their density (what was drawn before) is right on average but grey where one member's
    // stroke or the paper between lies. Four of walking_mean's strided settings at 32 strided
    // points each: within 0.02 a point on average and 0.01 in the mean ink. Drawn as combs
    // they were 0.13, 0.071, 0.049 and 0.090 a point off the exact box mean (the first two
    // 0.04 and 0.03 off in the mean ink); drawn, 0.0005, 0.0004, 0.0067 and 0.013.
    for (const Setting& st :
         {polygon(3, 5, 4.54663, 2.625, 0.05, 1.0), polygon(9, 20, 5.17638, 19.3185, 0.05, 0.4),
          polygon(0, 20, 4.1411, 15.4548, 0.2, 0.1), polygon(6, 40, 42, 0, 0.2, 0.15)}) {
        INFO(describe(st));
        Walker& k = walker(st);
        const AgainstExact got = againstExact(k, st, stridedPoints(k, st, 600, 800, 32, 11));
        REQUIRE(got.n >= 16);
        CHECK(got.error <= 0.02);
        CHECK(std::fabs(got.drawn - got.exact) <= 0.01);
    }
}

TEST_CASE("walking crowd: several turns' members are drawn over the pixel's cells") {
    // Where the interval turns up to eight times (handing over to the estimate by sixteen), the
    // members that reach a pixel are found by sampling the residual 24 times a turn: each
    // crossing of zero, each dip through zero and back between samples, and each turn back
    // towards zero within reach draws the members about it, and the windows of different
    // turns are laid over one another cell by cell (a third of the pixel's side). Against the
    // exact box mean at 64 strided points: the circles (offset 7.8, spacing 8, a
    // degree a member), and nonagons two a pixel at zoom 0.1, whose residual swings by 90 a
    // member. Estimated past two turns (before), a point was 0.026 and 0.116 off on average
    // (5 and 55 of the 64 points off by more than 8/255); drawn, 0.0021 and 0.025 (0 and 16),
    // the nonagons' ink within 0.001 of the exact 0.334 (5% light with 24 samples a turn,
    // without a polygon's six a facet).
    struct Case {
        Setting st;
        double error, ink;
    };
    Setting circ = circles(1.5);
    for (const Case& c :
         {Case{circ, 0.01, 0.005}, Case{polygon(9, 5, 2.38157, 1.375, 1.0, 0.1), 0.04, 0.01}}) {
        const Setting& st = c.st;
        INFO(describe(st));
        Walker& k = walker(st);
        double errSum = 0, drawnSum = 0, exactSum = 0;
        int off = 0;
        const std::vector<Strided> points = stridedPoints(k, st, 600, 400, 64, 5);
        for (const auto& [x, y, o] : points) {
            const double drawn = drawnInk(k, st, x, y);
            const double exact = exactMean(st, x, y, 1 / st.zoom, static_cast<int64_t>(o.lo), 8);
            SHOW(x, y, o.hi - o.lo + 1, drawn, exact);
            errSum += std::fabs(drawn - exact), drawnSum += drawn, exactSum += exact;
            off += std::fabs(drawn - exact) > 8.0 / 255;
        }
        const int n = static_cast<int>(points.size());
        REQUIRE(n >= 48);
        REPORT(describe(st), ": mean ink drawn ", drawnSum / n, ", exact ", exactSum / n,
               ", mean |error| ", errSum / n, ", points off by > 8/255: ", off, " of ", n);
        CHECK(errSum / n <= c.error);
        CHECK(std::fabs(drawnSum - exactSum) / n <= c.ink);
    }
}

TEST_CASE("walking crowd: a long period's chains that reach the pixel are drawn, pixel by pixel") {
    // Past 72 chains the chains are not all drawn: at the marginal drift a polygon's far members
    // are its facets' lines, and those that reach a pixel stand at two turns, found from the
    // residual over a turn (ChainSelection.h). The triangles (a period of 720) and
    // squares at a quarter degree (1440), at 48 strided points each, against the exact box
    // mean: within 0.1 at every point and 0.02 on average. The estimate these had drew an even
    // grey of the right ink where the exact field has lines a few pixels apart: a point's
    // error was 0.25 on average (measured), which the last check holds it to undo.
    struct Case {
        Setting st;
        double stroke;
    };
    for (const Case& c : {Case{triangles(1.5), 1.5}, Case{triangles(0.5), 0.5},
                          Case{polygon(4, 10, -10, 0, 0.25), 0.3}}) {
        Setting st = c.st;
        st.stroke = c.stroke;
        INFO(describe(st));
        Walker& k = walker(st);
        double errSum = 0, drawnSum = 0, exactSum = 0, evenSum = 0;
        const std::vector<Strided> points = stridedPoints(k, st, 380, 160, 48, 11);
        std::vector<double> exacts;
        for (const auto& [x, y, o] : points) {
            const double drawn = drawnInk(k, st, x, y);
            const double exact = exactMean(st, x, y, 1 / st.zoom, static_cast<int64_t>(o.lo), 16);
            SHOW(x, y, drawn, exact);
            CHECK(std::fabs(drawn - exact) <= 0.1);
            errSum += std::fabs(drawn - exact), drawnSum += drawn, exactSum += exact;
            exacts.push_back(exact);
        }
        const int n = static_cast<int>(points.size());
        REQUIRE(n >= 24);
        // An even grey of the exact mean ink: the best any estimate without the lines can do.
        for (double e : exacts) evenSum += std::fabs(e - exactSum / n);
        REPORT(describe(st), ": mean ink drawn ", drawnSum / n, ", exact ", exactSum / n,
               ", mean |error| ", errSum / n, ", an even grey's ", evenSum / n);
        CHECK(errSum / n <= 0.02);
        CHECK(errSum < 0.25 * evenSum);
    }
}

TEST_CASE("walking crowd: the point filter draws what it drew, and the mean the strided "
          "scan's missing members") {
    // filter = point: the crowd is not estimated; the picture is the solver's own.
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    const std::string body = "layer { family = triangles; spacing = 10; offset = (-10, 0); "
                             "turn = 0.5deg; stroke = 1.5 }\n";
    auto point = test::compileOk("scene { size = (96, 64); filter = point }\n" + body);
    auto mean = test::compileOk("scene { size = (96, 64) }\n" + body);
    CompileOptions asked;
    asked.filter = sema::FilterMode::Point;
    auto option = test::compileOk("scene { size = (96, 64) }\n" + body, asked);
    const Image a = test::renderScene(*point, *interp), b = test::renderScene(*option, *interp);
    CHECK(test::compareImages(a, b, 0.0).maxAbs == 0.0);
    const Image c = test::renderScene(*mean, *interp);
    CHECK(test::compareImages(a, c, 2.0 / 255).fractionWithin() < 0.9);
    double pointInk = 0, meanInk = 0; // 1 - red, black on white
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            pointInk += 1 - a.at(x, y, 0), meanInk += 1 - c.at(x, y, 0);
    CHECK(meanInk > pointInk); // the strided scan's missing members drawn as grey
}

TEST_CASE("walking crowd: within the budget the mean is the exhaustive field's, no crowd drawn") {
    // A benign drift: the scan is exhaustive, the crowd is not engaged, and what the mean filter
    // draws is the pixel's mean of the members found (the nearest member's stroke as written
    // across its normal, docs/filtering.md): within 0.06 of the exact box mean at every point,
    // 0.02 on average. A crowd drawn there would add its even grey between the strokes.
    Setting st;
    st.w.facets = 0, st.w.spacing = 10, st.w.offsetX = 3, st.w.turn = 2 * kDeg;
    st.stroke = 1.5;
    INFO(describe(st));
    Walker& k = walker(st);
    std::mt19937_64 rng(11);
    double drawnSum = 0, exactSum = 0;
    int n = 0;
    for (int i = 0; i < 40; ++i) {
        double x, y;
        inDisc(300, rng, x, y);
        const Out o = solveOn(k, st, x, y);
        REQUIRE(o.hi - o.lo + 1 <= lower::kWalkBudget); // exhaustive
        const double drawn = drawnInk(k, st, x, y);
        const double exact = exactMean(st, x, y, 1.0, static_cast<int64_t>(o.lo), 16);
        SHOW(x, y, drawn, exact);
        CHECK(std::fabs(drawn - exact) <= 0.06);
        drawnSum += drawn, exactSum += exact, ++n;
    }
    CHECK(std::fabs(drawnSum - exactSum) / n <= 0.02);
}

TEST_CASE("walking crowd: the JIT and the GPU draw the crowd the interpreter draws") {
    const std::string scenes[] = {
        "scene { size = (160, 120) }\nlayer { family = triangles; spacing = 10; "
        "offset = (-10, 0); turn = 0.5deg; stroke = 0.2 }\n",
        "scene { size = (160, 120) }\ncamera { zoom = 0.4 }\nlayer { family = circles; "
        "spacing = 8; offset = (7.8, 0); turn = 1deg; stroke = 0.3 }\n",
    };
    for (const std::string& text : scenes) checkBackendsDrawAsInterpreter(text);
    // A few turns' crossings drawn member by member (a quarter of the frame's pixels stride).
    checkBackendsDrawAsInterpreter(
        "scene { size = (160, 120) }\ncamera { zoom = 0.1 }\nlayer { family = ngon; sides = 9; "
        "spacing = 20; offset = (5.17638, 19.3185); turn = 0.05deg; stroke = 1.5 }\n");
    // Several turns' members drawn over the pixel's cells: the circles 400 to 560
    // units from the walk's middle (intervals of 2 to 8 turns), turned under the camera.
    checkBackendsDrawAsInterpreter(
        "scene { size = (160, 120) }\ncamera { center = (480, 200); rotation = 20deg }\n"
        "layer { family = circles; spacing = 8; offset = (7.8, 0); turn = 1deg; stroke = 1.5 }\n");
    // A turn of a short period, drawn chain by chain, each far member's stroke where single
    // precision puts it: at n s ~ 1e5 the residual of the last members is rounded to about
    // 0.05 world units (the pixel is 2.5), so the far lines move by up to 5/255 of ink and
    // their piles of members widen by as much. Measured on the JIT and lavapipe: every pixel
    // within 16/255, 99% within 10/255, a mean difference of 1.2/255.
    checkBackendsDrawAsInterpreter(
        "scene { size = (96, 64) }\ncamera { zoom = 0.4 }\nlayer { family = hexagons; "
        "spacing = 8; offset = (8, 0); turn = 10deg; stroke = 1.5 }\n",
        Bar{12.0 / 255, 0.99, 2.0 / 255});
}

namespace {

// The walking_triangles example's family (examples/walking_triangles.moire): each triangle
// pushed 7.4 along y at a spacing of 8 and turned half a degree, so that on its far side the
// members pile up closer than a pixel while the interval stays within the budget. At a
// stroke of `stroke` (the example's 1.8 merges the piled members into solid ink; a finer one
// leaves the pixel partly inked, where the count of members shows).
Setting piled(double stroke) {
    Setting st;
    st.w.facets = 3, st.w.spacing = 8, st.w.offsetY = 7.4, st.w.turn = 0.5 * kDeg;
    st.stroke = stroke;
    return st;
}

// The members of [lo, hi] whose strokes as written reach into the pixel of side `pixel` at
// (x, y): |h_p(n)| within t/2 plus half the pixel's diagonal (Eq. 24, exhaustively).
int membersInPixel(const Setting& st, double x, double y, double pixel, int64_t lo, int64_t hi) {
    int count = 0;
    for (int64_t n = lo; n <= hi; ++n)
        count += std::fabs(reference::residual(st.w, x, y, n)) < st.stroke / 2 + pixel * 0.71;
    return count;
}

// The pixel's box mean (k x k samples) of the stroke of the one member n alone: what the mean
// filter drew before it counted the members beside the nearest.
double memberMean(const Setting& st, int64_t n, double x, double y, double pixel, int k = 16) {
    int inked = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            const double sx = x + ((i + 0.5) / k - 0.5) * pixel;
            const double sy = y + ((j + 0.5) / k - 0.5) * pixel;
            inked += std::fabs(reference::residual(st.w, sx, sy, n)) < st.stroke / 2;
        }
    return double(inked) / (k * k);
}

} // namespace

TEST_CASE("walking crowd: members closer than a pixel within the budget all count") {
    // Where the scan is exhaustive but several members cross one pixel, the mean filter draws
    // the pixel's mean of their union, not the nearest member's alone: against the exact
    // field's 16 x 16 box mean (the union of every member's stroke as written), within 0.1 at
    // every point and 0.03 on average, where the nearest member alone is off by far more.
    const Setting st = piled(0.3);
    INFO(describe(st));
    Walker& k = walker(st);
    std::mt19937_64 rng(5);
    double drawnErr = 0, nearestErr = 0, worst = 0;
    int n = 0;
    for (int i = 0; i < 400 && n < 24; ++i) {
        double x, y;
        inDisc(500, rng, x, y);
        const Out o = solveOn(k, st, x, y);
        if (o.hi - o.lo + 1 > lower::kWalkBudget / 2) continue; // the crowd's estimate engages
        const auto lo = static_cast<int64_t>(o.lo), hi = static_cast<int64_t>(o.hi);
        if (membersInPixel(st, x, y, 1.0, lo, hi) < 2) continue; // not crowded
        const double drawn = drawnInk(k, st, x, y);
        const double exact = exactMean(st, x, y, 1.0, lo, 16);
        const double alone = memberMean(st, static_cast<int64_t>(o.index + 0.5), x, y, 1.0);
        SHOW(x, y, drawn, exact, alone);
        CHECK(std::fabs(drawn - exact) <= 0.1);
        worst = std::max(worst, std::fabs(drawn - exact));
        drawnErr += std::fabs(drawn - exact), nearestErr += std::fabs(alone - exact), ++n;
    }
    REQUIRE(n >= 12);
    REPORT("crowded exhaustive pixels ", n, ": mean |drawn - exact| ", drawnErr / n, " (worst ",
           worst, "), the nearest member alone ", nearestErr / n);
    CHECK(drawnErr / n <= 0.03);
    CHECK(nearestErr / n >= 2 * drawnErr / n);
}

TEST_CASE("walking crowd: the JIT and the GPU draw the piled members the interpreter draws") {
    // The example's far side, where members pile closer than a pixel within the budget: the
    // union the scan gathers is the same IR on every backend.
    checkBackendsDrawAsInterpreter("scene { size = (160, 120) }\ncamera { center = (0, -200) "
                                   "}\nlayer { family = triangles; spacing = 8; "
                                   "offset = (0, 7.4); turn = 0.5deg; stroke = 1.8 }\n");
}

TEST_CASE("walking crowd: a closed form's members finer than a pixel all count") {
    // The families the solver answers in closed form (§7.5: no offset, a translated circle,
    // a translated polygon no faster than its spacing) find the nearest member alone. Zoomed out
    // until several members share a pixel, the mean filter draws the union of every member
    // within reach (one chain, WalkingChains.cpp, over the square pixel's footprint across the
    // nearest member's normal): against the exact field's 64 x 64 box mean, within 0.05 at every
    // point and 0.01 on average, where the nearest member's stroke alone is off by five times as
    // much or more (measured: 0.0005 to 0.007 on average, 0.026 at worst, against 0.085 to 0.106
    // for the nearest alone). Four families, members 0.4 to 2 pixels apart: a circle slower
    // than its spacing, one faster (its members cross themselves: the chain's two runs), a
    // hexagon and concentric squares.
    struct Case {
        Setting st;
        double zoom;
    };
    auto make = [](int facets, double spacing, double ox, double oy, double stroke) {
        Setting st = polygon(facets, spacing, ox, oy, 0);
        st.stroke = stroke;
        return st;
    };
    for (const Case& c :
         {Case{make(0, 0.7, 0.3, 0.1, 0.1), 1.0}, Case{make(0, 2, 3, 0, 0.5), 0.5},
          Case{make(6, 0.8, 0.3, 0.2, 0.15), 1.0}, Case{make(4, 3, 0, 0, 0.6), 0.2}}) {
        Setting st = c.st;
        st.zoom = c.zoom;
        INFO(describe(st));
        Walker& k = walker(st);
        std::mt19937_64 rng(3);
        double drawnErr = 0, nearestErr = 0, worst = 0, drawnSum = 0, exactSum = 0;
        int n = 0;
        for (int i = 0; i < 24; ++i) {
            double x, y;
            inDisc(250 / st.zoom, rng, x, y);
            const Out o = solveOn(k, st, x, y);
            const double drawn = drawnInk(k, st, x, y);
            const double exact = exactMean(st, x, y, 1 / st.zoom, 0, 64);
            const double alone =
                memberMean(st, static_cast<int64_t>(std::llround(o.index)), x, y, 1 / st.zoom, 8);
            SHOW(x, y, drawn, exact, alone);
            CHECK(std::fabs(drawn - exact) <= 0.05);
            worst = std::max(worst, std::fabs(drawn - exact));
            drawnErr += std::fabs(drawn - exact), nearestErr += std::fabs(alone - exact);
            drawnSum += drawn, exactSum += exact, ++n;
        }
        REPORT(describe(st), ": mean |drawn - exact| ", drawnErr / n, " (worst ", worst,
               "), the nearest member alone ", nearestErr / n, "; ink drawn ", drawnSum / n,
               ", exact ", exactSum / n);
        CHECK(drawnErr / n <= 0.01);
        CHECK(nearestErr / n >= 5 * drawnErr / n);
    }
}

TEST_CASE("walking crowd: the JIT and the GPU draw a closed form's crowd the interpreter draws") {
    // Translated circles and hexagons zoomed out until their members are finer than a pixel:
    // the chain's union is the same IR on every backend.
    checkBackendsDrawAsInterpreter("scene { size = (160, 120) }\nlayer { family = circles; "
                                   "spacing = 0.7; offset = (0.3, 0.1); stroke = 0.1 }\n");
    checkBackendsDrawAsInterpreter("scene { size = (160, 120) }\ncamera { zoom = 0.5 }\nlayer "
                                   "{ family = hexagons; spacing = 1.6; offset = (0.6, 0.4); "
                                   "stroke = 0.3 }\n");
}
