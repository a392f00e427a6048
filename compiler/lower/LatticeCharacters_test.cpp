// Lattice layers in the character search (spec §3.6, §4.1: a lattice's index is a pair, and
// the characters range over integer combinations of its generators), against independent
// expectations: the generators' AD gradients against central differences, their values at
// the lattice's own points, and the search's winner against a brute force over lattice
// harmonics written here as plain loops, on the interpreter and the JIT (the small kernels on
// every backend that runs here).
#include "compiler/lower/Characters.h"
#include "compiler/lower/KernelProbe_test.h"
#include "compiler/lower/LatticeFamily.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>

using namespace moire;

namespace {

constexpr double kDeg = std::numbers::pi / 180;
constexpr double kSqrt3 = std::numbers::sqrt3;

// A kernel whose inputs are the world point (uniforms 0 and 1, marked as AD's independent
// variables), its derivative markers resolved by the AD pass.
class DerivedProbe {
  public:
    using Body = std::function<void(ir::Builder&, ir::ValueId x, ir::ValueId y)>;
    DerivedProbe(int numOutputs, const Body& body)
        : probe_(
              numOutputs,
              [&](ir::Builder& b) {
                  body(b, b.emit(ir::Op::Indep, {b.uniform(0)}, 0.0, 0),
                       b.emit(ir::Op::Indep, {b.uniform(1)}, 0.0, 1));
              },
              true) {}
    bool use(const std::string& backend) { return probe_.use(backend); }
    std::vector<double> run(double x, double y) const { return probe_.run({x, y}); }

