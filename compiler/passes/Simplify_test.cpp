// The cleanup passes (constant folding, CSE, DCE) preserve what a function computes: random
// functions with ifs and loops give bit-identical interpreter outputs before and after each
// pass, on inputs that include 0, -0, inf and NaN. Then the specific promises: folding
// uses the shared semantics and the zero rule, a constant `if` is inlined, CSE respects
// regions and min/max's operand order, DCE keeps what writes an output, loops survive.
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/ir/Semantics.h"
#include "compiler/passes/Simplify.h"

#include <cmath>
#include <doctest/doctest.h>
#include <limits>
#include <numbers>
#include <random>

using namespace moire;
using namespace moire::ir;
using optest::build;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool same(double got, double want) {
    if (std::isnan(want)) return std::isnan(got);
    return got == want && std::signbit(got) == std::signbit(want);
}
// Equal as numbers (-0 == +0; any NaN equals any NaN).
bool sameValue(double got, double want) {
    return std::isnan(want) ? std::isnan(got) : got == want;
}

size_t count(const Function& f, Op op) {
    size_t n = 0;
    for (const Block& blk : f.blocks)
        for (const Inst& inst : blk.insts) n += inst.op == op;
    return n;
}

// Random functions of three uniforms: float ops of every kind, constants (special values
// included), repeated subexpressions, ifs and loops nested two deep.
class RandomFunction {
  public:
    explicit RandomFunction(uint32_t seed) : rng_(seed) {}

    Function make() {
        return build(3, [&](Builder& b) {
            b_ = &b;
            pool_ = {b.uniform(0), b.uniform(1), b.uniform(2)};
            for (int i = 0; i < 14; ++i) step(0);
            for (int k = 0; k < 3; ++k) b.output(k, pool_[pool_.size() - 1 - k]);
        });
    }

  private:
    size_t below(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
    ValueId pick() { return pool_[below(pool_.size())]; }
    ValueId constant() {
        const double values[] = {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 1e30, kInf, kNaN};
        return b_->constF(values[below(std::size(values))]);
    }
    ValueId floatOp() {
        static const std::vector<Op> ops =
            optest::opsOfKind({optest::Kind::FloatUnary, optest::Kind::FloatBinary});
        Op op = ops[below(ops.size())];
        ValueId a = pick();
        return opInfo(op).numArgs == 1 ? b_->emit(op, {a})
                                       : b_->emit(op, {a, below(4) ? pick() : constant()});
    }
    void step(int depth) {
        Builder& b = *b_;
        switch (below(10)) {
        case 0:
            pool_.push_back(constant());
            break;
        case 1: { // the same expression twice: CSE fodder
            ValueId a = pick(), c = pick();
            pool_.push_back(b.mul(a, c));
            pool_.push_back(b.add(b.mul(a, c), b.emit(Op::MulZ, {c, a})));
            break;
        }
        case 2:
            pool_.push_back(b.select(b.lt(pick(), pick()), pick(), pick()));
            break;
        case 3:
            pool_.push_back(b.emit(Op::IToF, {b.emit(Op::FToI, {pick()})}));
            break;
        case 4:
            pool_.push_back(b.powi(pick(), static_cast<int64_t>(below(7)) - 3));
            break;
        case 5:
            if (depth < 2) {
                ValueId cond = below(3) ? b.lt(pick(), pick()) : b.constB(below(2));
                auto region = [&] {
                    auto saved = pool_;
                    for (int i = 0; i < 3; ++i) step(depth + 1);
                    std::vector<ValueId> y = {pick(), pool_.back()};
                    pool_ = saved;
                    return y;
                };
                auto r = b.ifThenElse(cond, region, region);
                pool_.insert(pool_.end(), r.begin(), r.end());
                break;
            }
            [[fallthrough]];
        case 6:
            if (depth < 2) {
                // Up to three iterations (a count from an input, or a constant one).
                ValueId n = below(2) ? b.emit(Op::FToI, {b.min(b.abs(pick()), b.constF(3.0))})
                                     : b.constI(below(4));
                auto r = b.loop(
                    {b.constI(0), pick()},
                    [&](std::span<const ValueId> p) {
                        return std::vector<ValueId>{b.emit(Op::ILt, {p[0], n})};
                    },
                    [&](std::span<const ValueId> p) {
                        auto saved = pool_;
                        pool_.push_back(p[1]);
                        for (int i = 0; i < 2; ++i) step(depth + 1);
                        std::vector<ValueId> y = {b.emit(Op::IAdd, {p[0], b.constI(1)}),
                                                  pool_.back()};
                        pool_ = saved;
                        return y;
                    });
                pool_.push_back(r[1]);
                break;
            }
            [[fallthrough]];
        default:
            pool_.push_back(floatOp());
            break;
        }
    }

    std::mt19937 rng_;
    Builder* b_ = nullptr;
    std::vector<ValueId> pool_;
};

} // namespace

