// The builtin lattices (square_lattice, triangle_lattice, hex_lattice) against brute force.
// For each kind, several spacings, stretches (isotropic and strongly anisotropic), rotations
// and origins, with edges = 0 and 1, the renderer's distance (double interpreter) at seeded
// random world points must equal an exhaustive search written here from the lattices'
// geometric description: every lattice point (or every edge segment) within a generous
// window, placed in the world through the layer's stretch, rotation and origin, and the
// least Euclidean distance to any of them. The index pair must be the brute-force nearest
// point's. The renderer rounds in the stretched basis and then picks the world-nearest of a
// few candidates around the rounded point (see compiler/lower/LatticeFamily.cpp), so the
// vertex distance is exact under any stretch, not just an isotropic one; the tests also
// count the points where plain rounding would have chosen another point, to show the
// anisotropic settings reach that case. MOIRE_LATTICES_REPORT=1 prints the measured figures.
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <doctest/doctest.h>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSqrt3 = std::numbers::sqrt3;
constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Kind { Square, Triangle, Hex };

const char* familyName(Kind k) {
    switch (k) {
    case Kind::Square:
        return "square_lattice";
    case Kind::Triangle:
        return "triangle_lattice";
    case Kind::Hex:
        return "hex_lattice";
    }
    return "";
}

struct Setting {
    double spacing, sx, sy;
    double rotationDeg, ox, oy;
    int edges;
};

std::string layerText(Kind kind, const Setting& s) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "layer { family = %s; spacing = %.17g; scale = (%.17g, %.17g); edges = %d; "
                  "rotation = %.17gdeg; origin = (%.17g, %.17g) }\n",
                  familyName(kind), s.spacing, s.sx, s.sy, s.edges, s.rotationDeg, s.ox, s.oy);
    return buf;
}

struct V2 {
    double x, y;
};

// The layer's frame (before the stretch) to the world: stretch, turn, move.
V2 toWorld(const Setting& s, V2 q) {
    double x = q.x * s.sx, y = q.y * s.sy;
    double c = std::cos(s.rotationDeg * kPi / 180.0), sn = std::sin(s.rotationDeg * kPi / 180.0);
    return {s.ox + c * x - sn * y, s.oy + sn * x + c * y};
}
V2 fromWorld(const Setting& s, V2 w) {
    double c = std::cos(s.rotationDeg * kPi / 180.0), sn = std::sin(s.rotationDeg * kPi / 180.0);
    double dx = w.x - s.ox, dy = w.y - s.oy;
    return {(c * dx + sn * dy) / s.sx, (-sn * dx + c * dy) / s.sy};
}

double dist(V2 a, V2 b) {
    return std::hypot(a.x - b.x, a.y - b.y);
}
double segmentDistance(V2 p, V2 a, V2 b) {
    double ex = b.x - a.x, ey = b.y - a.y;
    double t = ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey);
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.x - a.x - t * ex, p.y - a.y - t * ey);
}

// A lattice point (unstretched layer frame) with its integer pair, and an edge segment.
struct Site {
    V2 at;
    int i, j;
};
struct Segment {
    V2 a, b;
};