  private:
    test::KernelProbe probe_;
};

// A lattice layer as the lowering frames one: p - origin turned by -turn(p), where the turn
// may vary across the frame (turnRate per world unit along x), so AD has a frame to carry.
struct LatticeLayer {
    lower::LatticeKind kind;
    double spacing, sx, sy, turn, turnRate = 0.0, ox = 0.0, oy = 0.0;
};

lower::LayerFields latticeLayer(ir::Builder& b, ir::ValueId x, ir::ValueId y,
                                const LatticeLayer& l) {
    ir::ValueId dx = b.sub(x, b.constF(l.ox)), dy = b.sub(y, b.constF(l.oy));
    ir::ValueId turn = b.add(b.constF(l.turn), b.mul(x, b.constF(l.turnRate)));
    ir::ValueId c = b.emit(ir::Op::Cos, {turn}), s = b.emit(ir::Op::Sin, {turn});
    lower::LatticeInputs in;
    in.px = b.add(b.mul(c, dx), b.mul(s, dy)); // Rot(-turn) (dx, dy)
    in.py = b.sub(b.mul(c, dy), b.mul(s, dx));
    in.spacing = b.constF(l.spacing);
    in.scale = {b.constF(l.sx), b.constF(l.sy)};
    in.edges = b.constF(0.0);
    return lower::latticeFields(b, l.kind, in);
}

// A line family idx = <p, n> / pitch, n at `angle`, its gradient from AD.
lower::LayerFields lineLayer(ir::Builder& b, ir::ValueId x, ir::ValueId y, double pitch,
                             double angle) {
    lower::LayerFields f;
    f.index = b.div(b.add(b.mul(x, b.constF(std::cos(angle))), b.mul(y, b.constF(std::sin(angle)))),
                    b.constF(pitch));
    f.distance = b.constF(0.0);
    f.gradX = b.emit(ir::Op::DerivX, {f.index});
    f.gradY = b.emit(ir::Op::DerivY, {f.index});
    return f;
}

// ---- The oracle: lattice harmonics by hand, and a brute force over them ----

struct V2 {
    double x, y;
};
V2 operator+(V2 a, V2 b) {
    return {a.x + b.x, a.y + b.y};
}
V2 operator-(V2 a, V2 b) {
    return {a.x - b.x, a.y - b.y};
}
V2 operator*(double k, V2 a) {
    return {k * a.x, k * a.y};
}
double norm(V2 a) {
    return std::hypot(a.x, a.y);
}
V2 turned(V2 a, double t) {
    return {a.x * std::cos(t) - a.y * std::sin(t), a.x * std::sin(t) + a.y * std::cos(t)};
}

// A layer's generators' gradients, per world unit, from its basis: the reciprocal basis of
// the lattice the pattern repeats by (for the honeycomb, its centres'), stretched by S^-1
// and turned by the layer's (constant) turn. A line family has one generator.
struct Generators {
    V2 g[2];
    int count;
};
Generators generatorsOf(const LatticeLayer& l) {
    const double pitch = l.kind == lower::LatticeKind::Hex ? l.spacing * kSqrt3 : l.spacing;
    V2 gu{1 / pitch, 0}, gv{0, 1 / pitch};
    if (l.kind != lower::LatticeKind::Square) { // basis (1, 0), (1/2, sqrt3/2): reciprocal
        gu = {1 / pitch, -1 / (kSqrt3 * pitch)};
        gv = {0, 2 / (kSqrt3 * pitch)};
    }
    auto frame = [&](V2 g) { return turned(V2{g.x / l.sx, g.y / l.sy}, l.turn); };
    return {{frame(gu), frame(gv)}, 2};
}
Generators lineGenerators(double pitch, double angle) {
    return {{{std::cos(angle) / pitch, std::sin(angle) / pitch}, {0, 0}}, 1};
}

// A character of two layers: the integer harmonic h of each on its generators.
struct Harmonics {
    int a[2], b[2]; // layer 0's (a0, a1), layer 1's (b0, b1)
};
V2 carrier(const Generators& g, const int* h) {
    return g.count == 1 ? double(h[0]) * g.g[0] : double(h[0]) * g.g[0] + double(h[1]) * g.g[1];
}
// The price of a harmonic h of a lattice: its order max(|h0|, |h1|), the lattice's reading of
// Eq. 12's 1 / m (the m-th harmonic of a one-index family, (m, 0), costs m; so does the m-th
// of a diagonal row, (m, m)). Over every harmonic, not only the rows the search scans.
int harmonicOrder(const int* h) {
    return std::max(std::abs(h[0]), std::abs(h[1]));
}
// Eq. 11-12 restated: the beat cA + cB against half of cA - cB, floored at 1e-3 (kEtaFloor).
double oracleMerit(const Generators& A, const Generators& B, const Harmonics& k) {
    const V2 ca = carrier(A, k.a), cb = carrier(B, k.b);
    const double eta = norm(ca + cb) / (0.5 * norm(ca - cb));
    return harmonicOrder(k.a) * harmonicOrder(k.b) * std::max(eta, 1e-3);
}
// Every harmonic pair with coefficients in [-n, n] that involves both layers.
struct OracleBest {
    double mu;
    Harmonics k;
};
OracleBest bruteForce(const Generators& A, const Generators& B, int n) {
    OracleBest best{INFINITY, {}};
    const int a1n = A.count == 2 ? n : 0, b1n = B.count == 2 ? n : 0;
    for (int a0 = -n; a0 <= n; ++a0)
        for (int a1 = -a1n; a1 <= a1n; ++a1)
            for (int b0 = -n; b0 <= n; ++b0)
                for (int b1 = -b1n; b1 <= b1n; ++b1) {
                    if ((a0 == 0 && a1 == 0) || (b0 == 0 && b1 == 0)) continue;
                    Harmonics k{{a0, a1}, {b0, b1}};
                    const double mu = oracleMerit(A, B, k);
                    if (mu < best.mu) best = {mu, k};
                }
    return best;
}

// The searched winner of a stack (up to three layers), at the point kAt: outputs 0 mu, then
// each slot's coefficients on its generators (characterGenerators; zero past the stack),
// then the winner's combination and its gradient (characterCombination).
constexpr double kAtX = 37.3, kAtY = -12.9;
std::vector<double> searched(DerivedProbe& probe) {
    return probe.run(kAtX, kAtY);
}
DerivedProbe stackProbe(
    const std::function<std::vector<lower::LayerFields>(ir::Builder&, ir::ValueId, ir::ValueId)>&
        layers) {
    return DerivedProbe(10, [=](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
        std::vector<lower::LayerFields> fields = layers(b, x, y);
        lower::Character c = lower::stackCharacter(b, fields);
        b.output(0, c.mu);
        for (int i = 0; i < 3; ++i) {
            auto [ku, kv] = i < c.count ? lower::characterGenerators(b, c, i)
                                        : std::array{b.constF(0.0), b.constF(0.0)};
            b.output(1 + 2 * i, ku);
            b.output(2 + 2 * i, kv);
        }
        lower::Combination comb = lower::characterCombination(b, c, fields);
        b.output(7, comb.value);
        b.output(8, comb.gradX);
        b.output(9, comb.gradY);
    });
}
// The generators' values at p, from the basis (the layer's origin at 0).
std::array<double, 2> generatorValues(const LatticeLayer& l, V2 p) {
    const V2 q = turned(p, -l.turn);
    const double x = q.x / l.sx, y = q.y / l.sy;
    const double pitch = l.kind == lower::LatticeKind::Hex ? l.spacing * kSqrt3 : l.spacing;
    if (l.kind == lower::LatticeKind::Square) return {x / pitch, y / pitch};
    const double v = y * 2 / (kSqrt3 * pitch);
    return {x / pitch - v / 2, v};
}
Harmonics namedHarmonics(const std::vector<double>& out) { // of a two-layer stack
    return {{int(std::lround(out[1])), int(std::lround(out[2]))},
            {int(std::lround(out[3])), int(std::lround(out[4]))}};
}
bool sameCharacter(const Harmonics& p, const Harmonics& q) { // k and -k are one character
    for (int s : {1, -1})
        if (p.a[0] == s * q.a[0] && p.a[1] == s * q.a[1] && p.b[0] == s * q.b[0] &&
            p.b[1] == s * q.b[1])
            return true;
    return false;
}

// Outputs come back as float: the interpreter's are rounded once, the JIT's computed in float.
double tolerance(const std::string& backend) {
    return backend == "interp" ? 1e-5 : 1e-4;
}

// The character kernels of lattice stacks are large (16 pair searches for two lattices), and
// a software Vulkan takes seconds per compile; the search is the same IR everywhere, and the
// interpreter and the JIT hold it to the oracle. The small kernels run on every backend.
const std::vector<std::string>& searchBackends() {
    static const std::vector<std::string> names = {"interp", "jit"};
    return names;
}

} // namespace

