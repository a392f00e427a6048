// The JIT in lanes (Translator.h) computes, pixel by pixel, what the scalar JIT computes,
// where neighbouring pixels take different arms of an `if` and run a `loop` different numbers
// of times; and both agree with the reference interpreter. Kernels here call no libm function
// on values that differ from lane to lane, so lanes and scalar code must agree bit for bit
// (libmvec may round apart from libm; a call on a value the same in every lane is libm's).
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/ir/OpTable_test.h"

#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <random>

using namespace moire;
using ir::Builder;
using ir::Op;
using ir::ValueId;

namespace {

constexpr float kUnwritten = -7.0f;

// The pixel's column as an exact integer-valued float (x - 1/2), so the control decisions
// below are the same in float and double.
ValueId column(Builder& b) {
    return b.sub(b.leaf(Op::PixelX), b.constF(0.5));
}
ValueId modF(Builder& b, ValueId a, double m) {
    return b.emit(Op::Mod, {a, b.constF(m)});
}

// Divergent loops and expensive arms: a loop run (column mod 9) times whose body holds an
// `if` whose one arm runs a nested loop, and an output written only in one arm of an `if`.
ir::Function divergentLoops() {
    return optest::build(3, [](Builder& b) {
        ValueId col = column(b), row = b.sub(b.leaf(Op::PixelY), b.constF(0.5));
        ValueId scale = b.uniform(0);
        ValueId n = b.emit(Op::FToI, {b.add(modF(b, col, 9.0), modF(b, row, 2.0))});
        auto loop = b.loop(
            {b.constI(0), b.constF(0.25), b.constB(false)},
            [&](std::span<const ValueId> c) {
                return std::vector<ValueId>{b.emit(Op::ILt, {c[0], n})};
            },
            [&](std::span<const ValueId> c) {
                ValueId i = c[0], acc = c[1];
                ValueId big = b.gt(acc, b.constF(1.5));
                auto arm = b.ifThenElse(
                    big,
                    [&] {
                        // sum of k * 0.5 for k < i, by a loop
                        auto inner = b.loop(
                            {b.constI(0), b.constF(0.0)},
                            [&](std::span<const ValueId> d) {
                                return std::vector<ValueId>{b.emit(Op::ILt, {d[0], i})};
                            },
                            [&](std::span<const ValueId> d) {
                                ValueId k = b.emit(Op::IToF, {d[0]});
                                return std::vector<ValueId>{b.emit(Op::IAdd, {d[0], b.constI(1)}),
                                                            b.add(d[1], b.mul(k, b.constF(0.5)))};
                            });
                        return std::vector<ValueId>{b.div(inner[1], b.add(acc, scale))};
                    },
                    [&] { return std::vector<ValueId>{b.mul(acc, b.constF(0.75))}; });
                ValueId next = b.add(b.sqrt(b.add(acc, b.mul(col, scale))), arm[0]);
                return std::vector<ValueId>{b.emit(Op::IAdd, {i, b.constI(1)}), next,
                                            b.emit(Op::Or, {c[2], big})};
            });
        b.output(0, loop[1]);
        ValueId third = b.lt(modF(b, col, 3.0), b.constF(1.0));
        auto picked = b.ifThenElse(
            third,
            [&] {
                auto steps = b.loop(
                    {b.constF(0.0)},
                    [&](std::span<const ValueId> c) {
                        return std::vector<ValueId>{b.lt(c[0], modF(b, col, 5.0))};
                    },
                    [&](std::span<const ValueId> c) {
                        return std::vector<ValueId>{b.add(c[0], b.constF(1.0))};
                    });
                b.output(2, b.add(steps[0], b.mul(row, b.constF(0.125))));
                return std::vector<ValueId>{steps[0]};
            },
            [&] { return std::vector<ValueId>{b.neg(col)}; });
        b.output(1, b.add(picked[0], b.select(loop[2], b.constF(100.0), b.constF(0.0))));
    });
}

// Short arms, run for every lane and merged by selects: ints, bools and an output written
// in one of them.
ir::Function cheapArms() {
    return optest::build(2, [](Builder& b) {
        ValueId col = column(b);
        ValueId odd = b.gt(modF(b, col, 2.0), b.constF(0.5));
        auto r = b.ifThenElse(
            odd,
            [&] {
                b.output(1, b.mul(col, b.constF(3.0)));
                return std::vector<ValueId>{b.constI(7), b.constB(true), b.add(col, b.constF(1))};
            },
            [&] {
                return std::vector<ValueId>{b.emit(Op::FToI, {col}), b.constB(false),
                                            b.div(b.constF(1.0), b.add(col, b.constF(2)))};
            });
        ValueId asF = b.emit(Op::IToF, {r[0]});
        b.output(0, b.add(b.select(r[1], asF, b.neg(asF)), r[2]));
    });
}

std::vector<float> runTile(const CompiledKernel& k, TileRect t, const std::vector<double>& u) {
    int w = t.x1 - t.x0, h = t.y1 - t.y0, n = k.numOutputs();
    std::vector<float> out(static_cast<size_t>(w) * h * n, kUnwritten);
    KernelFrame frame{u.data(), 64, 64};
    k.runTile(frame, t, out.data(), static_cast<size_t>(w) * n);
    return out;
}

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every pixel of `tile` from the JIT in `lanes` against the scalar JIT (bit for bit) and
// the interpreter (to float precision; a slot the interpreter's pixel did not write must
// still hold what the buffer held).
void checkTile(const ir::Function& f, TileRect tile, unsigned lanes,
               const std::function<bool(int slot, double x)>& written) {
    LlvmJitBackend::Options scalarOptions, laneOptions;
    scalarOptions.lanes = 1;
    laneOptions.lanes = static_cast<int>(lanes);
    LlvmJitBackend scalar(scalarOptions), wide(laneOptions);
    REQUIRE(wide.lanes() == lanes);
    const std::vector<double> u = {0.375};
    std::vector<float> want = runTile(*scalar.compile(f), tile, u);
    std::vector<float> got = runTile(*wide.compile(f), tile, u);
    const int n = f.numOutputs, w = tile.x1 - tile.x0;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            optest::InterpInputs in;
            in.uniforms = u;
            in.pixelX = x + 0.5;
            in.pixelY = y + 0.5;
            in.imageW = in.imageH = 64;
            std::vector<double> exact = optest::interpret(f, in);
            for (int s = 0; s < n; ++s) {
                size_t i = (static_cast<size_t>(y - tile.y0) * w + (x - tile.x0)) * n + s;
                CAPTURE(lanes);
                CAPTURE(x);
                CAPTURE(y);
                CAPTURE(s);
                CAPTURE(got[i]);
                CAPTURE(want[i]);
                CHECK(sameBits(got[i], want[i]));
                if (!written(s, x))
                    CHECK(got[i] == kUnwritten);
                else
                    CHECK(std::fabs(got[i] - exact[s]) <=
                          1e-5 * std::max(1.0, std::fabs(exact[s])));
            }
        }
}

