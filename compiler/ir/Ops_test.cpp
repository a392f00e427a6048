// Every op is handled by every backend and by the constant folder, with the meaning that
// Semantics.h gives it: the interpreter exactly as evalFloat<double>, the JIT as
// evalFloat<float> (to within one rounding, since it calls the same libm in single
// precision), the Vulkan backend to the precision the Vulkan spec requires of the GPU's
// instructions (OpTable_test.h: exactly where they are correctly rounded), including at 0,
// -0, huge values, inf and NaN, which all three must give as Semantics.h does. Ops are taken
// from the explicit table in OpTable_test.h, whose completeness is checked first: an op added
// to Ops.def fails here until it is classified, and then the checks of its kind apply to it.
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/ir/Semantics.h"
#include "compiler/passes/Simplify.h"

#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <limits>
#include <map>
#include <random>

using namespace moire;
using namespace moire::ir;
using optest::build;
using optest::Kind;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const std::vector<double> kSpecial = {0.0, -0.0,  0.5,    -0.5, 1.0,   -1.0, 2.5,   -3.0,
                                      7.0, 100.0, -100.0, 1e30, -1e30, kInf, -kInf, kNaN};

// Equal including the sign of zero; any NaN equals any NaN.
bool same(double got, double want) {
    if (std::isnan(want)) return std::isnan(got);
    return got == want && std::signbit(got) == std::signbit(want);
}
// The JIT against evalFloat<float>: the same value to within one float rounding (libm's
// single-precision functions may be reached by a different call path), or within `ulps`
// units in the last place where the JIT calls libmvec (LlvmJitBackend::callsLibm).
bool sameFloat(float got, float want, int ulps = 1) {
    if (std::isnan(want) || std::isinf(want) || want == 0.0f) return same(got, want);
    return std::fabs(got - want) <= ulps * std::numeric_limits<float>::epsilon() * std::fabs(want);
}

// Folding a function whose operands are all constants must leave one constant per output
// (once the operands it no longer needs are dropped).
void checkFoldsAway(const Function& folded) {
    for (const Block& blk : passes::eliminateDeadCode(folded).blocks)
        for (const Inst& inst : blk.insts) {
            std::string opName = spelling(inst.op);
            CAPTURE(opName);
            CHECK((inst.op == Op::ConstF || inst.op == Op::Output));
        }
}

// The one output of `f(uniforms)` on every backend: the interpreter against `wantDouble`
// rounded to float, the JIT against `wantFloat` (within one rounding), and the Vulkan backend
// by `vulkanOk` (the precision the Vulkan spec requires, OpTable_test.h) or, for ops made
// only of exact instructions, exactly against `wantFloat`.
struct BackendCheck {
    std::vector<std::unique_ptr<Backend>> backends = optest::allBackends();
    std::vector<std::unique_ptr<CompiledKernel>> kernels;
    void compile(const Function& f) {
        kernels.clear();
        for (auto& b : backends) kernels.push_back(b->compile(f));
    }
    void check(const std::vector<double>& uniforms, double wantDouble, float wantFloat,
               const std::function<bool(float)>& vulkanOk = {}, int jitUlps = 1) {
        for (size_t i = 0; i < backends.size(); ++i) {
            const std::string name = backends[i]->name();
            CAPTURE(name);
            float got = optest::runPixel(*kernels[i], uniforms)[0];
            CAPTURE(got);
            if (name == "interp")
                CHECK(same(got, static_cast<float>(wantDouble)));
            else if (name == "jit")
                CHECK(sameFloat(got, wantFloat, jitUlps));
            else if (name == "vulkan")
                CHECK((vulkanOk ? vulkanOk(got) : same(got, wantFloat)));
            else
                FAIL("no precision rule for backend '", name, "': add one here");
        }
    }
};

} // namespace

TEST_CASE("every op in Ops.def is classified exactly once") {
    REQUIRE_MESSAGE(static_cast<int>(optest::opTable().size()) == kNumOps,
                    "Ops.def and compiler/ir/OpTable_test.h disagree: classify the new op there");
    for (int i = 0; i < kNumOps; ++i) {
        Op op = static_cast<Op>(i);
        std::string opName = spelling(op);
        CAPTURE(opName);
        int n = 0;
        for (const optest::Entry& e : optest::opTable()) n += e.op == op;
        CHECK(n == 1);
        Kind k = optest::kindOf(op);
        // The classification agrees with the op table and with Semantics.h.
        bool floatKind = k == Kind::FloatUnary || k == Kind::FloatBinary || k == Kind::PowI;
        CHECK(isFloatOp(op) == floatKind);
        CHECK(isCompareOp(op) == (k == Kind::Compare));
        CHECK(((opInfo(op).flags & flags::Leaf) != 0) == (k == Kind::Leaf || k == Kind::FrameLeaf));
        if (floatKind) {
            // evalFloat's default is NaN: an op it forgot would be NaN at ordinary inputs.
            double a[3] = {0.37, 0.61, 0.0};
            CHECK_FALSE(std::isnan(evalFloat<double>(op, a, 2)));
            CHECK(opInfo(op).numArgs == (k == Kind::FloatBinary ? 2 : 1));
        }
    }
}

