// The AD pass on control flow the language cannot write yet but the IR has: tangents carried
// through both branches of an `if` and around the back edge of a `loop` (including a value
// whose tangent only arrives through the back edge, and carried values that swap slots),
// derivative markers inside a loop body, and structural zeros. Expectations: central finite
// differences of the same function on the double interpreter, or the analytic derivative.
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/passes/AutoDiff.h"
#include "compiler/passes/Simplify.h"

#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <random>

using namespace moire;
using namespace moire::ir;

namespace {

using Vals = std::vector<ValueId>;
using Body = std::function<ValueId(Builder&, ValueId, ValueId)>;

// out0 = body(x, y), with x and y the independent variables (uniforms 0 and 1); with
// `derivs`, out1 and out2 are its partials.
Function field(const Body& body, bool derivs) {
    Function f;
    f.name = "field";
    f.numOutputs = derivs ? 3 : 1;
    Builder b(f);
    ValueId x = b.emit(Op::Indep, {b.uniform(0)}, 0.0, 0);
    ValueId y = b.emit(Op::Indep, {b.uniform(1)}, 0.0, 1);
    ValueId r = body(b, x, y);
    b.output(0, r);
    if (derivs) {
        b.output(1, b.emit(Op::DerivX, {r}));
        b.output(2, b.emit(Op::DerivY, {r}));
    }
    verify(f);
    return f;
}

// A loop of `n` iterations (a constant count) over carried values `inits`.
Vals repeat(Builder& b, int n, Vals inits,
            const std::function<Vals(std::span<const ValueId>)>& body) {
    inits.insert(inits.begin(), b.constI(0));
    auto r = b.loop(
        inits,
        [&](std::span<const ValueId> p) {
            return Vals{b.emit(Op::ILt, {p[0], b.constI(n)})};
        },
        [&](std::span<const ValueId> p) {
            Vals next = body(p.subspan(1));
            next.insert(next.begin(), b.emit(Op::IAdd, {p[0], b.constI(1)}));
            return next;
        });
    return Vals(r.begin() + 1, r.end());
}

double offInt(double v) {
    return std::fabs(v - std::round(v));
}

struct Case {
    const char* name;
    Body body;
    std::function<bool(double, double)> smooth = [](double, double) { return true; };
};

std::vector<Case> cases() {
    return {
        {"if with x in both branches",
         [](Builder& b, ValueId x, ValueId y) {
             return b.ifThenElse(
                 b.gt(b.mul(x, y), b.constF(0.5)), [&] { return Vals{b.mul(b.sin(x), y)}; },
                 [&] { return Vals{b.sub(b.mul(x, x), y)}; })[0];
         },
         [](double x, double y) { return std::fabs(x * y - 0.5) > 1e-2; }},
        {"if with a tangent in one branch only",
         [](Builder& b, ValueId x, ValueId y) {
             return b.ifThenElse(
                 b.gt(y, b.constF(0.0)), [&] { return Vals{b.mul(x, x)}; },
                 [&] { return Vals{b.constF(2.0)}; })[0];
         },
         [](double, double y) { return std::fabs(y) > 1e-2; }},
        {"Horner loop carrying x and y",
         [](Builder& b, ValueId x, ValueId y) {
             return repeat(b, 4, {y}, [&](std::span<const ValueId> p) {
                 return Vals{b.add(b.mul(p[0], x), b.sin(y))};
             })[0];
         }},
        {"tangent entering through the back edge",
         [](Builder& b, ValueId x, ValueId y) {
             // acc = sum_{k=1}^{5} sin(k x) y, from a constant start.
             auto r = repeat(b, 5, {b.constF(1.0), b.constF(0.0)}, [&](std::span<const ValueId> p) {
                 return Vals{b.add(p[0], b.constF(1.0)),
                             b.add(p[1], b.mul(b.sin(b.mul(p[0], x)), y))};
             });
             return r[1];
         }},
        {"carried values swapping slots",
         [](Builder& b, ValueId x, ValueId y) {
             auto r = repeat(b, 3, {x, y}, [&](std::span<const ValueId> p) {
                 return Vals{p[1], b.mul(p[0], x)};
             });
             return b.add(r[0], b.mul(b.constF(2.0), r[1]));
         }},
        {"trip count depending on x",
         [](Builder& b, ValueId x, ValueId y) {
             ValueId n = b.emit(Op::FToI, {b.mul(b.abs(x), b.constF(3.0))});
             auto r = b.loop(
                 {b.constI(0), y},
                 [&](std::span<const ValueId> p) {
                     return Vals{b.emit(Op::ILt, {p[0], n})};
                 },
                 [&](std::span<const ValueId> p) {
                     return Vals{b.emit(Op::IAdd, {p[0], b.constI(1)}),
                                 b.add(b.mul(p[1], x), b.constF(1.0))};
                 });
             return r[1];
         },
         [](double x, double) { return offInt(std::fabs(x) * 3) > 1e-2 && std::fabs(x) > 1e-2; }},
        {"if inside a loop inside an if",
         [](Builder& b, ValueId x, ValueId y) {
             return b.ifThenElse(
                 b.lt(x, b.constF(1.5)),
                 [&] {
                     return repeat(b, 3, {x}, [&](std::span<const ValueId> p) {
                         return b.ifThenElse(
                             b.gt(p[0], y),
                             [&] { return Vals{b.sub(p[0], b.mul(y, b.constF(0.5)))}; },
                             [&] { return Vals{b.add(b.mul(p[0], p[0]), y)}; });
                     });
                 },
                 [&] { return Vals{b.hypot(x, y)}; })[0];
         },
         // Kinks where an iterate crosses y; finite differences at a nearby pair tell.
         [](double x, double y) {
             double p = x;
             for (int k = 0; k < 3 && x < 1.5; ++k) {
                 if (std::fabs(p - y) < 1e-2) return false;
                 p = p > y ? p - 0.5 * y : p * p + y;
             }
             return std::fabs(x - 1.5) > 1e-2;
         }},
    };
}

} // namespace