const std::vector<TileRect> kTiles = {
    {0, 0, 1, 1},         // one pixel: every lane but the first past the tile
    {3, 2, 3 + 37, 4},    // an odd width from an odd column: a short last run
    {16, 1, 16 + 32, 2}}; // whole runs only

} // namespace

TEST_CASE("jit lanes: divergent loops and arms give each pixel its scalar value") {
    ir::Function f = divergentLoops();
    for (unsigned lanes : {4u, 8u, 16u})
        for (TileRect t : kTiles)
            checkTile(f, t, lanes, [](int slot, double x) {
                return slot != 2 || std::fmod(x, 3.0) < 1.0; // slot 2: only where third holds
            });
}

TEST_CASE("jit lanes: short arms run for every lane and merge by selects") {
    ir::Function f = cheapArms();
    for (unsigned lanes : {4u, 8u, 16u})
        for (TileRect t : kTiles)
            checkTile(f, t, lanes, [](int slot, double x) {
                return slot != 1 || std::fmod(x, 2.0) > 0.5; // slot 1: odd columns only
            });
}

TEST_CASE("jit lanes: the host's lane count is a SIMD width, and 1 is scalar") {
    LlvmJitBackend host;
    CHECK((host.lanes() == 4 || host.lanes() == 8 || host.lanes() == 16));
    LlvmJitBackend::Options o;
    o.lanes = 1;
    CHECK(LlvmJitBackend(o).lanes() == 1);
}