// Kinds whose ops the tests below (and OpsPipeline_test.cpp) name one by one: a new op of
// one of these kinds needs its own check there, so its arrival fails here.
TEST_CASE("the ops checked one by one are all the ops of their kinds") {
    using V = std::vector<Op>;
    CHECK(optest::opsOfKind({Kind::Leaf}) == V{Op::ConstF, Op::ConstI, Op::ConstB, Op::PixelX,
                                               Op::PixelY, Op::ImageW, Op::ImageH, Op::Uniform});
    CHECK(optest::opsOfKind({Kind::FrameLeaf}) == V{Op::Time, Op::Param});
    CHECK(optest::opsOfKind({Kind::Marker}) == V{Op::Indep, Op::DerivX, Op::DerivY, Op::Detach});
    CHECK(optest::opsOfKind({Kind::Control}) == V{Op::If, Op::Loop, Op::Yield});
    CHECK(optest::opsOfKind({Kind::Sink}) == V{Op::Output});
    CHECK(optest::opsOfKind({Kind::Select, Kind::FToI, Kind::IToF}) ==
          V{Op::Select, Op::FToI, Op::IToF});
}

TEST_CASE(
    "float ops follow Semantics.h on the interpreter, the constant folder and every backend") {
    BackendCheck backends;
    const std::vector<int64_t> exponents = {0, 1, 2, 3, 5, 17, -1, -2, -3};
    for (Op op : optest::opsOfKind({Kind::FloatUnary, Kind::FloatBinary, Kind::PowI})) {
        std::string opName = spelling(op);
        CAPTURE(opName);
        const bool binary = opInfo(op).numArgs == 2;
        for (int64_t n : op == Op::PowI ? exponents : std::vector<int64_t>{0}) {
            CAPTURE(n);
            auto emitOp = [&](Builder& b, ValueId a, ValueId c) {
                return binary ? b.emit(op, {a, c}, 0.0, n) : b.emit(op, {a}, 0.0, n);
            };
            Function kernel =
                build(1, [&](Builder& b) { b.output(0, emitOp(b, b.uniform(0), b.uniform(1))); });
            backends.compile(kernel);
            // The special values pairwise, then random pairs of every sign and magnitude.
            std::vector<std::pair<double, double>> inputs;
            for (double a : kSpecial)
                for (double c : binary ? kSpecial : std::vector<double>{0.0})
                    inputs.push_back({a, c});
            std::mt19937 rng(7);
            std::uniform_real_distribution<double> mant(-1.0, 1.0), expo(-6.0, 6.0);
            auto random = [&] { return mant(rng) * std::pow(10.0, expo(rng)); };
            for (int i = 0; i < 64; ++i) inputs.push_back({random(), random()});
            for (auto [a, c] : inputs) {
                CAPTURE(a);
                CAPTURE(c);
                double in[3] = {a, c, 0.0};
                float inF[3] = {static_cast<float>(a), static_cast<float>(c), 0.0f};
                double want = evalFloat<double>(op, in, n);
                CHECK(same(optest::interpret(kernel, {{a, c}})[0], want));
                Function folded = passes::constantFold(build(
                    1, [&](Builder& b) { b.output(0, emitOp(b, b.constF(a), b.constF(c))); }));
                checkFoldsAway(folded);
                CHECK(same(optest::interpret(folded, {})[0], want));
                backends.check(
                    {a, c}, want, evalFloat<float>(op, inF, n),
                    [&](float got) {
                        return optest::withinVulkanPrecision(op, n, inF[0], inF[1], got);
                    },
                    LlvmJitBackend::callsLibm(op) ? 4 : 1);
            }
        }
    }
}