TEST_CASE("folding, CSE and DCE preserve what random functions with ifs and loops compute") {
    std::mt19937 rng(99);
    const double special[] = {0.0, -0.0, 1.0, -2.5, 0.75, 1e30, -kInf, kNaN};
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    size_t folded = 0, merged = 0, dropped = 0;
    for (uint32_t seed = 1; seed <= 150; ++seed) {
        CAPTURE(seed);
        Function f = RandomFunction(seed).make();
        Function passes[] = {passes::constantFold(f), passes::eliminateCommonSubexpressions(f),
                             passes::eliminateDeadCode(f), passes::simplify(f)};
        folded += f.instCount() - passes[0].instCount();
        merged += f.instCount() - passes[1].instCount();
        dropped += f.instCount() - passes[2].instCount();
        for (int trial = 0; trial < 8; ++trial) {
            optest::InterpInputs in;
            for (int k = 0; k < 3; ++k)
                in.uniforms.push_back(trial < 4 ? special[(trial * 3 + k) % 8] : u(rng));
            CAPTURE(trial);
            std::vector<double> want = optest::interpret(f, in);
            for (int p = 0; p < 4; ++p) {
                CAPTURE(p);
                std::vector<double> got = optest::interpret(passes[p], in);
                // Up to the sign of a zero: folding mulz(x, 1) to x may keep a -0 that mulz
                // would have made +0 (ConstantFold.cpp says why); the identities that must
                // keep the sign are checked on their own below.
                for (int k = 0; k < 3; ++k) CHECK(sameValue(got[k], want[k]));
            }
        }
    }
    // The generator must give each pass something to do, or the check above proves little.
    CHECK(folded > 100);
    CHECK(merged > 100);
    CHECK(dropped > 100);
}

TEST_CASE("folding follows the shared semantics, clamps and zero rule included") {
    auto fold1 = [](auto&& body) {
        Function f = passes::eliminateDeadCode(
            passes::constantFold(build(1, [&](Builder& b) { b.output(0, body(b)); })));
        CHECK(f.instCount() == 2); // one constant, one output
        return optest::interpret(f, {})[0];
    };
    auto un = [&](Op op, double a) {
        return fold1([&](Builder& b) { return b.emit(op, {b.constF(a)}); });
    };
    CHECK(un(Op::Log, 0.0) == doctest::Approx(-69.07755278982137)); // log(kTiny), not -inf
    CHECK(un(Op::Log, -5.0) == doctest::Approx(-69.07755278982137));
    CHECK(same(un(Op::Sqrt, -4.0), 0.0));                              // sqrt(max(x, 0)), not NaN
    CHECK(un(Op::Asin, 2.0) == doctest::Approx(std::numbers::pi / 2)); // clamped to [-1, 1]
    CHECK(un(Op::Acos, -7.0) == doctest::Approx(std::numbers::pi));
    CHECK(same(un(Op::Round, -0.5), 0.0)); // floor(x + 1/2)
    CHECK(same(fold1([](Builder& b) {
                   return b.emit(Op::Mod, {b.constF(-1.0), b.constF(3.0)});
               }),
               2.0));
    CHECK(same(fold1([](Builder& b) {
                   return b.emit(Op::Atan2, {b.constF(0.0), b.constF(0.0)});
               }),
               0.0));
    CHECK(same(fold1([](Builder& b) { return b.powi(b.constF(-2.0), 3); }), -8.0));
    CHECK(same(fold1([](Builder& b) { return b.powi(b.constF(0.0), -1); }), kInf));
    CHECK(same(
        fold1([](Builder& b) { return b.emit(Op::IToF, {b.emit(Op::FToI, {b.constF(kNaN)})}); }),
        0.0));
    // The zero rule: mulz(0, inf) and mulz(NaN, 0) are 0.
    CHECK(same(fold1([](Builder& b) {
                   return b.emit(Op::MulZ, {b.constF(0.0), b.div(b.constF(1.0), b.constF(0.0))});
               }),
               0.0));
    CHECK(same(fold1([](Builder& b) {
                   return b.emit(Op::MulZ, {b.constF(kNaN), b.constF(0.0)});
               }),
               0.0));
}