// The geometry near the unstretched point u, from the lattices' description: a window of
// +-k cells around a rough cell estimate, large enough that the world-nearest point and
// edge are always inside it (k grows with the stretch's aspect ratio, since a world
// disc becomes a long ellipse in the unstretched frame).
//  square:   points s (i, j); edges join each point to its right and upper neighbours.
//  triangle: points s (i + j/2, j sqrt3/2); edges join each point to its neighbours at
//            +a1, +a2 and +a2 - a1.
//  hex:      hexagons of side s, centred on an A2 lattice of pitch s sqrt3 (first basis
//            vector along x), corners at s (cos, sin)(30 + 60k deg); the points are the
//            corners, labelled by their coordinates in the basis l1 = s (cos 30, sin 30),
//            l2 = s (0, 1); the edges are the six sides of every hexagon.
void geometry(Kind kind, double s, V2 u, int k, std::vector<Site>& sites,
              std::vector<Segment>& segments) {
    sites.clear();
    segments.clear();
    if (kind == Kind::Square) {
        int i0 = int(std::floor(u.x / s)), j0 = int(std::floor(u.y / s));
        for (int i = i0 - k; i <= i0 + k; ++i)
            for (int j = j0 - k; j <= j0 + k; ++j) {
                V2 p{s * i, s * j};
                sites.push_back({p, i, j});
                segments.push_back({p, {p.x + s, p.y}});
                segments.push_back({p, {p.x, p.y + s}});
            }
        return;
    }
    double pitch = kind == Kind::Hex ? s * kSqrt3 : s;
    int j0 = int(std::floor(u.y / (pitch * kSqrt3 / 2)));
    int i0 = int(std::floor(u.x / pitch - j0 / 2.0));
    for (int i = i0 - k; i <= i0 + k; ++i)
        for (int j = j0 - k; j <= j0 + k; ++j) {
            V2 p{pitch * (i + j / 2.0), pitch * j * kSqrt3 / 2};
            if (kind == Kind::Triangle) {
                sites.push_back({p, i, j});
                segments.push_back({p, {p.x + s, p.y}});
                segments.push_back({p, {p.x + s / 2, p.y + s * kSqrt3 / 2}});
                segments.push_back({p, {p.x - s / 2, p.y + s * kSqrt3 / 2}});
                continue;
            }
            V2 corner[6];
            for (int c = 0; c < 6; ++c) {
                double a = (30.0 + 60.0 * c) * kPi / 180.0;
                corner[c] = {p.x + s * std::cos(a), p.y + s * std::sin(a)};
                double m = corner[c].x / (s * kSqrt3 / 2);
                double n = corner[c].y / s - m / 2;
                sites.push_back({corner[c], int(std::lround(m)), int(std::lround(n))});
            }
            for (int c = 0; c < 6; ++c) segments.push_back({corner[c], corner[(c + 1) % 6]});
        }
}

// What the brute force finds at a world point for one layer.
struct Truth {
    double vertex = kInf, edge = kInf;
    double second = kInf;         // the runner-up point's distance (ties make the index moot)
    int i = 0, j = 0;             // the world-nearest point's pair
    bool roundingDiffers = false; // the point nearest in the unstretched frame is another one
};

Truth bruteForce(Kind kind, const Setting& st, V2 world) {
    V2 u = fromWorld(st, world);
    double aspect = std::max(st.sx, st.sy) / std::min(st.sx, st.sy);
    int k = int(std::ceil(2.0 * aspect)) + 3;
    static std::vector<Site> sites;
    static std::vector<Segment> segments;
    geometry(kind, st.spacing, u, k, sites, segments);
    Truth t;
    double nearestUnit = kInf;
    int ui = 0, uj = 0;
    for (const Site& site : sites) {
        double d = dist(world, toWorld(st, site.at));
        if (d < t.vertex) {
            t.vertex = d;
            t.i = site.i;
            t.j = site.j;
        }
        double du = dist(u, site.at);
        if (du < nearestUnit) {
            nearestUnit = du;
            ui = site.i;
            uj = site.j;
        }
    }
    // (A honeycomb corner is listed once per hexagon around it: skip its copies.)
    for (const Site& site : sites)
        if (site.i != t.i || site.j != t.j)
            t.second = std::min(t.second, dist(world, toWorld(st, site.at)));
    t.roundingDiffers = ui != t.i || uj != t.j;
    for (const Segment& e : segments)
        t.edge = std::min(t.edge, segmentDistance(world, toWorld(st, e.a), toWorld(st, e.b)));
    return t;
}

std::vector<Setting> settings() {
    std::vector<Setting> out;
    for (double spacing : {7.0, 12.5})
        for (auto [sx, sy] : {std::pair{1.0, 1.0}, {1.0, 2.5}, {0.4, 1.0}, {3.0, 0.5}})
            for (auto [rot, ox, oy] : {std::tuple{0.0, 0.0, 0.0}, {23.0, 3.5, -6.0}})
                for (int edges : {0, 1}) out.push_back({spacing, sx, sy, rot, ox, oy, edges});
    return out;
}

std::vector<V2> worldPoints(int n, double half, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-half, half);
    std::vector<V2> out;
    for (int i = 0; i < n; ++i) {
        double x = u(rng), y = u(rng);
        out.push_back({x, y});
    }
    return out;
}

