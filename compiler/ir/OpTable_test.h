// Test-only helpers shared by the op-coverage tests (Ops_test.cpp, OpsPipeline_test.cpp):
// the classification of every op in Ops.def, and small runners for kernels.
//
// The table is deliberately explicit: adding an op to Ops.def makes `opTableIsComplete`
// fail until the op is classified here, and the classification decides which checks
// (semantics on every backend, constant folding, AD, the passes) the op is put through.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/IR.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
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
        {Op::DerivY, Kind::Marker},     {Op::Add, Kind::FloatBinary},
        {Op::Sub, Kind::FloatBinary},   {Op::Mul, Kind::FloatBinary},
        {Op::MulZ, Kind::FloatBinary},  {Op::Div, Kind::FloatBinary},
        {Op::Neg, Kind::FloatUnary},    {Op::Abs, Kind::FloatUnary},
        {Op::Sign, Kind::FloatUnary},   {Op::Floor, Kind::FloatUnary},
        {Op::Round, Kind::FloatUnary},  {Op::Fract, Kind::FloatUnary},
        {Op::Mod, Kind::FloatBinary},   {Op::Min, Kind::FloatBinary},
        {Op::Max, Kind::FloatBinary},   {Op::Sqrt, Kind::FloatUnary},
        {Op::Exp, Kind::FloatUnary},    {Op::Log, Kind::FloatUnary},
        {Op::Pow, Kind::FloatBinary},   {Op::PowI, Kind::PowI},
        {Op::Sin, Kind::FloatUnary},    {Op::Cos, Kind::FloatUnary},
        {Op::Tan, Kind::FloatUnary},    {Op::Asin, Kind::FloatUnary},
        {Op::Acos, Kind::FloatUnary},   {Op::Atan, Kind::FloatUnary},
        {Op::Atan2, Kind::FloatBinary}, {Op::Hypot, Kind::FloatBinary},
        {Op::Select, Kind::Select},     {Op::Lt, Kind::Compare},
        {Op::Le, Kind::Compare},        {Op::Gt, Kind::Compare},
        {Op::Ge, Kind::Compare},        {Op::Eq, Kind::Compare},
        {Op::Ne, Kind::Compare},        {Op::And, Kind::Logic},
        {Op::Or, Kind::Logic},          {Op::Not, Kind::Logic},
        {Op::IAdd, Kind::IntArith},     {Op::ISub, Kind::IntArith},
        {Op::IMul, Kind::IntArith},     {Op::ILt, Kind::IntCompare},
        {Op::ILe, Kind::IntCompare},    {Op::IEq, Kind::IntCompare},
        {Op::FToI, Kind::FToI},         {Op::IToF, Kind::IToF},
        {Op::If, Kind::Control},        {Op::Loop, Kind::Control},
        {Op::Yield, Kind::Control},     {Op::Output, Kind::Sink},
        {Op::Tally, Kind::Counter},
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

// Every backend available here; a missing one is skipped with a message.
inline std::vector<std::unique_ptr<Backend>> allBackends() {
    std::vector<std::unique_ptr<Backend>> out;
    for (const std::string& name : test::availableBackends())
        if (auto b = test::makeBackendOrSkip(name)) out.push_back(std::move(b));
    return out;
}
} // namespace moire::optest
