// Test-only helpers shared by the op-coverage tests (Ops_test.cpp, OpsPipeline_test.cpp):
// the classification of every op in Ops.def, and small runners for kernels.
//
// The table is deliberately explicit: adding an op to Ops.def makes `opTableIsComplete`
// fail until the op is classified here, and the classification decides which checks
// (semantics on every backend, constant folding, AD, the passes) the op is put through.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/IR.h"
#include "compiler/ir/Semantics.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <limits>
#include <vector>

namespace moire::optest {

using ir::Op;

enum class Kind {
    Leaf,        // no operands, valid in a kernel
    FrameLeaf,   // no operands, valid only before SplitFrame (time, param)
    Marker,      // AD markers, removed by the AD pass
    FloatUnary,  // f -> f, defined by evalFloat
    FloatBinary, // f, f -> f, defined by evalFloat
    PowI,        // f -> f with an integer exponent in iimm
    Select,      // b, T, T -> T
    Compare,     // f, f -> b, defined by evalCompare
    Logic,       // b (, b) -> b
    IntArith,    // i, i -> i (wrapping 32-bit)
    IntCompare,  // i, i -> b
    FToI,        // f -> i
    IToF,        // i -> f
    Control,     // if, loop, yield
    Sink,        // output
    Counter,     // tally: counted by the interpreter, ignored by other backends
};

struct Entry {
    Op op;
    Kind kind;
};

inline const std::vector<Entry>& opTable() {
    static const std::vector<Entry> table = {
        {Op::ConstF, Kind::Leaf},       {Op::ConstI, Kind::Leaf},
        {Op::ConstB, Kind::Leaf},       {Op::PixelX, Kind::Leaf},
        {Op::PixelY, Kind::Leaf},       {Op::ImageW, Kind::Leaf},
        {Op::ImageH, Kind::Leaf},       {Op::Time, Kind::FrameLeaf},
        {Op::Param, Kind::FrameLeaf},   {Op::Uniform, Kind::Leaf},
        {Op::Indep, Kind::Marker},      {Op::DerivX, Kind::Marker},
        {Op::DerivY, Kind::Marker},     {Op::Detach, Kind::Marker},
        {Op::Add, Kind::FloatBinary},   {Op::Sub, Kind::FloatBinary},
        {Op::Mul, Kind::FloatBinary},   {Op::MulZ, Kind::FloatBinary},
        {Op::Div, Kind::FloatBinary},   {Op::Neg, Kind::FloatUnary},
        {Op::Abs, Kind::FloatUnary},    {Op::Sign, Kind::FloatUnary},
        {Op::Floor, Kind::FloatUnary},  {Op::Round, Kind::FloatUnary},
        {Op::Fract, Kind::FloatUnary},  {Op::Mod, Kind::FloatBinary},
        {Op::Min, Kind::FloatBinary},   {Op::Max, Kind::FloatBinary},
        {Op::Sqrt, Kind::FloatUnary},   {Op::Exp, Kind::FloatUnary},
        {Op::Log, Kind::FloatUnary},    {Op::Pow, Kind::FloatBinary},
        {Op::PowI, Kind::PowI},         {Op::Sin, Kind::FloatUnary},
        {Op::Cos, Kind::FloatUnary},    {Op::Tan, Kind::FloatUnary},
        {Op::Asin, Kind::FloatUnary},   {Op::Acos, Kind::FloatUnary},
        {Op::Atan, Kind::FloatUnary},   {Op::Atan2, Kind::FloatBinary},
        {Op::Hypot, Kind::FloatBinary}, {Op::Select, Kind::Select},
        {Op::Lt, Kind::Compare},        {Op::Le, Kind::Compare},
        {Op::Gt, Kind::Compare},        {Op::Ge, Kind::Compare},
        {Op::Eq, Kind::Compare},        {Op::Ne, Kind::Compare},
        {Op::And, Kind::Logic},         {Op::Or, Kind::Logic},
        {Op::Not, Kind::Logic},         {Op::IAdd, Kind::IntArith},
        {Op::ISub, Kind::IntArith},     {Op::IMul, Kind::IntArith},
        {Op::ILt, Kind::IntCompare},    {Op::ILe, Kind::IntCompare},
        {Op::IEq, Kind::IntCompare},    {Op::FToI, Kind::FToI},
        {Op::IToF, Kind::IToF},         {Op::If, Kind::Control},
        {Op::Loop, Kind::Control},      {Op::Yield, Kind::Control},
        {Op::Output, Kind::Sink},       {Op::Tally, Kind::Counter},
    };
    return table;
}

inline Kind kindOf(Op op) {
    for (const Entry& e : opTable())
        if (e.op == op) return e.kind;
    FAIL("op '", ir::spelling(op), "' is missing from the op table (compiler/ir/OpTable_test.h)");
    return Kind::Leaf;
}

inline std::vector<Op> opsOfKind(std::initializer_list<Kind> kinds) {
    std::vector<Op> out;
    for (const Entry& e : opTable())
        if (std::find(kinds.begin(), kinds.end(), e.kind) != kinds.end()) out.push_back(e.op);
    return out;
}

// A function with `numOutputs` outputs built by `body(Builder&)`, verified.
template <class Body>
ir::Function build(int numOutputs, Body&& body) {
    ir::Function f;
    f.name = "test";
    f.numOutputs = numOutputs;
    ir::Builder b(f);
    body(b);
    ir::verify(f);
    return f;
}

// Runs `f` once on the reference interpreter, in double, and returns its outputs.
struct InterpInputs {
    std::vector<double> uniforms{}, params{};
    double time = 0.0, pixelX = 0.5, pixelY = 0.5, imageW = 1.0, imageH = 1.0;
};
inline std::vector<double> interpret(const ir::Function& f, const InterpInputs& in) {
    Interpreter interp(f);
    std::vector<double> out(f.numOutputs), regs;
    InterpEnv env;
    env.pixelX = in.pixelX;
    env.pixelY = in.pixelY;
    env.imageW = in.imageW;
    env.imageH = in.imageH;
    env.time = in.time;
    env.params = in.params.data();
    env.numParams = in.params.size();
    env.uniforms = in.uniforms.data();
    env.numUniforms = in.uniforms.size();
    env.outputs = out.data();
    interp.run(env, regs);
    return out;
}

// Runs a compiled kernel on a 1x1 image (its pixel centre at (0.5, 0.5)).
inline std::vector<float> runPixel(const CompiledKernel& k, const std::vector<double>& uniforms) {
    std::vector<float> out(k.numOutputs());
    KernelFrame frame;
    frame.uniforms = uniforms.data();
    frame.imageW = frame.imageH = 1;
    k.runTile(frame, TileRect{0, 0, 1, 1}, out.data(), out.size());
    return out;
}

// ---------------------------------------------------------------------------------------
// How closely the Vulkan backend must follow Semantics.h for a float op. A GPU's maths is
// not libm's, so it is held to what the Vulkan specification requires of the SPIR-V that the
// op's GLSL form (compiler/backend/glsl/GlslEmit.cpp) compiles to: the Vulkan spec's appendix
// "Precision and Operation of SPIR-V Instructions" (the trigonometric bounds are in its later
// versions; Vulkan 1.0 left them undefined), for single precision:
//   OpFAdd, OpFSub, OpFMul, comparisons, conversions: correctly rounded / exact;
//   OpFDiv: 2.5 ULP (for |b| in [2^-126, 2^126]);
//   exp: 3 + 2|x| ULP;  log: 3 ULP, or absolute 2^-21 for x in [0.5, 2];
//   pow(x, y): inherited from exp2(y log2 x);  sqrt: inherited from 1 / inversesqrt (2 ULP);
//   sin, cos: absolute 2^-11 on [-pi, pi] (and nothing outside; the GLSL form reduces the
//   argument by whole turns first);  tan: inherited from sin / cos;
//   asin, acos: inherited from atan2(x, sqrt(1 - x^2)), atan2(sqrt(1 - x^2), x);
//   atan, atan2: 4096 ULP;
//   any denormal may be flushed to zero.
// With SignedZeroInfNanPreserve (which the shader declares) infinities, NaN and the sign of
// zero are kept, so wherever Semantics.h gives one of them the GPU must give exactly it.
// "Inherited" bounds are worked out below from those of their parts, one ULP counted as
// 2^-23 of the value (the largest it is relative to the value).
// ---------------------------------------------------------------------------------------
constexpr double kUlp = 0x1p-23;
constexpr double kFloatMin = 0x1p-126; // below this a result may be flushed to zero
constexpr double kFloatMax = std::numeric_limits<float>::max();

// |got - exact| <= abs + rel |exact|; `any`: the spec asks for nothing here (sin of 1e30);
// neither: the op is made of correctly rounded instructions and must equal the float formula.
struct Precision {
    double abs = 0.0, rel = 0.0;
    bool any = false;
};

// The largest change of f(v) over v in [lo, hi] from f(mid), for f monotone on that range.
template <class F>
double spread(F f, double mid, double lo, double hi) {
    return std::max(std::fabs(f(lo) - f(mid)), std::fabs(f(hi) - f(mid)));
}

inline Precision vulkanPrecision(Op op, int64_t n, double a, double c) {
    // The GLSL form reduces sin/cos/tan arguments by whole turns exactly for |k| < 2^17 turns,
    // to within 2^-22 of [-pi, pi]; beyond that the spec bounds nothing.
    const double reducible = 131072.0 * 6.283185307179586, trig = 0x1p-11 + 0x1p-22;
    switch (op) {
    case Op::Div:
        return {0.0, 2.5 * kUlp};
    case Op::Sqrt: // 1 / inversesqrt(x): 2 ULP, then a division, 2.5 ULP
        return {0.0, 4.5 * kUlp};
    case Op::Exp:
        return {0.0, (3.0 + 2.0 * std::fabs(a)) * kUlp};
    case Op::Log: {
        double x = std::max(a, ir::kTiny);
        return x >= 0.5 && x <= 2.0 ? Precision{0x1p-21, 0.0} : Precision{0.0, 3.0 * kUlp};
    }
    case Op::Pow: { // exp2(t), t = y log2|x| rounded: exp2's 3 + 2|t| ULP, and t's own error
        double l = std::log2(std::fabs(a)), t = c * l, ax = std::fabs(a);
        double logErr = ax >= 0.5 && ax <= 2.0 ? 0x1p-21 : 3.0 * kUlp * std::fabs(l);
        double tErr = std::fabs(c) * logErr + std::fabs(t) * kUlp / 2;
        return {0.0, (3.0 + 2.0 * std::fabs(t)) * kUlp + std::expm1(std::log(2.0) * tErr)};
    }
    case Op::PowI: { // 1 / x (2.5 ULP) raised to |n| by multiplications, each rounded again
        if (n >= 0) return {};
        int mults = 0;
        for (uint64_t e = static_cast<uint64_t>(-n); e > 1; e >>= 1) mults += 1 + (e & 1);
        return {0.0, (2.5 * static_cast<double>(-n) + mults) * kUlp};
    }
    case Op::Sin:
    case Op::Cos:
        if (std::fabs(a) > reducible) return {0.0, 0.0, true};
        return {trig, 0.0};
    case Op::Tan: { // sin / cos, each within `trig`, then the division
        if (std::fabs(a) > reducible) return {0.0, 0.0, true};
        const double si = std::sin(a), co = std::cos(a);
        if (std::fabs(co) <= 2 * trig) return {0.0, 0.0, true}; // at a pole: no bound
        double worst = 0.0;
        for (double ds : {-trig, trig})
            for (double dc : {-trig, trig})
                worst = std::max(worst, std::fabs((si + ds) / (co + dc) - si / co));
        return {worst, 2.5 * kUlp};
    }
    case Op::Asin:
    case Op::Acos: {
        // atan2 (4096 ULP) of x and s = sqrt(1 - x^2), where s carries the roundings of x^2
        // and of 1 - x^2 (2^-24 each, of values that sum to 1) and the sqrt's 4.5 ULP; the
        // angle is monotone in s, so it moves at most to where the ends of s's range take it.
        const double x = std::clamp(a, -1.0, 1.0), d = 1.0 - x * x;
        auto angle = [&](double s) { return op == Op::Asin ? std::atan2(x, s) : std::atan2(s, x); };
        const double lo = std::sqrt(std::max(d - kUlp / 2, 0.0)) * (1 - 4.5 * kUlp);
        const double hi = std::sqrt(d + kUlp / 2) * (1 + 4.5 * kUlp);
        return {spread(angle, std::sqrt(d), lo, hi), 4096.0 * kUlp};
    }
    case Op::Atan:
    case Op::Atan2:
        return {0.0, 4096.0 * kUlp};
    case Op::Hypot: // sqrt(x^2 + y^2) of sides scaled by a power of two: sqrt 4.5, roundings
        return {0.0, 8.0 * kUlp};
    default:
        return {};
    }
}

// Equal, NaN to any NaN, the sign of zero included.
inline bool sameValue(double got, double want) {
    if (std::isnan(want)) return std::isnan(got);
    return got == want && std::signbit(got) == std::signbit(want);
}

// Whether `got`, from the Vulkan backend, is within the precision above for float op `op` at
// float inputs (a, c) (exponent `n` for powi).
inline bool withinVulkanPrecision(Op op, int64_t n, float a, float c, float got) {
    const float inF[3] = {a, c, 0.0f};
    // The exact value at the float inputs. Read through volatiles: GCC 12.2's SLP vectoriser
    // (-O2 and up) was seen to fold a pair of (double)(float)x conversions back to x, which
    // would move the reference to the unrounded inputs wherever this is inlined.
    volatile float va = a, vc = c;
    const double in[3] = {va, vc, 0.0};
    const float formula = ir::evalFloat<float>(op, inF, n);
    const double exact = ir::evalFloat<double>(op, in, n);
    const Precision p = vulkanPrecision(op, n, a, c);
    auto flushed = [&](double v) { return std::fabs(v) < kFloatMin && got == 0.0f; };
    if (op == Op::Mod) {
        // Inherited from a - b floor(a / b) with the product rounded (m_mod is `precise`): the
        // quotient may be 2.5 ULP off the exact one (3 from the rounded), or flushed if tiny,
        // so floor may land on a neighbouring integer.
        const float q = a / c;
        std::vector<float> quotients = {q};
        if (std::fabs(q) < kFloatMin) quotients.push_back(0.0f);
        for (float dir : {INFINITY, -INFINITY}) {
            float v = q;
            for (int i = 0; i < 3; ++i) quotients.push_back(v = std::nextafter(v, dir));
        }
        for (float k : quotients) {
            volatile float product = c * std::floor(k);
            if (sameValue(got, a - product)) return true;
        }
        return false;
    }
    if (!p.any && p.abs == 0.0 && p.rel == 0.0) // correctly rounded steps only
        return sameValue(got, formula) || flushed(formula);
    if (sameValue(got, static_cast<float>(exact)) || sameValue(got, formula)) return true;
    if (std::isnan(exact) || std::isnan(got)) return false;
    if (p.any) return true;
    if (flushed(exact)) return true;
    const double bound = p.abs + p.rel * std::fabs(exact);
    if (std::isinf(got)) // overflow, where the exact value is (or may round to) infinite
        return std::signbit(got) == std::signbit(exact) && std::fabs(exact) + bound >= kFloatMax;
    if (exact == 0.0 && p.abs == 0.0) return sameValue(got, exact);
    return std::fabs(got - exact) <= bound;
}

// Every backend available here; a missing one is skipped with a message. The JIT comes in
// each of its shapes: the host's lanes (as `moire` runs it), scalar, and 4 lanes (the SSE
// shape, chosen on hosts without AVX2), so every op is translated each way.
inline std::vector<std::unique_ptr<Backend>> allBackends() {
    std::vector<std::unique_ptr<Backend>> out;
    for (const std::string& name : test::availableBackends())
        if (auto b = test::makeBackendOrSkip(name)) out.push_back(std::move(b));
    for (int lanes : {1, 4}) {
        LlvmJitBackend::Options o;
        o.lanes = lanes;
        out.push_back(std::make_unique<LlvmJitBackend>(o));
    }
    return out;
}

} // namespace moire::optest