TEST_CASE("mulz(0, x) folds to 0 whatever x turns out to be") {
    Function f = build(2, [](Builder& b) {
        b.output(0, b.emit(Op::MulZ, {b.constF(0.0), b.uniform(0)}));
        b.output(1, b.emit(Op::MulZ, {b.emit(Op::Exp, {b.uniform(0)}), b.constF(-0.0)}));
    });
    Function g = passes::simplify(f);
    CHECK(count(g, Op::MulZ) == 0);
    CHECK(count(g, Op::Uniform) == 0);
    for (double x : {1.0, kInf, -kInf, kNaN, 1e300}) {
        CAPTURE(x);
        CHECK(optest::interpret(f, {{x}}) == std::vector<double>{0.0, 0.0});
        CHECK(optest::interpret(g, {{x}}) == std::vector<double>{0.0, 0.0});
    }
}

TEST_CASE("folding keeps the sign of a zero: x + 0 is not x") {
    // 1 / (x + 0) is +inf at x = -0; folding x + 0 to x made it -inf.
    Function f = build(2, [](Builder& b) {
        b.output(0, b.div(b.constF(1.0), b.add(b.uniform(0), b.constF(0.0))));
        b.output(1, b.div(b.constF(1.0), b.sub(b.uniform(0), b.constF(-0.0))));
    });
    for (const Function& g : {passes::constantFold(f), passes::simplify(f)}) {
        CHECK(optest::interpret(g, {{-0.0}}) == std::vector<double>{kInf, kInf});
        CHECK(optest::interpret(g, {{2.0}}) == std::vector<double>{0.5, 0.5});
    }
    // The exact identities still apply.
    Function h = passes::simplify(build(2, [](Builder& b) {
        b.output(0, b.add(b.uniform(0), b.constF(-0.0)));
        b.output(1, b.sub(b.uniform(0), b.constF(0.0)));
    }));
    CHECK(count(h, Op::Add) + count(h, Op::Sub) == 0);
}

TEST_CASE("an if on a constant condition is inlined") {
    for (bool cond : {true, false}) {
        CAPTURE(cond);
        Function f = build(1, [&](Builder& b) {
            ValueId u = b.uniform(0);
            auto outer = b.ifThenElse(
                b.lt(b.constF(1.0), b.constF(2.0)), // always true: nested inside the taken branch
                [&] {
                    return b.ifThenElse(
                        b.constB(cond),
                        [&] { return std::vector<ValueId>{b.mul(u, b.constF(3.0))}; },
                        [&] { return std::vector<ValueId>{b.sub(u, b.constF(5.0))}; });
                },
                [&] { return std::vector<ValueId>{b.constF(99.0)}; });
            b.output(0, outer[0]);
        });
        Function g = passes::simplify(f);
        CHECK(count(g, Op::If) == 0);
        CHECK(g.blocks.size() == 1);
        CHECK(optest::interpret(g, {{2.0}})[0] == (cond ? 6.0 : -3.0));
    }
}