void checkAgainstBruteForce(Kind kind, uint64_t seed) {
    const std::vector<Setting> all = settings();
    std::string scene;
    for (const Setting& st : all) scene += layerText(kind, st);
    auto program =
        test::compileOk(scene, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    const auto& layout = program->layout;

    double worstVertex = 0.0, worstEdge = 0.0; // over the spacing
    int indexChecked = 0, roundingWouldMiss = 0;
    for (V2 w : worldPoints(250, 60.0, seed)) {
        std::vector<double> out = probe.at(w.x, w.y);
        for (size_t l = 0; l < all.size(); ++l) {
            const Setting& st = all[l];
            Truth t = bruteForce(kind, st, w);
            double d = out[layout.distanceSlot(int(l))];
            CAPTURE(layerText(kind, st));
            CAPTURE(w.x);
            CAPTURE(w.y);
            double err = std::fabs(d - (st.edges ? t.edge : t.vertex)) / st.spacing;
            (st.edges ? worstEdge : worstVertex) =
                std::max(st.edges ? worstEdge : worstVertex, err);
            CHECK(err < 1e-10);
            // The index is the nearest point's pair with either distance, unless two points
            // are (all but) equally near.
            if (t.second - t.vertex > 1e-9 * st.spacing) {
                ++indexChecked;
                CHECK(out[layout.indexSlot(int(l))] == t.i);
                CHECK(out[layout.aux0Slot(int(l))] == t.j);
            }
            if (t.roundingDiffers && !st.edges) ++roundingWouldMiss;
        }
    }
    if (std::getenv("MOIRE_LATTICES_REPORT"))
        std::printf("%s: worst |error| / spacing: points %.3g, edges %.3g; index pairs checked "
                    "%d; point-layer samples where rounding alone would miss %d\n",
                    familyName(kind), worstVertex, worstEdge, indexChecked, roundingWouldMiss);
    CHECK(worstVertex < 1e-10);
    CHECK(worstEdge < 1e-10);
    CHECK(indexChecked > 250 * int(all.size()) * 9 / 10);
    // The stretched settings do reach the points where the nearest point in the unstretched
    // frame (what rounding alone returns) is not the nearest in the world; the square
    // lattice, a rectangle when stretched, has none.
    if (kind == Kind::Square)
        CHECK(roundingWouldMiss == 0);
    else
        CHECK(roundingWouldMiss > 100);
}

} // namespace

TEST_CASE("lattices: square_lattice's points and edges are the brute-force nearest") {
    checkAgainstBruteForce(Kind::Square, 101);
}

TEST_CASE("lattices: triangle_lattice's points and edges are the brute-force nearest") {
    checkAgainstBruteForce(Kind::Triangle, 202);
}

TEST_CASE("lattices: hex_lattice's corners and sides are the brute-force nearest") {
    checkAgainstBruteForce(Kind::Hex, 303);
}