TEST_CASE("lattice characters: the generators' AD gradients match central differences") {
    // The differences are taken inside the kernel, which the interpreter runs in double, so
    // that only the outputs are rounded to float; the layers' turn varies along x, so AD has
    // the whole frame to carry, not only the basis.
    const LatticeLayer layers[] = {
        {lower::LatticeKind::Square, 9, 1, 1, 10 * kDeg, 0.003, 4, -2},
        {lower::LatticeKind::Triangle, 10, 1.7, 0.6, -25 * kDeg, -0.002, -3, 5},
        {lower::LatticeKind::Hex, 8, 1, 1.7, 40 * kDeg, 0.001, 0, 0},
    };
    const double h = 1e-3;
    for (const LatticeLayer& l : layers) {
        DerivedProbe probe(8, [&](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
            lower::LayerFields f = latticeLayer(b, x, y, l);
            const ir::ValueId ad[] = {f.genUX, f.genUY, f.genVX, f.genVY};
            for (int i = 0; i < 4; ++i) b.output(i, ad[i]);
            auto at = [&](double dx, double dy) {
                return latticeLayer(b, b.add(x, b.constF(dx)), b.add(y, b.constF(dy)), l);
            };
            lower::LayerFields xp = at(h, 0), xm = at(-h, 0), yp = at(0, h), ym = at(0, -h);
            auto central = [&](ir::ValueId plus, ir::ValueId minus) {
                return b.div(b.sub(plus, minus), b.constF(2 * h));
            };
            b.output(4, central(xp.genU, xm.genU));
            b.output(5, central(yp.genU, ym.genU));
            b.output(6, central(xp.genV, xm.genV));
            b.output(7, central(yp.genV, ym.genV));
        });
        if (!probe.use("interp")) return;
        for (auto [x, y] : {std::pair{3.1, -7.4}, {-41.7, 22.9}, {120.3, 88.8}}) {
            CAPTURE(int(l.kind));
            CAPTURE(x);
            CAPTURE(y);
            const std::vector<double> out = probe.run(x, y);
            for (int i = 0; i < 4; ++i) {
                CAPTURE(i);
                CHECK(std::abs(out[size_t(i)]) > 1e-3); // no generator is flat here
                CHECK(out[size_t(i)] == doctest::Approx(out[size_t(4 + i)]).epsilon(1e-5));
            }
        }
    }
}

