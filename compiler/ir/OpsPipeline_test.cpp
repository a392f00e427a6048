// Every op through the whole middle and back end, the way a scene takes it: a small scene
// function that uses the op on two independent inputs (through `indep`) and asks for its
// gradient (through `deriv.x` / `deriv.y`) is simplified, differentiated, simplified, split
// into frame program and kernel, and run on every backend. Expectations are independent of
// the passes: the value is the unoptimised function on the interpreter, the gradient is a
// finite difference of it. So an op that the AD pass, a cleanup pass, SplitFrame or a
// backend mishandles fails here. The printer and the verifier are checked at the end.
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/passes/AutoDiff.h"
#include "compiler/passes/Simplify.h"
#include "compiler/passes/SplitFrame.h"

#include <cmath>
#include <doctest/doctest.h>

using namespace moire;
using namespace moire::ir;
using optest::Kind;

namespace {

// A differentiable float expression of (a, c) that uses `op`.
ValueId sample(Builder& b, Op op, ValueId a, ValueId c) {
    auto toInt = [&](ValueId v) { return b.emit(Op::FToI, {b.mul(v, b.constF(10.0))}); };
    auto pick = [&](ValueId cond) { return b.select(cond, b.mul(a, c), b.sub(a, c)); };
    switch (optest::kindOf(op)) {
    case Kind::FloatUnary:
        return b.emit(op, {a});
    case Kind::FloatBinary:
        return b.emit(op, {a, c});
    case Kind::PowI:
        return b.add(b.powi(a, 3), b.powi(c, -2));
    case Kind::Select:
        return b.select(b.gt(c, a), b.sin(a), c);
    case Kind::Compare:
        return pick(b.emit(op, {a, c}));
    case Kind::Logic: {
        ValueId p = b.lt(a, c), q = b.gt(c, b.constF(0.0));
        return pick(op == Op::Not ? b.emit(op, {p}) : b.emit(op, {p, q}));
    }
    case Kind::IntArith:
        return b.add(b.emit(Op::IToF, {b.emit(op, {toInt(a), toInt(c)})}), b.mul(a, c));
    case Kind::IntCompare:
        return pick(b.emit(op, {toInt(a), toInt(c)}));
    case Kind::FToI:
    case Kind::IToF:
        return b.add(b.emit(Op::IToF, {toInt(a)}), b.mul(a, c));
    case Kind::Leaf:
        switch (op) {
        case Op::ConstF:
            return b.mul(a, b.constF(2.5));
        case Op::ConstI:
            return b.mul(b.emit(Op::IToF, {b.constI(3)}), a);
        case Op::ConstB:
            return pick(b.constB(false));
        case Op::Uniform:
            return b.mul(a, b.mul(b.uniform(0), c));
        default:
            return b.mul(b.add(a, b.leaf(op)), c); // pixel.x/y, image.w/h
        }
    case Kind::FrameLeaf:
        return op == Op::Time ? b.add(a, b.mul(b.leaf(Op::Time), c))
                              : b.mul(a, b.mul(b.param(2), c));
    case Kind::Control:
        if (op == Op::Loop) {
            // acc = acc * a + sin(c), three times, from acc = c.
            auto res = b.loop(
                {b.constI(0), c},
                [&](std::span<const ValueId> p) {
                    return std::vector<ValueId>{b.emit(Op::ILt, {p[0], b.constI(3)})};
                },
                [&](std::span<const ValueId> p) {
                    return std::vector<ValueId>{b.emit(Op::IAdd, {p[0], b.constI(1)}),
                                                b.add(b.mul(p[1], a), b.sin(c))};
                });
            return res[1];
        }
        return b.ifThenElse(
            b.lt(a, c), [&] { return std::vector<ValueId>{b.mul(a, c)}; },
            [&] { return std::vector<ValueId>{b.sub(b.emit(Op::Exp, {a}), c)}; })[0];
    case Kind::Counter: // must survive every pass: the kernel keeps it
        b.emitSink(Op::Tally, {}, 1);
        return b.mul(b.sin(a), c);
    case Kind::Marker: // indep, deriv.x and deriv.y are in every scene built below
        // detach of a value that does not vary (so that finite differences agree with AD)
        if (op == Op::Detach) return b.mul(b.sin(a), b.add(c, b.emit(op, {b.param(2)})));
        return b.mul(b.sin(a), c);
    case Kind::Sink: // output is in every scene too
        return b.mul(b.sin(a), c);
    }
    return kNoValue;
}

// out0 = sample(a, c) with a, c the independent variables, read from params 0 and 1 and
// varying with the pixel (so that they reach the kernel); with `derivs`, out1 and out2
// are its partials.
Function scene(Op op, bool derivs) {
    Function f;
    f.name = "scene";
    f.numOutputs = derivs ? 3 : 1;
    Builder b(f);
    auto input = [&](int i, Op pixel) {
        ValueId offset = b.sub(b.leaf(pixel), b.constF(0.5)); // 0 at the pixel of a 1x1 image
        return b.emit(Op::Indep, {b.add(b.param(i), offset)}, 0.0, i);
    };
    ValueId a = input(0, Op::PixelX), c = input(1, Op::PixelY);
    ValueId r = sample(b, op, a, c);
    b.output(0, r);
    if (derivs) {
        b.output(1, b.emit(Op::DerivX, {r}));
        b.output(2, b.emit(Op::DerivY, {r}));
    }
    verify(f);
    return f;
}

optest::InterpInputs inputsAt(double a, double c) {
    optest::InterpInputs in;
    in.params = {a, c, 1.7};
    in.uniforms = {1.9};
    in.time = 0.9;
    return in;
}

bool contains(const Function& f, Op op) {
    for (const Block& blk : f.blocks)
        for (const Inst& inst : blk.insts)
            if (inst.op == op) return true;
    return false;
}

// How close a backend's float outputs must come to the exact value (relative, or absolute
// below 1). The interpreter is double throughout; the JIT is float with the same libm; the
// Vulkan backend is float with the GPU's maths, held to twice the loosest bound the Vulkan
// spec allows one instruction, 2^-11 (atan, asin, acos: 4096 ULP; sin, cos: absolute), as a
// value or its derivative passes through up to two of them. (Measured on lavapipe: acos at
// 1.2e-4, everything else below 2e-6.)
double tolerance(const std::string& backend) {
    if (backend == "interp") return 1e-6;
    if (backend == "jit") return 1e-4;
    if (backend == "vulkan") return 0x1p-10;
    FAIL("no tolerance for backend '", backend, "': add one here");
    return 0.0;
}

bool close(double got, double want, double rel) {
    return std::fabs(got - want) <= rel * std::max(std::fabs(want), 1.0);
}

} // namespace