TEST_CASE("lattices: edges, spacing and scale are run-time values, and t can switch edges") {
    // `edges` is a select in the kernel, not a branch of the compiler, so changing it (or
    // the spacing, or the stretch) changes numbers only: the kernel's structure is the same.
    for (Kind kind : {Kind::Square, Kind::Triangle, Kind::Hex}) {
        CAPTURE(familyName(kind));
        auto a = test::compileOk(layerText(kind, {7, 1, 1, 0, 0, 0, 0}));
        auto b = test::compileOk(layerText(kind, {9, 1.5, 0.5, 10, 1, 2, 1}));
        CHECK(a->kernelHash == b->kernelHash);
        // (The hash does see structure: another kind of lattice is another kernel.)
        Kind other = kind == Kind::Hex ? Kind::Square : Kind::Hex;
        CHECK(test::compileOk(layerText(other, {7, 1, 1, 0, 0, 0, 0}))->kernelHash !=
              a->kernelHash);
    }
    // A clock-driven `edges` draws the points at t = 0 and the edges at t = 1, exactly as
    // the constant settings do.
    Setting st{8, 1, 1.7, 12, 2, -1, 0};
    std::string timed = "layer { family = hex_lattice; spacing = 8; scale = (1, 1.7); edges = t; "
                        "rotation = 12deg; origin = (2, -1) }\n";
    Setting edgesOn = st;
    edgesOn.edges = 1;
    auto program = test::compileOk(timed + layerText(Kind::Hex, st) + layerText(Kind::Hex, edgesOn),
                                   {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    const auto& layout = program->layout;
    int differ = 0;
    for (V2 w : worldPoints(60, 40.0, 404)) {
        std::vector<double> at0 = probe.at(w.x, w.y, 0.0), at1 = probe.at(w.x, w.y, 1.0);
        CHECK(at0[layout.distanceSlot(0)] == at0[layout.distanceSlot(1)]);
        CHECK(at1[layout.distanceSlot(0)] == at1[layout.distanceSlot(2)]);
        differ += at0[layout.distanceSlot(0)] != at1[layout.distanceSlot(0)];
    }
    CHECK(differ > 50); // points and edges are different fields
}

TEST_CASE("lattices: the JIT's fields agree with the exact interpreter's to single precision") {
    auto jit = test::makeBackendOrSkip("jit");
    if (!jit) return;
    const std::vector<Setting> some = {
        {7, 1, 1, 0, 0, 0, 0},          {7, 1, 1, 0, 0, 0, 1},      {12.5, 1, 2.5, 23, 3.5, -6, 0},
        {12.5, 1, 2.5, 23, 3.5, -6, 1}, {9, 3, 0.5, -40, -2, 5, 0}, {9, 3, 0.5, -40, -2, 5, 1}};
    for (Kind kind : {Kind::Square, Kind::Triangle, Kind::Hex}) {
        CAPTURE(familyName(kind));
        std::string scene;
        for (const Setting& st : some) scene += layerText(kind, st);
        auto program =
            test::compileOk(scene, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
        Prober exact(*program, nullptr), single(*program, jit.get());
        const auto& layout = program->layout;
        double worst = 0.0;
        int indexChecked = 0;
        for (V2 w : worldPoints(80, 60.0, 505)) {
            std::vector<double> a = exact.at(w.x, w.y), b = single.at(w.x, w.y);
            for (size_t l = 0; l < some.size(); ++l) {
                CAPTURE(layerText(kind, some[l]));
                CAPTURE(w.x);
                CAPTURE(w.y);
                int slot = layout.distanceSlot(int(l));
                // The kernel runs in float on points up to ~85 units from the origin: the
                // point itself carries ~5e-6 of rounding, and the lattice arithmetic a few
                // ulps more. 1e-4 is a generous margin over that, and far below a stroke.
                double err = std::fabs(a[slot] - b[slot]);
                worst = std::max(worst, err);
                CHECK(err < 1e-4);
                // Floats may pick the other of two (nearly) equidistant points.
                Truth t = bruteForce(kind, some[l], w);
                if (t.second - t.vertex > 1e-3) {
                    ++indexChecked;
                    CHECK(b[layout.indexSlot(int(l))] == a[layout.indexSlot(int(l))]);
                    CHECK(b[layout.aux0Slot(int(l))] == a[layout.aux0Slot(int(l))]);
                }
            }
        }
        if (std::getenv("MOIRE_LATTICES_REPORT"))
            std::printf("%s: JIT vs interpreter, worst |distance difference| %.3g\n",
                        familyName(kind), worst);
        CHECK(indexChecked > 400);
    }
}

TEST_CASE("lattices: a negative spacing or scale draws the same lattice") {
    // All three point sets (and edge sets) are symmetric under x -> -x and y -> -y, so the
    // sign of the spacing or of a scale changes nothing drawn; without the magnitudes the
    // hexagon's apothem and the per-facet norms would turn negative.
    for (Kind kind : {Kind::Square, Kind::Triangle, Kind::Hex}) {
        for (int edges : {0, 1}) {
            Setting plain{7, 1, 2, 10, 1, -2, edges}, mirrored{-7, -1, 2, 10, 1, -2, edges},
                flipped{7, 1, -2, 10, 1, -2, edges};
            auto program = test::compileOk(
                layerText(kind, plain) + layerText(kind, mirrored) + layerText(kind, flipped),
                {.mode = CompileOptions::Mode::Probe, .layerFields = true});
            Prober probe(*program, nullptr);
            const auto& layout = program->layout;
            CAPTURE(familyName(kind));
            CAPTURE(edges);
            for (V2 w : worldPoints(60, 40.0, 606)) {
                std::vector<double> out = probe.at(w.x, w.y);
                double d = out[layout.distanceSlot(0)];
                CHECK(out[layout.distanceSlot(1)] == doctest::Approx(d).epsilon(1e-12));
                CHECK(out[layout.distanceSlot(2)] == doctest::Approx(d).epsilon(1e-12));
            }
        }
    }
}