TEST_CASE("lattice characters: the generators are the integer pair at the lattice's points") {
    // At the point i a1 + j a2 of the basis the pattern repeats by (stretched, turned and
    // moved as the layer is), the generators read exactly (i, j).
    const LatticeLayer layers[] = {
        {lower::LatticeKind::Square, 9, 1.3, 0.8, 20 * kDeg, 0, 4, -2},
        {lower::LatticeKind::Triangle, 10, 1.7, 0.6, -25 * kDeg, 0, -3, 5},
        {lower::LatticeKind::Hex, 8, 1, 1.7, 40 * kDeg, 0, 1, 1},
    };
    for (const LatticeLayer& l : layers) {
        DerivedProbe probe(2, [&](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
            lower::LayerFields f = latticeLayer(b, x, y, l);
            b.output(0, f.genU);
            b.output(1, f.genV);
        });
        const double pitch = l.kind == lower::LatticeKind::Hex ? l.spacing * kSqrt3 : l.spacing;
        const V2 a1{pitch, 0};
        const V2 a2 =
            l.kind == lower::LatticeKind::Square ? V2{0, pitch} : V2{pitch / 2, pitch * kSqrt3 / 2};
        for (const std::string& backend : test::probeBackends()) {
            if (!probe.use(backend)) continue;
            for (auto [i, j] : {std::pair{0, 0}, {3, -2}, {-5, 7}}) {
                const V2 q = double(i) * a1 + double(j) * a2;
                const V2 p = turned(V2{q.x * l.sx, q.y * l.sy}, l.turn) + V2{l.ox, l.oy};
                const std::vector<double> out = probe.run(p.x, p.y);
                CAPTURE(backend);
                CAPTURE(int(l.kind));
                CHECK(out[0] == doctest::Approx(i).epsilon(1e-4));
                CHECK(out[1] == doctest::Approx(j).epsilon(1e-4));
            }
        }
    }
}

TEST_CASE("lattice characters: a square lattice turned against itself beats at its own rows") {
    // Two square lattices of one spacing, 3 degrees apart: every row beats with its turned
    // copy at eta = 2 tan(1.5 deg), order one. The search must reach the brute force's least
    // merit, and the character it names must have that merit by the brute force's reckoning.
    const LatticeLayer A{lower::LatticeKind::Square, 10, 1, 1, 0};
    const LatticeLayer B{lower::LatticeKind::Square, 10, 1, 1, 3 * kDeg};
    DerivedProbe probe = stackProbe([&](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
        return std::vector<lower::LayerFields>{latticeLayer(b, x, y, A), latticeLayer(b, x, y, B)};
    });
    const Generators gA = generatorsOf(A), gB = generatorsOf(B);
    const OracleBest want = bruteForce(gA, gB, 4);
    CHECK(want.mu == doctest::Approx(2 * std::tan(1.5 * kDeg)).epsilon(1e-9));
    for (const std::string& backend : searchBackends()) {
        if (!probe.use(backend)) continue;
        CAPTURE(backend);
        const std::vector<double> out = searched(probe);
        CHECK(out[0] == doctest::Approx(want.mu).epsilon(tolerance(backend)));
        CHECK(oracleMerit(gA, gB, namedHarmonics(out)) ==
              doctest::Approx(want.mu).epsilon(tolerance(backend)));
    }
}