TEST_CASE("comparisons follow Semantics.h, NaN included") {
    BackendCheck backends;
    for (Op op : optest::opsOfKind({Kind::Compare})) {
        std::string opName = spelling(op);
        CAPTURE(opName);
        auto emitOp = [&](Builder& b, ValueId a, ValueId c) {
            return b.select(b.emit(op, {a, c}), b.constF(1.0), b.constF(0.0));
        };
        Function kernel =
            build(1, [&](Builder& b) { b.output(0, emitOp(b, b.uniform(0), b.uniform(1))); });
        backends.compile(kernel);
        for (double a : kSpecial)
            for (double c : kSpecial) {
                CAPTURE(a);
                CAPTURE(c);
                double want = evalCompare<double>(op, a, c) ? 1.0 : 0.0;
                CHECK(same(optest::interpret(kernel, {{a, c}})[0], want));
                Function folded = passes::constantFold(build(
                    1, [&](Builder& b) { b.output(0, emitOp(b, b.constF(a), b.constF(c))); }));
                checkFoldsAway(folded);
                CHECK(same(optest::interpret(folded, {})[0], want));
                float wantF = evalCompare<float>(op, static_cast<float>(a), static_cast<float>(c))
                                  ? 1.0f
                                  : 0.0f;
                backends.check({a, c}, want, wantF);
            }
    }
}

// Booleans and integers have no entry in Semantics.h; their expected values are written
// out here (C semantics; integers wrap at 32 bits).
TEST_CASE("boolean, integer and conversion ops agree with C semantics on every backend") {
    BackendCheck backends;
    auto boolOf = [](Builder& b, ValueId v) { return b.emit(Op::Ne, {v, b.constF(0.0)}); };
    auto asFloat = [](Builder& b, ValueId v) {
        Type t = b.function().type(v);
        return t == Type::B   ? b.select(v, b.constF(1.0), b.constF(0.0))
               : t == Type::I ? b.emit(Op::IToF, {v})
                              : v;
    };
    // op(operand(a), operand(c)) as a float, of uniforms or of constants.
    auto run = [&](Op op, const std::vector<std::pair<double, double>>& inputs, auto&& operand,
                   auto&& expected) {
        std::string opName = spelling(op);
        CAPTURE(opName);
        auto fn = [&](bool constants, double a, double c) {
            return build(1, [&](Builder& b) {
                ValueId x = operand(b, constants ? b.constF(a) : b.uniform(0));
                ValueId y = operand(b, constants ? b.constF(c) : b.uniform(1));
                b.output(
                    0, asFloat(b, opInfo(op).numArgs == 1 ? b.emit(op, {x}) : b.emit(op, {x, y})));
            });
        };
        Function kernel = fn(false, 0, 0);
        backends.compile(kernel);
        for (auto [a, c] : inputs) {
            CAPTURE(a);
            CAPTURE(c);
            double want = expected(a, c);
            CHECK(same(optest::interpret(kernel, {{a, c}})[0], want));
            Function folded = passes::constantFold(fn(true, a, c));
            checkFoldsAway(folded);
            CHECK(same(optest::interpret(folded, {})[0], want));
            backends.check({a, c}, want, static_cast<float>(want));
        }
    };
    // Expected values by op; every op of these kinds must have one.
    using Ref = std::function<double(double, double)>;
    auto wrap = [](int64_t v) { return double(static_cast<int32_t>(static_cast<uint32_t>(v))); };
    const std::map<Op, Ref> refs = {
        {Op::And, [](double a, double c) { return double(a != 0 && c != 0); }},
        {Op::Or, [](double a, double c) { return double(a != 0 || c != 0); }},
        {Op::Not, [](double a, double) { return double(a == 0); }},
        {Op::IAdd, [&](double a, double c) { return wrap(int64_t(a) + int64_t(c)); }},
        {Op::ISub, [&](double a, double c) { return wrap(int64_t(a) - int64_t(c)); }},
        {Op::IMul, [&](double a, double c) { return wrap(int64_t(a) * int64_t(c)); }},
        {Op::ILt, [](double a, double c) { return double(a < c); }},
        {Op::ILe, [](double a, double c) { return double(a <= c); }},
        {Op::IEq, [](double a, double c) { return double(a == c); }},
    };
    auto refOf = [&](Op op) {
        std::string opName = spelling(op);
        INFO("no expected values for '", opName, "': add them here");
        REQUIRE(refs.count(op) == 1);
        return refs.at(op);
    };
    const std::vector<std::pair<double, double>> bools = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
    for (Op op : optest::opsOfKind({Kind::Logic})) run(op, bools, boolOf, refOf(op));

    auto toInt = [](Builder& b, ValueId v) { return b.emit(Op::FToI, {v}); };
    const double big = 1 << 30;
    std::vector<std::pair<double, double>> ints;
    for (double a : {0.0, 1.0, -1.0, 7.0, -13.0, big, -big, 46341.0})
        for (double c : {0.0, 3.0, -13.0, big, 46341.0}) ints.push_back({a, c});
    for (Op op : optest::opsOfKind({Kind::IntArith, Kind::IntCompare}))
        run(op, ints, toInt, refOf(op));

    // ftoi: floor, clamped to +-2^30, NaN -> 0; itof back (exact for these values).
    std::vector<std::pair<double, double>> floats;
    for (double a : {0.5, -0.5, 2.9, -2.1, 3.0, 1e30, -1e30, kInf, -kInf, kNaN, 4.0 * big})
        floats.push_back({a, 0});
    auto ftoi = [&](double a) {
        return std::isnan(a) ? 0.0 : std::clamp(std::floor(a), -big, big);
    };
    auto id = [](Builder&, ValueId v) { return v; };
    run(Op::FToI, floats, id, [&](double a, double) { return ftoi(a); });
    run(Op::IToF, ints, toInt, [&](double a, double) { return a; });
}

