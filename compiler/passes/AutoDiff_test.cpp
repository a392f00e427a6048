// Forward-mode AD, held to independent expectations: the gradient the compiler derives for a
// field expression against central finite differences of the same expression's values (on
// the double-precision interpreter), for every function and operator of the language; the
// zero rule of the spec (an exact zero factor wins over inf and NaN); and the clamps at
// singular points, which must give the same finite numbers on every backend.
//
// A field is compiled as `layer { family = <expr>; spacing = 1 }` with probe and layer
// outputs: its index is exactly the expression, its gradient outputs the derived gradient in
// world coordinates, and a Prober evaluates them at any world point.
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <random>

using namespace moire;

namespace {

constexpr double kTime = 0.7; // the clock for `t`
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Dual {
    double v, gx, gy;
};

// One field expression, compiled once, evaluated exactly (interpreter, double) or on a backend.
class Field {
  public:
    explicit Field(const std::string& expr)
        : program_(test::compileOk("layer { family = " + expr + "; spacing = 1 }",
                                   {.mode = CompileOptions::Mode::Probe, .layerFields = true})),
          exact_(*program_, nullptr) {}

    Dual exact(double x, double y) { return read(exact_.at(x, y, kTime)); }
    double value(double x, double y) {
        return exact_.at(x, y, kTime)[program_->layout.indexSlot(0)];
    }
    Dual on(Backend& backend, double x, double y) {
        auto it = probers_.find(&backend);
        if (it == probers_.end())
            it = probers_.emplace(&backend, std::make_unique<Prober>(*program_, &backend)).first;
        return read(it->second->at(x, y, kTime));
    }