TEST_CASE("lattice characters: a lattice against line families names the row they beat with") {
    // Each case has one slowest character, which the brute force over every harmonic of the
    // lattice finds; the search must name the same one (up to sign) at the same merit.
    struct Case {
        const char* what;
        LatticeLayer lattice;
        double pitch, angle; // the line family
    };
    const Case cases[] = {
        // The diagonal row u + v (pitch 10 / sqrt2, normal at 45 degrees) against lines 2%
        // coarser, a degree off it: (1, 1) on the lattice, -1 on the lines.
        {"square, diagonal row",
         {lower::LatticeKind::Square, 10, 1, 1, 0},
         1.02 * 10 / std::sqrt(2),
         46 * kDeg},
        // Lines at about half the pitch along the first generator: the second harmonic of the
        // row u, (2, 0) against -1.
        {"square, 2:1", {lower::LatticeKind::Square, 10, 1, 1, 2 * kDeg}, 10 / 2.03, 3 * kDeg},
        // The A2 lattice's third row u + v (normal at 30 degrees, pitch s sqrt3 / 2).
        {"triangle, third row",
         {lower::LatticeKind::Triangle, 10, 1, 1, 0},
         0.98 * 10 * kSqrt3 / 2,
         31 * kDeg},
        // The honeycomb repeats by its centres (pitch s sqrt3): lines beating with their rows.
        {"hex, centres' row",
         {lower::LatticeKind::Hex, 6, 1, 1, 5 * kDeg},
         1.03 * 6 * 1.5,
         94 * kDeg},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        DerivedProbe probe = stackProbe([&](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
            return std::vector<lower::LayerFields>{latticeLayer(b, x, y, c.lattice),
                                                   lineLayer(b, x, y, c.pitch, c.angle)};
        });
        const Generators gA = generatorsOf(c.lattice), gB = lineGenerators(c.pitch, c.angle);
        const OracleBest want = bruteForce(gA, gB, 6);
        CHECK(want.mu <= lower::kFringeMerit); // each case is a fringe
        for (const std::string& backend : searchBackends()) {
            if (!probe.use(backend)) continue;
            CAPTURE(backend);
            const std::vector<double> out = searched(probe);
            const Harmonics got = namedHarmonics(out);
            CAPTURE(got.a[0]);
            CAPTURE(got.a[1]);
            CAPTURE(got.b[0]);
            CAPTURE(want.k.a[0]);
            CAPTURE(want.k.a[1]);
            CAPTURE(want.k.b[0]);
            CHECK(out[0] == doctest::Approx(want.mu).epsilon(tolerance(backend)));
            CHECK(sameCharacter(got, want.k));
            // The overlay's field: the named combination of the generators and the index,
            // and its gradient, by hand.
            const std::array<double, 2> uv = generatorValues(c.lattice, {kAtX, kAtY});
            const double idx = (kAtX * std::cos(c.angle) + kAtY * std::sin(c.angle)) / c.pitch;
            const V2 grad = carrier(gA, got.a) + carrier(gB, got.b);
            const double value = got.a[0] * uv[0] + got.a[1] * uv[1] + got.b[0] * idx;
            CHECK(out[7] == doctest::Approx(value).epsilon(tolerance(backend)));
            CHECK(out[8] == doctest::Approx(grad.x).epsilon(tolerance(backend)));
            CHECK(out[9] == doctest::Approx(grad.y).epsilon(tolerance(backend)));
        }
    }
}

TEST_CASE("lattice characters: in a stack of three, the lattice's slot and row are reported") {
    // Bottom to top: lines beating with the square lattice's diagonal row, lines far from
    // everything, the lattice on top. The winner is the bottom pair's (the brute force over
    // each pair says so), with nothing on the middle layer.
    const LatticeLayer lattice{lower::LatticeKind::Square, 10, 1, 1, 0};
    const double pitch = 1.02 * 10 / std::sqrt(2), angle = 46 * kDeg;
    const double farPitch = 3.1, farAngle = 71 * kDeg;
    DerivedProbe probe = stackProbe([&](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
        return std::vector<lower::LayerFields>{lineLayer(b, x, y, pitch, angle),
                                               lineLayer(b, x, y, farPitch, farAngle),
                                               latticeLayer(b, x, y, lattice)};
    });
    const Generators gL = generatorsOf(lattice), gNear = lineGenerators(pitch, angle),
                     gFar = lineGenerators(farPitch, farAngle);
    const OracleBest want = bruteForce(gL, gNear, 6);
    CHECK(bruteForce(gL, gFar, 6).mu > 2 * want.mu);
    CHECK(bruteForce(gNear, gFar, 6).mu > 2 * want.mu);
    for (const std::string& backend : searchBackends()) {
        if (!probe.use(backend)) continue;
        CAPTURE(backend);
        const std::vector<double> out = searched(probe);
        CHECK(out[0] == doctest::Approx(want.mu).epsilon(tolerance(backend)));
        // Slot 0 the bottom lines, slot 1 the far lines, slot 2 the lattice.
        const Harmonics got{{int(std::lround(out[5])), int(std::lround(out[6]))},
                            {int(std::lround(out[1])), int(std::lround(out[2]))}};
        CHECK(out[2] == 0); // a one-index layer has no second generator
        CHECK(out[3] == 0);
        CHECK(out[4] == 0);
        CHECK(sameCharacter(got, want.k));
    }
}

TEST_CASE("lattice characters: a lattice alone has no character") {
    // A lattice's own generators make row families of that layer, not beats: a stack of one
    // lattice reads no character, like any sole layer, even stretched until two of its rows
    // (2u + v and the columns) nearly align.
    DerivedProbe probe(1, [](ir::Builder& b, ir::ValueId x, ir::ValueId y) {
        const std::vector<lower::LayerFields> one = {
            latticeLayer(b, x, y, {lower::LatticeKind::Triangle, 10, 3, 0.2, 0})};
        b.output(0, lower::stackCharacter(b, one).mu);
    });
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        CAPTURE(backend);
        CHECK(searched(probe)[0] == doctest::Approx(lower::kNoCharacter).epsilon(1e-6));
    }
}