// hypot is computed as sqrt(x^2 + y^2) with power-of-two scaling where the squares would
// overflow or underflow: within one float rounding of the exact value (std::hypot in double,
// rounded) across float's range, at the scaling thresholds, and with inf and NaN as hypotf.
TEST_CASE("jit hypot: one rounding of the exact value from subnormals to the float maximum") {
    ir::Function f =
        optest::build(1, [](Builder& b) { b.output(0, b.hypot(b.uniform(0), b.uniform(1))); });
    std::vector<double> values = {
        0.0,    1.0,  3.0,  0x1p60,         0x1.000002p60, 0x1p-60, 0x1.fffffep-61, 0x1p-149, 1e-40,
        3.4e38, 1e30, -7.5, 0x1.fffffep127, 1e-30,         0.1};
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> mant(0.5, 1.0), expo(-140.0, 127.0);
    for (int i = 0; i < 120; ++i) values.push_back(std::ldexp(mant(rng), int(expo(rng))));
    for (int lanes : {1, 4, LlvmJitBackend::Options::kHostLanes}) {
        LlvmJitBackend::Options o;
        o.lanes = lanes;
        LlvmJitBackend jit(o);
        auto k = jit.compile(f);
        for (size_t i = 0; i < values.size(); ++i)
            for (size_t j = i; j < values.size(); j += 7) {
                float a = static_cast<float>(values[i]), c = static_cast<float>(values[j]);
                float want = static_cast<float>(std::hypot(double(a), double(c)));
                float got = optest::runPixel(*k, {a, c})[0];
                CAPTURE(lanes);
                CAPTURE(a);
                CAPTURE(c);
                CAPTURE(got);
                CAPTURE(want);
                CHECK((got == want ||
                       std::fabs(got - want) <= std::nextafter(want, INFINITY) - want));
            }
        const float inf = INFINITY, nan = NAN;
        CHECK(optest::runPixel(*k, {inf, nan})[0] == inf);
        CHECK(optest::runPixel(*k, {nan, -inf})[0] == inf);
        CHECK(std::isnan(optest::runPixel(*k, {nan, 2.0})[0]));
        CHECK(optest::runPixel(*k, {0.0, -0.0})[0] == 0.0f);
    }
}

// A maths call whose arguments are the same in every lane (the row, a uniform) is one call of
// the scalar function, splatted: the code in lanes calls sinf, not libmvec, for it (and so
// gives scalar code's bits), also inside a divergent arm; a call on the column stays in lanes.
TEST_CASE("jit lanes: maths of a row's or a frame's value is one scalar call") {
    ir::Function invariant = optest::build(3, [](Builder& b) {
        ValueId row = b.sub(b.leaf(Op::PixelY), b.constF(0.5)), u = b.uniform(0);
        b.output(0, b.emit(Op::Sin, {b.mul(row, u)}));
        b.output(1, b.emit(Op::Atan2, {row, b.add(u, b.constF(1.0))}));
        ValueId odd = b.gt(modF(b, column(b), 2.0), b.constF(0.5));
        auto arm = b.ifThenElse(
            odd, [&] { return std::vector<ValueId>{b.emit(Op::Cos, {b.mul(u, row)})}; },
            [&] { return std::vector<ValueId>{b.constF(2.0)}; });
        b.output(2, arm[0]);
    });
    ir::Function varying = optest::build(
        1, [](Builder& b) { b.output(0, b.emit(Op::Sin, {b.mul(column(b), b.uniform(0))})); });
    for (unsigned lanes : {4u, 8u, 16u}) {
        LlvmJitBackend::Options o;
        o.lanes = static_cast<int>(lanes);
        LlvmJitBackend wide(o);
        CAPTURE(lanes);
        const std::string code = wide.dumpLlvm(invariant);
        CHECK(code.find("@_ZGV") == std::string::npos);
        CHECK(code.find("call float @sinf(") != std::string::npos);
        CHECK(code.find("call float @atan2f(") != std::string::npos);
        CHECK(code.find("call float @cosf(") != std::string::npos);
        // The column's sine: libmvec, or without it one scalar call per lane; never one call.
        const std::string column = wide.dumpLlvm(varying);
        size_t scalarCalls = 0;
        for (size_t at = 0; (at = column.find("call float @sinf(", at)) != std::string::npos; ++at)
            ++scalarCalls;
        CHECK((column.find("@_ZGV") != std::string::npos || scalarCalls == lanes));
        for (TileRect t : kTiles) checkTile(invariant, t, lanes, [](int, double) { return true; });
    }
}
