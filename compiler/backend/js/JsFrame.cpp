// IR -> JavaScript, on the structure the GLSL emitter shares (backend/StructuredText.h):
// every value a block-scoped constant, a loop `for (;;)` over its carried variables. Pure ops are
// spelled from one table (kForms) in the order of Ops.def, whose helpers (in kPrelude) give
// Semantics.h's meaning where JavaScript's Math differs from C's: min and max with NaN, the clamps
// at singular points, pow(1, NaN) and pow(-1, +-inf), float-to-int.
#include "compiler/backend/js/JsFrame.h"

#include "compiler/backend/StructuredText.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <cmath>
#include <cstdint>
#include <fmt/format.h>

namespace moire::js {

using ir::Op;
using ir::ValueId;

namespace {

// "$0", "$1", "$2" are the operands, "$i" the integer immediate. An empty form: written by
// hand (constants, control flow, sinks) or refused (`why`).
struct Form {
    Op op;
    const char* js;
    const char* why = nullptr; // the reason the op cannot be in a frame program
};
constexpr const char* kPixel = "the pixel's position and the image's size belong to the kernel";
constexpr Form kForms[] = {
    {Op::ConstF, ""},
    {Op::ConstI, ""},
    {Op::ConstB, ""},
    {Op::PixelX, "", kPixel},
    {Op::PixelY, "", kPixel},
    {Op::ImageW, "", kPixel},
    {Op::ImageH, "", kPixel},
    {Op::Time, "time"},
    {Op::Param, "literals[$i]"},
    {Op::Uniform, "", "uniforms are the kernel's inputs: the frame program computes them"},
    {Op::Indep, "", "differentiation markers are removed by the AD pass"},
    {Op::DerivX, "", "differentiation markers are removed by the AD pass"},
    {Op::DerivY, "", "differentiation markers are removed by the AD pass"},
    {Op::Detach, "", "differentiation markers are removed by the AD pass"},
    {Op::Add, "($0 + $1)"},
    {Op::Sub, "($0 - $1)"},
    {Op::Mul, "($0 * $1)"},
    {Op::MulZ, "m_mulz($0, $1)"},
    {Op::Div, "($0 / $1)"},
    {Op::Neg, "(-$0)"},
    {Op::Abs, "Math.abs($0)"},
    {Op::Sign, "m_sign($0)"},
    {Op::Floor, "Math.floor($0)"},
    {Op::Round, "Math.floor($0 + 0.5)"},
    {Op::Fract, "($0 - Math.floor($0))"},
    {Op::Mod, "($0 - $1 * Math.floor($0 / $1))"},
    {Op::Min, "m_min($0, $1)"},
    {Op::Max, "m_max($0, $1)"},
    {Op::Sqrt, "Math.sqrt(m_max($0, 0))"},
    {Op::Exp, "Math.exp($0)"},
    {Op::Log, "Math.log(m_max($0, 1e-30))"},
    {Op::Pow, "m_pow($0, $1)"},
    {Op::PowI, ""},
    {Op::Sin, "Math.sin($0)"},
    {Op::Cos, "Math.cos($0)"},
    {Op::Tan, "Math.tan($0)"},
    {Op::Asin, "Math.asin(m_min(m_max($0, -1), 1))"},
    {Op::Acos, "Math.acos(m_min(m_max($0, -1), 1))"},
    {Op::Atan, "Math.atan($0)"},
    {Op::Atan2, "Math.atan2($0, $1)"},
    {Op::Hypot, "Math.hypot($0, $1)"},
    {Op::Select, "($0 ? $1 : $2)"},
    {Op::Lt, "($0 < $1)"},
    {Op::Le, "($0 <= $1)"},
    {Op::Gt, "($0 > $1)"},
    {Op::Ge, "($0 >= $1)"},
    {Op::Eq, "($0 === $1)"},
    {Op::Ne, "($0 !== $1)"},
    {Op::And, "($0 && $1)"},
    {Op::Or, "($0 || $1)"},
    {Op::Not, "(!$0)"},
    // 32-bit integers that wrap, as the IR's do: `| 0` keeps the low 32 bits of a sum,
    // Math.imul those of a product.
    {Op::IAdd, "(($0 + $1) | 0)"},
    {Op::ISub, "(($0 - $1) | 0)"},
    {Op::IMul, "Math.imul($0, $1)"},
    {Op::ILt, "($0 < $1)"},
    {Op::ILe, "($0 <= $1)"},
    {Op::IEq, "($0 === $1)"},
    {Op::FToI, "m_ftoi($0)"},
    {Op::IToF, "$0"},
    {Op::If, ""},
    {Op::Loop, ""},
    {Op::Yield, ""},
    {Op::Output, ""},
    {Op::Tally, ""}, // counted by the interpreter only, as on every other backend
};
static_assert(backend::formsFollowOps(kForms), "kForms has a JS form per op, in Ops.def's order");

// Semantics.h where Math differs: C's pow gives 1 for pow(1, NaN) and pow(-1, +-inf), where
// Math.pow gives NaN; an integer has no negative zero (`| 0` drops floor(-0)'s sign).
constexpr const char* kPrelude = R"(const m_min = (a, b) => (b < a ? b : a);
const m_max = (a, b) => (b > a ? b : a);
const m_mulz = (a, b) => (a === 0 || b === 0 ? 0 : a * b);
const m_sign = (a) => (a > 0 ? 1 : a < 0 ? -1 : 0);
const m_pow = (x, y) => (x === 1 || (x === -1 && Math.abs(y) === Infinity) ? 1 : Math.pow(x, y));
const m_ftoi = (a) => (a !== a ? 0 : Math.min(Math.max(Math.floor(a), -1073741824), 1073741824) | 0);
)";

std::string floatLiteral(double v) {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return v > 0 ? "Infinity" : "(-Infinity)";
    // fmt's shortest form reads back as the same double.
    std::string s = fmt::format("{}", v);
    return std::signbit(v) ? "(" + s + ")" : s;
}

// The immediate's low 32 bits, as every backend takes an integer constant.
std::string intLiteral(int64_t v) {
    const int32_t i = static_cast<int32_t>(static_cast<uint32_t>(v));
    return i < 0 ? fmt::format("({})", i) : fmt::format("{}", i);
}

class Emitter : backend::StructuredText {
  public:
    explicit Emitter(const ir::Function& f) : StructuredText(f, Syntax{2, "for (;;) {", "1"}) {}