  private:
    Dual read(const std::vector<double>& o) const {
        const auto& l = program_->layout;
        return {o[l.indexSlot(0)], o[l.gradXSlot(0)], o[l.gradYSlot(0)]};
    }
    std::unique_ptr<SceneProgram> program_;
    Prober exact_;
    std::map<Backend*, std::unique_ptr<Prober>> probers_;
};

// Every backend available here; one missing at run time is skipped with a message.
std::vector<std::unique_ptr<Backend>> allBackends() {
    std::vector<std::unique_ptr<Backend>> out;
    for (const std::string& name : test::availableBackends())
        if (auto b = test::makeBackendOrSkip(name)) out.push_back(std::move(b));
    return out;
}

// Fourth-order central difference: error O(h^4), so with h = 1e-4 it is far below the 1e-6
// tolerance for any smooth field, and rounding costs about 1e-12 |f|.
Dual finiteDifference(Field& f, double x, double y) {
    const double h = 1e-4;
    auto d = [&](double dx, double dy) {
        return (f.value(x - 2 * h * dx, y - 2 * h * dy) - 8 * f.value(x - h * dx, y - h * dy) +
                8 * f.value(x + h * dx, y + h * dy) - f.value(x + 2 * h * dx, y + 2 * h * dy)) /
               (12 * h);
    };
    return {f.value(x, y), d(1, 0), d(0, 1)};
}

bool close(double got, double want, double rel, double floor = 1.0) {
    if (std::isinf(want)) return got == want;
    return std::fabs(got - want) <= rel * std::max(std::fabs(want), floor);
}

// Distance of v from the nearest whole number.
double offInt(double v) {
    return std::fabs(v - std::round(v));
}

using Fn2 = std::function<double(double, double)>;

struct Box {
    double x0 = -2.5, x1 = 2.5, y0 = -2.5, y1 = 2.5;
};

struct Case {
    const char* expr;
    Fn2 value; // the expression written in C++: holds the front end to the language's meaning
    Box box = {};
    // False within a margin of a kink, jump or branch cut (where finite differences mean
    // nothing); the margin is far wider than the difference stencil (4e-4).
    std::function<bool(double, double)> smooth = [](double, double) { return true; };
};

const double kM = 1e-2; // kink margin, in the units of the kinked argument
const double kPi = std::numbers::pi, kE = std::numbers::e;
double wrapRef(double v, double w) {
    return v - w * std::floor(v / w + 0.5);
}
double smoothRef(double e0, double e1, double v) {
    double u = std::clamp((v - e0) / (e1 - e0), 0.0, 1.0);
    return u * u * (3 - 2 * u);
}
bool awayFromOrigin(double x, double y) {
    return std::hypot(x, y) > 0.05;
}

std::vector<Case> languageCases() {
    using std::pow;
    return {
        // operators
        {"x + y", [](double x, double y) { return x + y; }},
        {"x - 2 * y", [](double x, double y) { return x - 2 * y; }},
        {"x * y", [](double x, double y) { return x * y; }},
        {"x / y", [](double x, double y) { return x / y; }, {-2.5, 2.5, 0.3, 2.5}},
        {"-x * y + -(x - y)", [](double x, double y) { return -x * y - (x - y); }},
        // right-associative: 2 ^ (x ^ 2), a pow with a constant base
        {"2 ^ x ^ 2", [](double x, double) { return pow(2, x * x); }, {-1.5, 1.5}},
        {"x ^ 3 - 3 * x * y ^ 2", [](double x, double y) { return x * x * x - 3 * x * y * y; }},
        {"x ^ -2 + y ^ 0", [](double x, double) { return 1 / (x * x) + 1; }, {0.3, 2.5}},
        {"x ^ y", [](double x, double y) { return pow(x, y); }, {0.2, 3.0}},
        {"x ^ 0.5 + y ^ 1.5",
         [](double x, double y) { return pow(x, 0.5) + pow(y, 1.5); },
         {0.1, 3.0, 0.1, 3.0}},
        {"e ^ (x * y / 3)", [](double x, double y) { return std::exp(x * y / 3); }},
        {"pi * x + tau * y + e * x * y",
         [](double x, double y) { return kPi * x + 2 * kPi * y + kE * x * y; }},
        {"sin(x + t) * y", [](double x, double y) { return std::sin(x + kTime) * y; }},
        // functions
        {"sin(x * y)", [](double x, double y) { return std::sin(x * y); }},
        {"cos(x - 2 * y)", [](double x, double y) { return std::cos(x - 2 * y); }},
        {"tan(x)", [](double x, double) { return std::tan(x); }, {-1.3, 1.3}},
        {"asin(x) + acos(y)",
         [](double x, double y) { return std::asin(x) + std::acos(y); },
         {-0.95, 0.95, -0.95, 0.95}},
        {"atan(x * y)", [](double x, double y) { return std::atan(x * y); }},
        {"exp(x) * y", [](double x, double y) { return std::exp(x) * y; }},
        {"log(x * x + y)",
         [](double x, double y) { return std::log(x * x + y); },
         {-2.5, 2.5, 0.1, 2.5}},
        {"sqrt(x * x + y * y + 1) + sqrt(x + 3)",
         [](double x, double y) { return std::sqrt(x * x + y * y + 1) + std::sqrt(x + 3); }},
        {"abs(x * y - 1)",
         [](double x, double y) { return std::fabs(x * y - 1); },
         {},
         [](double x, double y) { return std::fabs(x * y - 1) > kM; }},
        {"floor(x) * y",
         [](double x, double y) { return std::floor(x) * y; },
         {},
         [](double x, double) { return offInt(x) > kM; }},
        {"fract(x * y)",
         [](double x, double y) { return x * y - std::floor(x * y); },
         {},
         [](double x, double y) { return offInt(x * y) > kM; }},
        {"round(x) + x * y",
         [](double x, double y) { return std::floor(x + 0.5) + x * y; },
         {},
         [](double x, double) { return offInt(x + 0.5) > kM; }},
        {"sign(x) * y",
         [](double x, double y) { return (x > 0 ? 1 : -1) * y; },
         {},
         [](double x, double) { return std::fabs(x) > kM; }},
        {"min(x, y)",
         [](double x, double y) { return std::min(x, y); },
         {},
         [](double x, double y) { return std::fabs(x - y) > kM; }},
        {"max(x * y, x + y)",
         [](double x, double y) { return std::max(x * y, x + y); },
         {},
         [](double x, double y) { return std::fabs(x * y - x - y) > kM; }},
        {"mod(x, 3)",
         [](double x, double) { return x - 3 * std::floor(x / 3); },
         {-4, 4, -1, 1},
         [](double x, double) { return offInt(x / 3) > kM; }},
        {"mod(x, y)",
         [](double x, double y) { return x - y * std::floor(x / y); },
         {-4, 4, 0.5, 3},
         [](double x, double y) { return offInt(x / y) > kM; }},
        {"hypot(x, y)", [](double x, double y) { return std::hypot(x, y); }, {}, awayFromOrigin},
        {"clamp(x * y, -1, 1)",
         [](double x, double y) { return std::clamp(x * y, -1.0, 1.0); },
         {},
         [](double x, double y) { return std::fabs(std::fabs(x * y) - 1) > kM; }},
        {"wrap(x * y, 2)",
         [](double x, double y) { return wrapRef(x * y, 2); },
         {},
         [](double x, double y) { return offInt(x * y / 2 + 0.5) > kM; }},
        // smoothstep is C1 at its ends, so differences stay accurate across them
        {"smoothstep(-1, 1, x * y)", [](double x, double y) { return smoothRef(-1, 1, x * y); }},
        {"mix(x, y, 0.3) + mix(sin(x), y, x / 4)",
         [](double x, double y) {
             return x + (y - x) * 0.3 + std::sin(x) + (y - std::sin(x)) * x / 4;
         }},
        {"length((x, 2 * y))",
         [](double x, double y) { return std::hypot(x, 2 * y); },
         {},
         awayFromOrigin},
        {"r * cos(3 * theta)",
         [](double x, double y) { return std::hypot(x, y) * std::cos(3 * std::atan2(y, x)); },
         {},
         [](double x, double y) { return awayFromOrigin(x, y) && !(x < 0 && std::fabs(y) < kM); }},
        // composites
        {"sin(x * y) / hypot(x, y)",
         [](double x, double y) { return std::sin(x * y) / std::hypot(x, y); },
         {},
         [](double x, double y) { return std::hypot(x, y) > 0.1; }},
        {"atan2(y, x ^ 2 - 1)",
         [](double x, double y) { return std::atan2(y, x * x - 1); },
         {},
         [](double x, double y) {
             double u = x * x - 1;
             return std::hypot(y, u) > 0.05 && !(u < 0 && std::fabs(y) < kM);
         }},
        {"exp(sin(x)) * log(1 + y * y) - sqrt(abs(x) + 1)",
         [](double x, double y) {
             return std::exp(std::sin(x)) * std::log(1 + y * y) - std::sqrt(std::fabs(x) + 1);
         },
         {},
         [](double x, double) { return std::fabs(x) > kM; }},
    };
}

} // namespace