TEST_CASE("deriv: AD through if and loop matches finite differences on every backend") {
    auto backends = optest::allBackends();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (const Case& c : cases()) {
        std::string name = c.name;
        CAPTURE(name);
        Function value = field(c.body, false);
        Function derived = passes::autoDiff(field(c.body, true));
        Function optimised = passes::simplify(derived);
        std::vector<std::unique_ptr<CompiledKernel>> kernels;
        for (auto& backend : backends) kernels.push_back(backend->compile(optimised));
        int checked = 0;
        for (int i = 0; i < 30; ++i) {
            double x = u(rng), y = u(rng);
            if (!c.smooth(x, y)) continue;
            ++checked;
            CAPTURE(x);
            CAPTURE(y);
            const double h = 1e-4;
            auto v = [&](double dx, double dy) {
                return optest::interpret(value, {{x + dx * h, y + dy * h}})[0];
            };
            double fx = (v(-2, 0) - 8 * v(-1, 0) + 8 * v(1, 0) - v(2, 0)) / (12 * h);
            double fy = (v(0, -2) - 8 * v(0, -1) + 8 * v(0, 1) - v(0, 2)) / (12 * h);
            std::vector<double> ad = optest::interpret(derived, {{x, y}});
            CHECK(ad[0] == doctest::Approx(v(0, 0)).epsilon(1e-12));
            CHECK(ad[1] == doctest::Approx(fx).epsilon(1e-6).scale(1.0));
            CHECK(ad[2] == doctest::Approx(fy).epsilon(1e-6).scale(1.0));
            CHECK(optest::interpret(optimised, {{x, y}}) == ad);
            for (size_t k = 0; k < backends.size(); ++k) {
                CAPTURE(backends[k]->name());
                std::vector<float> got = optest::runPixel(*kernels[k], {x, y});
                for (int j = 0; j < 3; ++j)
                    CHECK(got[j] == doctest::Approx(ad[j]).epsilon(1e-4).scale(1.0));
            }
        }
        CHECK(checked >= 15);
    }
}

TEST_CASE("deriv: a derivative marker inside a loop body") {
    // sum_{k=1}^{3} d/dx sin(k x y) = sum_k k y cos(k x y)
    Function f = passes::autoDiff(field(
        [](Builder& b, ValueId x, ValueId y) {
            auto r = repeat(b, 3, {b.constF(1.0), b.constF(0.0)}, [&](std::span<const ValueId> p) {
                ValueId d = b.emit(Op::DerivX, {b.sin(b.mul(b.mul(p[0], x), y))});
                return Vals{b.add(p[0], b.constF(1.0)), b.add(p[1], d)};
            });
            return r[1];
        },
        false));
    for (auto [x, y] : {std::pair{0.3, 1.1}, {-1.7, 0.4}}) {
        double want = 0;
        for (int k = 1; k <= 3; ++k) want += k * y * std::cos(k * x * y);
        CHECK(optest::interpret(f, {{x, y}})[0] == doctest::Approx(want).epsilon(1e-12));
    }
}