    std::string run() {
        out_ = fmt::format("(() => {{\n\"use strict\";\n// Generated by moire from the frame IR "
                           "({} outputs).\n{}return (literals, time, out) => {{\n",
                           f_.numOutputs, kPrelude);
        block(0, 1);
        out_ += "};\n})()";
        return out_;
    }

  private:
    // Every value is a block-scoped constant; what an If or a Loop assigns again, a `let`.
    std::string floatLiteral(double v) const override { return js::floatLiteral(v); }
    std::string intLiteral(int64_t v) const override { return js::intLiteral(v); }
    std::string output(int64_t slot) const override { return fmt::format("out[{}]", slot); }
    std::string constant(ir::Type) const override { return "const"; }
    std::string variable(ir::Type) const override { return "let"; }
    const char* form(const ir::Inst& inst) const override {
        return kForms[static_cast<int>(inst.op)].js;
    }

    bool special(const ir::Inst& inst, int depth) override {
        if (const char* why = refusal(inst.op))
            MOIRE_ICE("JavaScript frame program: '{}' cannot be translated: {}",
                      ir::spelling(inst.op), why);
        return false;
    }
};

} // namespace

const char* refusal(Op op) {
    return kForms[static_cast<int>(op)].why;
}

std::string emitFrameJs(const ir::Function& frame) {
    return Emitter(frame).run();
}

} // namespace moire::js