TEST_CASE("select passes its chosen operand through unchanged, for every operand type") {
    BackendCheck backends;
    for (Type t : {Type::F, Type::I, Type::B}) {
        // select(c != 0, x, y) with x, y converted to type t, and the result back to float.
        auto selectFn = [&](double c, double x, double y, bool constants) {
            return build(1, [&](Builder& b) {
                auto in = [&](int slot, double v) {
                    return constants ? b.constF(v) : b.uniform(slot);
                };
                auto conv = [&](ValueId v) {
                    if (t == Type::I) return b.emit(Op::FToI, {v});
                    return t == Type::B ? b.emit(Op::Ne, {v, b.constF(0.0)}) : v;
                };
                ValueId r = b.select(b.emit(Op::Ne, {in(0, c), b.constF(0.0)}), conv(in(1, x)),
                                     conv(in(2, y)));
                if (t == Type::I) r = b.emit(Op::IToF, {r});
                if (t == Type::B) r = b.select(r, b.constF(1.0), b.constF(0.0));
                b.output(0, r);
            });
        };
        backends.compile(selectFn(0, 0, 0, false));
        for (double c : {0.0, 1.0, kNaN})
            for (double x : {-0.0, 2.0, kInf, kNaN})
                for (double y : {0.0, -5.0, -kInf}) {
                    CAPTURE(c);
                    CAPTURE(x);
                    CAPTURE(y);
                    double pick = c != 0.0 ? x : y; // NaN != 0: a NaN condition is true
                    double want = t == Type::F   ? pick
                                  : t == Type::B ? double(pick != 0.0)
                                                 : semFToI(pick);
                    CHECK(same(optest::interpret(selectFn(0, 0, 0, false), {{c, x, y}})[0], want));
                    Function folded = passes::constantFold(selectFn(c, x, y, true));
                    checkFoldsAway(folded);
                    CHECK(same(optest::interpret(folded, {})[0], want));
                    backends.check({c, x, y}, want, static_cast<float>(want));
                }
    }
}

TEST_CASE("leaves read the pixel, the image, constants and uniforms on every backend") {
    const std::vector<double> uniforms = {1.25, 99.0, -3.5};
    Function f = build(8, [&](Builder& b) {
        b.output(0, b.leaf(Op::PixelX));
        b.output(1, b.leaf(Op::PixelY));
        b.output(2, b.leaf(Op::ImageW));
        b.output(3, b.leaf(Op::ImageH));
        b.output(4, b.add(b.uniform(2), b.constF(-0.5)));                    // -4
        b.output(5, b.emit(Op::IToF, {b.constI(-7)}));                       // -7
        b.output(6, b.select(b.constB(true), b.uniform(0), b.constF(1e30))); // 1.25
        b.output(7, b.emit(Op::Indep, {b.uniform(0)}, 0.0, 1)); // indep is the identity
    });
    const TileRect tile{2, 3, 5, 5};
    const int w = 9, h = 7, n = f.numOutputs, cols = tile.x1 - tile.x0;
    for (auto& backend : optest::allBackends()) {
        CAPTURE(backend->name());
        auto k = backend->compile(f);
        std::vector<float> out(static_cast<size_t>(cols * (tile.y1 - tile.y0) * n), kNaN);
        KernelFrame frame{uniforms.data(), w, h};
        k->runTile(frame, tile, out.data(), static_cast<size_t>(cols * n));
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const float* p =
                    &out[static_cast<size_t>(((y - tile.y0) * cols + (x - tile.x0)) * n)];
                CAPTURE(x);
                CAPTURE(y);
                CHECK(p[0] == x + 0.5f);
                CHECK(p[1] == y + 0.5f);
                CHECK(p[2] == w);
                CHECK(p[3] == h);
                CHECK(p[4] == -4.0f);
                CHECK(p[5] == -7.0f);
                CHECK(p[6] == 1.25f);
                CHECK(p[7] == 1.25f);
            }
    }
    // time and param exist only in the frame program, which the interpreter runs.
    Function frame = build(2, [](Builder& b) {
        b.output(0, b.leaf(Op::Time));
        b.output(1, b.param(1));
    });
    optest::InterpInputs in;
    in.time = 2.5;
    in.params = {0.0, 4.5};
    CHECK(optest::interpret(frame, in) == std::vector<double>{2.5, 4.5});
}