TEST_CASE("deriv: a partial that does not depend on a variable is a structural zero") {
    // d/dy of a function of x alone is the constant 0, emitted as such: no arithmetic, so
    // no inf * 0 where d/dx overflows.
    Function f = passes::simplify(passes::autoDiff(
        field([](Builder& b, ValueId x,
                 ValueId) { return b.emit(Op::Exp, {b.mul(x, b.constF(1000.0))}); },
              true)));
    const Inst* out2 = nullptr;
    std::vector<const Inst*> def(f.numValues());
    for (const Inst& inst : f.blocks[0].insts) {
        for (ValueId r : inst.results) def[r] = &inst;
        if (inst.op == Op::Output && inst.iimm == 2) out2 = &inst;
    }
    REQUIRE(out2);
    CHECK(def[out2->args[0]]->op == Op::ConstF);
    CHECK(def[out2->args[0]]->imm == 0.0);
    std::vector<double> at = optest::interpret(f, {{1.0, 0.0}});
    CHECK(std::isinf(at[1]));
    CHECK(at[2] == 0.0);
}

TEST_CASE("deriv: a derivative of a derivative is refused, not silently zero") {
    // The pass is first order; d/dx (d/dx x^3) would otherwise come out as 0.
    Function f = field(
        [](Builder& b, ValueId x, ValueId) { return b.emit(Op::DerivX, {b.powi(x, 3)}); }, true);
    CHECK_THROWS_AS(passes::autoDiff(f), InternalError);
    // A derivative nobody differentiates again is fine.
    CHECK_NOTHROW(passes::autoDiff(field(
        [](Builder& b, ValueId x, ValueId) { return b.emit(Op::DerivX, {b.powi(x, 3)}); }, false)));
}

TEST_CASE("deriv: a detached value is constant to AD, so a gradient can be read where a "
          "gradient points") {
    // g(p) = sin(p_x) cos(2 p_y), read at p = (x, y) + detach(s grad g(x, y)): its derivative
    // is g's gradient at the moved point, as a function of the point alone (without detach,
    // the move's own dependence on (x, y) is a derivative of a derivative, refused).
    auto g = [](Builder& b, ValueId px, ValueId py) {
        return b.mul(b.sin(px), b.cos(b.mul(py, b.constF(2.0))));
    };
    auto moved = [&](bool detach) {
        return field(
            [&](Builder& b, ValueId x, ValueId y) {
                ValueId here = g(b, x, y);
                ValueId s = b.constF(0.3);
                ValueId ox = b.mul(s, b.emit(Op::DerivX, {here}));
                ValueId oy = b.mul(s, b.emit(Op::DerivY, {here}));
                if (detach) {
                    ox = b.emit(Op::Detach, {ox});
                    oy = b.emit(Op::Detach, {oy});
                }
                return g(b, b.add(x, ox), b.add(y, oy));
            },
            true);
    };
    CHECK_THROWS_AS(passes::autoDiff(moved(false)), InternalError);
    Function f = passes::simplify(passes::autoDiff(moved(true)));
    for (const Block& blk : f.blocks)
        for (const Inst& inst : blk.insts) CHECK(inst.op != Op::Detach);
    for (auto [x, y] : {std::pair{0.3, 1.1}, {-1.7, 0.4}, {2.2, -0.9}}) {
        const double px = x + 0.3 * std::cos(x) * std::cos(2 * y);
        const double py = y - 0.6 * std::sin(x) * std::sin(2 * y);
        std::vector<double> at = optest::interpret(f, {{x, y}});
        CHECK(at[0] == doctest::Approx(std::sin(px) * std::cos(2 * py)).epsilon(1e-12));
        CHECK(at[1] == doctest::Approx(std::cos(px) * std::cos(2 * py)).epsilon(1e-12));
        CHECK(at[2] == doctest::Approx(-2 * std::sin(px) * std::sin(2 * py)).epsilon(1e-12));
    }
}