TEST_CASE("CSE respects regions and the operand order of min and max") {
    Function f = build(3, [](Builder& b) {
        ValueId u = b.uniform(0), v = b.uniform(1);
        // sin(u) inside a branch, then again after it: the second must not reuse the first.
        auto r = b.ifThenElse(
            b.lt(u, v), [&] { return std::vector<ValueId>{b.sin(u)}; },
            [&] { return std::vector<ValueId>{v}; });
        b.output(0, b.add(r[0], b.sin(u)));
        // min(u, v) and min(v, u) differ when one is NaN (the second operand wins a NaN).
        b.output(1, b.sub(b.min(u, v), b.min(v, u)));
        b.output(2, b.add(b.mul(u, v), b.mul(v, u))); // commutative: merged
    });
    Function g = passes::eliminateCommonSubexpressions(f);
    CHECK(count(g, Op::Sin) == 2);
    CHECK(count(g, Op::Min) == 2);
    CHECK(count(g, Op::Mul) == 1);
    for (auto [u, v] : {std::pair{0.3, 0.9}, {0.9, 0.3}, {kNaN, 1.0}}) {
        std::vector<double> want = optest::interpret(f, {{u, v}}),
                            got = optest::interpret(g, {{u, v}});
        for (int k = 0; k < 3; ++k) CHECK(same(got[k], want[k]));
    }
}

TEST_CASE("DCE drops what no output needs and keeps an output written inside a region") {
    Function f = build(2, [](Builder& b) {
        ValueId u = b.uniform(0);
        b.sin(b.mul(u, u)); // dead
        b.loop(
            {b.constI(0)},
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.emit(Op::ILt, {p[0], b.constI(5)})};
            },
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.emit(Op::IAdd, {p[0], b.constI(1)})};
            }); // dead
        // An if whose results nobody reads, but whose branch writes output 1.
        b.ifThenElse(
            b.gt(u, b.constF(0.0)),
            [&] {
                b.output(1, b.mul(u, b.constF(2.0)));
                return std::vector<ValueId>{};
            },
            [&] { return std::vector<ValueId>{}; });
        b.output(0, b.add(u, b.constF(1.0)));
    });
    Function g = passes::eliminateDeadCode(f);
    CHECK(count(g, Op::Sin) == 0);
    CHECK(count(g, Op::Loop) == 0);
    CHECK(count(g, Op::If) == 1);
    CHECK(count(g, Op::Output) == 2);
    CHECK(optest::interpret(g, {{4.0}}) == std::vector<double>{5.0, 8.0});
}

// sum_{k=1}^{n} 1/k^2 (-> pi^2 / 6): a loop must come out of every pass still a loop, still
// computing the sum, whether its trip count is known (a constant) or not (an input).
TEST_CASE("loops survive every pass") {
    for (bool constantCount : {false, true}) {
        CAPTURE(constantCount);
        Function f = build(1, [&](Builder& b) {
            ValueId n = constantCount ? b.constI(1000) : b.emit(Op::FToI, {b.uniform(0)});
            auto r = b.loop(
                {b.constI(1), b.constF(0.0)},
                [&](std::span<const ValueId> p) {
                    return std::vector<ValueId>{b.emit(Op::ILe, {p[0], n})};
                },
                [&](std::span<const ValueId> p) {
                    ValueId k = b.emit(Op::IToF, {p[0]});
                    return std::vector<ValueId>{b.emit(Op::IAdd, {p[0], b.constI(1)}),
                                                b.add(p[1], b.div(b.constF(1.0), b.mul(k, k)))};
                });
            b.output(0, r[1]);
        });
        double sum = 0.0;
        for (int k = 1; k <= 1000; ++k) sum += 1.0 / (double(k) * k);
        for (const Function& g : {passes::constantFold(f), passes::eliminateCommonSubexpressions(f),
                                  passes::eliminateDeadCode(f), passes::simplify(f)}) {
            CHECK(count(g, Op::Loop) == 1);
            CHECK(same(optest::interpret(g, {{1000.0}})[0], sum));
            CHECK(std::fabs(sum - std::numbers::pi * std::numbers::pi / 6) < 1.1e-3);
        }
        for (auto& backend : optest::allBackends()) {
            CAPTURE(backend->name());
            float got = optest::runPixel(*backend->compile(passes::simplify(f)), {1000.0})[0];
            CHECK(got == doctest::Approx(sum).epsilon(1e-5));
        }
    }
}