// sum_{k=1}^{n} 1/k^2 over odd k only, by a loop whose body holds an if: both control-flow
// ops, their yields, and an integer and a float carried value.
TEST_CASE("if, loop and yield run the same on every backend") {
    Function f = build(2, [](Builder& b) {
        ValueId n = b.emit(Op::FToI, {b.uniform(0)});
        auto res = b.loop(
            {b.constI(1), b.constF(0.0)},
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.emit(Op::ILe, {p[0], n})};
            },
            [&](std::span<const ValueId> p) {
                ValueId k = b.emit(Op::IToF, {p[0]});
                ValueId odd =
                    b.emit(Op::Ne, {b.emit(Op::Fract, {b.mul(k, b.constF(0.5))}), b.constF(0.0)});
                auto term = b.ifThenElse(
                    odd, [&] { return std::vector<ValueId>{b.div(b.constF(1.0), b.mul(k, k))}; },
                    [&] { return std::vector<ValueId>{b.constF(0.0)}; });
                return std::vector<ValueId>{b.emit(Op::IAdd, {p[0], b.constI(1)}),
                                            b.add(p[1], term[0])};
            });
        b.output(0, res[1]);
        b.output(1, b.emit(Op::IToF, {res[0]}));
    });
    auto backends = optest::allBackends();
    std::vector<std::unique_ptr<CompiledKernel>> kernels;
    for (auto& backend : backends) kernels.push_back(backend->compile(f));
    for (int n : {0, 1, 2, 7, 40}) {
        CAPTURE(n);
        double sum = 0.0;
        float sumF = 0.0f;
        for (int k = 1; k <= n; k += 2) {
            sum += 1.0 / (double(k) * k);
            sumF += 1.0f / (float(k) * float(k));
        }
        std::vector<double> exact = optest::interpret(f, {{double(n)}});
        CHECK(same(exact[0], sum));
        CHECK(exact[1] == n + 1);
        for (size_t i = 0; i < backends.size(); ++i) {
            CAPTURE(backends[i]->name());
            std::vector<float> got = optest::runPixel(*kernels[i], {double(n)});
            if (backends[i]->name() == "vulkan") {
                // Each term's division may be 2.5 ULP off (Vulkan's OpFDiv), and then each
                // partial sum may round the other way: one ULP of the sum per term.
                const double terms = (n + 1) / 2;
                CHECK(std::fabs(got[0] - sumF) <= (2.5 + terms) * optest::kUlp * sumF);
            } else {
                CHECK(sameFloat(got[0],
                                backends[i]->name() == "interp" ? static_cast<float>(sum) : sumF));
            }
            CHECK(got[1] == n + 1);
        }
    }
}

TEST_CASE("ops: tally counts on the interpreter and costs nothing elsewhere") {
    // A loop of 5 iterations with a tally in its body, and one more tally outside it.
    Function f = build(1, [](Builder& b) {
        auto res = b.loop(
            {b.constF(0.0)},
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.lt(p[0], b.constF(5.0))};
            },
            [&](std::span<const ValueId> p) {
                b.emitSink(Op::Tally, {}, 2);
                return std::vector<ValueId>{b.add(p[0], b.constF(1.0))};
            });
        b.emitSink(Op::Tally, {}, 0);
        b.output(0, res[0]);
    });
    optest::InterpInputs in;
    CHECK(optest::interpret(f, in)[0] == 5.0);
    CHECK(Interpreter::lastTally(2) == 5);
    CHECK(Interpreter::lastTally(0) == 1);
    CHECK(Interpreter::lastTally(1) == 0);
    // A second run starts its counts again.
    optest::interpret(f, in);
    CHECK(Interpreter::lastTally(2) == 5);
    for (auto& backend : optest::allBackends()) {
        CAPTURE(backend->name());
        CHECK(optest::runPixel(*backend->compile(passes::simplify(f)), {})[0] == 5.0f);
    }
}
