// The registry of compiler-built families: it builds exactly the standard library's builtin
// families (and the walking solver), an unregistered name is an internal error, and each
// registered builder, reached through the registry from a scene, draws what an exhaustive
// search written here finds (the lattices' points; the walking members by the independent
// reference scan of tests/reference).
#include "compiler/diag/Diagnostics.h"
#include "compiler/lower/FamilyRegistry.h"
#include "compiler/lower/WalkingFamily.h"
#include "runtime/Probe.h"
#include "tests/reference/WalkingReference.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <set>
#include <string>

using namespace moire;

namespace {

std::set<std::string> builtinFamiliesOfTheLibrary() {
    auto program = test::compileOk("layer { family = lines }");
    std::set<std::string> names;
    for (const auto& [decl, family] : program->checked.families)
        if (family.kind == sema::FamilyKind::Builtin) names.insert(decl->name);
    return names;
}

// The least distance from (x, y) to the points lattice(i, j) for |i|, |j| <= 12.
template <class Point>
double bruteNearest(double x, double y, Point lattice) {
    double best = 1e300;
    for (int i = -12; i <= 12; ++i)
        for (int j = -12; j <= 12; ++j)
            for (auto [px, py] : lattice(i, j)) best = std::min(best, std::hypot(x - px, y - py));
    return best;
}

using Points = std::vector<std::pair<double, double>>;

} // namespace

TEST_CASE("family registry: the builtin families of the library, each built, and the solver") {
    const std::set<std::string> library = builtinFamiliesOfTheLibrary();
    REQUIRE(!library.empty());
    std::set<std::string> registered;
    for (const lower::RegisteredFamily& f : lower::registeredFamilies()) {
        INFO(f.name);
        CHECK(registered.insert(f.name).second); // registered once
        CHECK(f.build);
        if (std::string(f.name) != lower::kWalking) CHECK(library.count(f.name) == 1);
    }
    for (const std::string& name : library) {
        INFO(name);
        CHECK(registered.count(name) == 1);
    }
    CHECK(registered.count(lower::kWalking) == 1);
    CHECK_THROWS_AS(lower::familyBuilder("no_such_family"), InternalError);
}

TEST_CASE("family registry: each lattice draws the brute-force nearest point") {
    const double s = 7.5, r3 = std::numbers::sqrt3;
    struct Case {
        const char* name;
        std::function<Points(int, int)> points;
    };
    const Case cases[] = {
        {"square_lattice",
         [&](int i, int j) {
             return Points{{i * s, j * s}};
         }},
        {"triangle_lattice",
         [&](int i, int j) {
             return Points{{(i + 0.5 * j) * s, j * s * r3 / 2}};
         }},
        // Corners of hexagons of side s about centres a triangle lattice of pitch s sqrt 3.
        {"hex_lattice",
         [&](int i, int j) {
             const double p = s * r3, cx = p * (i + 0.5 * j), cy = p * j * r3 / 2;
             Points corners;
             for (int k = 0; k < 6; ++k) {
                 const double a = (30.0 + 60.0 * k) * std::numbers::pi / 180.0;
                 corners.push_back({cx + s * std::cos(a), cy + s * std::sin(a)});
             }
             return corners;
         }},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        auto program =
            test::compileOk(std::string("layer { family = ") + c.name + "; spacing = 7.5 }",
                            {.mode = CompileOptions::Mode::Probe, .layerFields = true});
        Prober probe(*program, nullptr);
        for (double x = -20.25; x < 20; x += 3.7)
            for (double y = -15.5; y < 15; y += 4.1) {
                const double got = probe.at(x, y)[program->layout.distanceSlot(0)];
                CHECK(got == doctest::Approx(bruteNearest(x, y, c.points)).epsilon(1e-9));
            }
    }
}

TEST_CASE("family registry: a walking layer draws the reference scan's nearest member") {
    auto program =
        test::compileOk("layer { family = squares; spacing = 9; phase = 2; offset = (1.5, -0.5); "
                        "turn = 3deg; stroke = 1 }",
                        {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    reference::Walking w{4, 9.0, 2.0, 1.5, -0.5, 3.0 * std::numbers::pi / 180.0};
    // The probe's pixel is one world unit: band h = max(1/2, 1.15), a = 0.7 (an oracle
    // written again here on purpose), guard max(h + a, 3/4 s).
    const double guard = std::max(1.15 + 0.7, 0.75 * 9.0);
    for (double x = -60; x < 60; x += 13.3)
        for (double y = -45; y < 45; y += 11.9) {
            const double want = reference::nearest(w, x, y, guard).distance;
            const double got = probe.at(x, y)[program->layout.distanceSlot(0)];
            INFO(x, ", ", y);
            CHECK(got == doctest::Approx(want).epsilon(1e-7));
        }
}