TEST_CASE("every op survives AD, the cleanup passes, SplitFrame and every backend") {
    auto backends = optest::allBackends();
    const std::pair<double, double> points[] = {{0.37, 0.61}, {-1.33, 0.47}, {2.21, -0.83}};
    for (const optest::Entry& e : optest::opTable()) {
        std::string opName = spelling(e.op);
        CAPTURE(opName);
        Function withDerivs = scene(e.op, true);
        Function valueOnly = scene(e.op, false);
        // The compiler's order (Compile.cpp): simplify, AD, simplify, split, simplify.
        Function raw = passes::autoDiff(withDerivs);
        Function derived = passes::simplify(passes::autoDiff(passes::simplify(withDerivs)));
        for (Op marker : {Op::Indep, Op::DerivX, Op::DerivY, Op::Detach})
            CHECK_FALSE(contains(derived, marker));
        passes::FrameSplit split = passes::splitFrame(derived, 3);
        Function kernel = passes::simplify(split.kernel);
        for (Op frameOnly : {Op::Time, Op::Param}) CHECK_FALSE(contains(kernel, frameOnly));
        std::vector<std::unique_ptr<CompiledKernel>> kernels;
        for (auto& backend : backends) kernels.push_back(backend->compile(kernel));

        int checked = 0;
        for (auto [a, c] : points) {
            CAPTURE(a);
            CAPTURE(c);
            double value = optest::interpret(valueOnly, inputsAt(a, c))[0];
            if (std::isnan(value)) continue; // pow of a negative base
            ++checked;
            // Fourth-order central differences of the unoptimised value.
            const double h = 1e-4;
            auto fd = [&](double da, double dc) {
                auto v = [&](double k) {
                    return optest::interpret(valueOnly,
                                             inputsAt(a + k * h * da, c + k * h * dc))[0];
                };
                return (v(-2) - 8 * v(-1) + 8 * v(1) - v(2)) / (12 * h);
            };
            const double want[3] = {value, fd(1, 0), fd(0, 1)};
            std::vector<double> got = optest::interpret(raw, inputsAt(a, c));
            std::vector<double> opt = optest::interpret(derived, inputsAt(a, c));
            for (int k = 0; k < 3; ++k) {
                CAPTURE(k);
                CHECK(close(got[k], want[k], 1e-6));
                CHECK(close(opt[k], got[k], 1e-12));
            }
            std::vector<double> frame = optest::interpret(split.frame, inputsAt(a, c));
            std::vector<double> uniforms(frame.begin(), frame.begin() + split.numUniforms);
            std::vector<double> exact = optest::interpret(kernel, {uniforms});
            for (int k = 0; k < 3; ++k) CHECK(close(exact[k], got[k], 1e-12));
            for (size_t i = 0; i < backends.size(); ++i) {
                CAPTURE(backends[i]->name());
                std::vector<float> out = optest::runPixel(*kernels[i], uniforms);
                double rel = tolerance(backends[i]->name());
                for (int k = 0; k < 3; ++k) {
                    CAPTURE(k);
                    CHECK(close(out[k], got[k], rel));
                }
            }
        }
        CHECK(checked >= 2);
    }
}

TEST_CASE("the printer spells every op") {
    for (const optest::Entry& e : optest::opTable()) {
        std::string opName = spelling(e.op);
        CAPTURE(opName);
        std::string text = print(scene(e.op, true));
        CAPTURE(text);
        CHECK((text.find(" " + opName + " ") != std::string::npos ||
               text.find(" " + opName + "\n") != std::string::npos));
    }
}