TEST_CASE(
    "deriv: AD gradients of every language function match finite differences on every backend") {
    auto backends = allBackends();

    std::mt19937 rng(20240611);
    for (const Case& c : languageCases()) {
        std::string expr = c.expr;
        CAPTURE(expr);
        Field f(c.expr);
        std::uniform_real_distribution<double> ux(c.box.x0, c.box.x1), uy(c.box.y0, c.box.y1);
        int checked = 0;
        const int kPoints = 24;
        for (int i = 0; i < kPoints; ++i) {
            double x = ux(rng), y = uy(rng);
            if (!c.smooth(x, y)) continue;
            ++checked;
            CAPTURE(x);
            CAPTURE(y);
            Dual ad = f.exact(x, y);
            CHECK(close(ad.v, c.value(x, y), 1e-12));
            Dual fd = finiteDifference(f, x, y);
            CHECK(close(ad.gx, fd.gx, 1e-6));
            CHECK(close(ad.gy, fd.gy, 1e-6));
            for (auto& backend : backends) {
                CAPTURE(backend->name());
                // The interpreter backend rounds its outputs to float; the JIT computes in float.
                double rel = backend->name() == "interp" ? 1e-6 : 1e-3;
                Dual got = f.on(*backend, x, y);
                CHECK(close(got.v, ad.v, rel));
                CHECK(close(got.gx, ad.gx, rel));
                CHECK(close(got.gy, ad.gy, rel));
            }
        }
        CHECK(checked >= kPoints / 2); // the skip rule must leave most points to check
    }
}

// The zero rule (spec §10.2): in a chain-rule product an exact zero factor contributes
// nothing, even when the other factor overflowed. A plain multiply would give 0 * inf = NaN.
TEST_CASE("deriv: an exact zero factor wins over an overflowed one (the zero rule)") {
    auto backends = allBackends();

    struct Expect {
        const char* expr;
        double x, y;
        Dual want; // exact, inf included
    };
    const double halfPi = std::acos(0.0);
    const Expect cases[] = {
        // d/dy = exp(...) * 2000 y: inf * 0 at y = 0, must be 0.
        {"exp(1000 + 1000 * y ^ 2)", 0.5, 0.0, {kInf, 0.0, 0.0}},
        // d/dx overflows; d/dy is structurally zero and stays exactly 0.
        {"exp(1000 * x)", 1.0, 0.3, {kInf, kInf, 0.0}},
        // atan'(inf) = 0 exactly, times an infinite inner slope: 0, as the true slope ~e^-1000.
        {"atan(exp(1000 + x))", 0.2, -0.4, {halfPi, 0.0, 0.0}},
        // C-infinity with every derivative 0 at the origin; the inner quotient's slope is
        // 0/0 = NaN there, and exp's exact-zero value must absorb it.
        {"exp(-1 / (x * x))", 0.0, 1.0, {0.0, 0.0, 0.0}},
        // d(x^y)/dx = y x^(y-1) = 0 * inf at x = y = 0: the exponent's exact zero wins.
        // d/dy = x^y log(x) meets log's floor, log(1e-30).
        {"x ^ y", 0.0, 0.0, {1.0, 0.0, std::log(1e-30)}},
        // floor has slope exactly 0, so d/dy is 0 * inf + 1 = 1, not NaN.
        {"floor(y) * exp(1000 * x) + y", 2.0, 1.5, {kInf, kInf, 1.0}},
    };
    for (const Expect& e : cases) {
        std::string expr = e.expr;
        CAPTURE(expr);
        Field f(e.expr);
        Dual exact = f.exact(e.x, e.y);
        // Zeros must be exact (the rule is exact); infinities must match.
        auto check = [&](const Dual& d) {
            CHECK(close(d.v, e.want.v, 1e-6));
            CHECK(close(d.gx, e.want.gx, 1e-6, 0.0));
            CHECK(close(d.gy, e.want.gy, 1e-6, 0.0));
        };
        check(exact);
        for (auto& backend : backends) {
            CAPTURE(backend->name());
            check(f.on(*backend, e.x, e.y));
        }
    }
}

// Singular points: the clamps of Semantics.h (log's floor, sqrt of max(x, 0), asin/acos's
// clamp, the floored denominators of atan2's and hypot's rules) promise finite values and
// slopes, and the same ones on every backend. Where no clamp applies (1/x at 0), the
// backends must still agree on the infinity.
TEST_CASE("deriv: singular points give the same finite values and slopes on every backend") {
    auto backends = allBackends();

    struct Pole {
        const char* expr;
        double x, y;
        Dual want;
        bool finite = true;
    };
    const double halfPi = std::acos(0.0);
    const double logTiny = std::log(1e-30);
    const Pole poles[] = {
        {"log(x)", 0.0, 1.0, {logTiny, 0.0, 0.0}},
        {"log(x)", -2.0, 1.0, {logTiny, 0.0, 0.0}},
        {"log(x * x + y * y)", 0.0, 0.0, {logTiny, 0.0, 0.0}},
        {"sqrt(x)", 0.0, 1.0, {0.0, 0.0, 0.0}},
        {"sqrt(x)", -3.0, 1.0, {0.0, 0.0, 0.0}},
        {"sqrt(x * x + y * y)", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"atan2(y, x)", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"theta", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"asin(x)", 1.0, 0.0, {halfPi, 0.0, 0.0}},
        {"asin(x)", -1.0, 0.0, {-halfPi, 0.0, 0.0}},
        {"asin(x)", 1.5, 0.0, {halfPi, 0.0, 0.0}},
        {"acos(y)", 0.0, 1.0, {0.0, 0.0, 0.0}},
        {"acos(y)", 0.0, -2.0, {2 * halfPi, 0.0, 0.0}},
        {"hypot(x, y)", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"r", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"length((x, y))", 0.0, 0.0, {0.0, 0.0, 0.0}},
        {"1 / x", 0.0, 1.0, {kInf, -kInf, 0.0}, false},
    };
    for (const Pole& p : poles) {
        std::string expr = p.expr;
        CAPTURE(expr);
        CAPTURE(p.x);
        CAPTURE(p.y);
        Field f(p.expr);
        Dual exact = f.exact(p.x, p.y);
        if (p.finite) {
            CHECK(std::isfinite(exact.v));
            CHECK(std::isfinite(exact.gx));
            CHECK(std::isfinite(exact.gy));
        }
        CHECK(close(exact.v, p.want.v, 1e-12));
        CHECK(close(exact.gx, p.want.gx, 1e-12));
        CHECK(close(exact.gy, p.want.gy, 1e-12));
        for (auto& backend : backends) {
            CAPTURE(backend->name());
            Dual got = f.on(*backend, p.x, p.y);
            CHECK(close(got.v, exact.v, 1e-6));
            CHECK(close(got.gx, exact.gx, 1e-6));
            CHECK(close(got.gy, exact.gy, 1e-6));
        }
    }
}
