// IR -> JavaScript. Every value becomes a block-scoped constant named after its id; regions
// become blocks; a loop becomes `for (;;)` over its carried variables, as in the GLSL emitter.
// Pure ops are spelled from one table (kForms) in the order of Ops.def, whose helpers (in
// kPrelude) give Semantics.h's meaning where JavaScript's Math differs from C's: min and max
// with NaN, the clamps at singular points, pow(1, NaN) and pow(-1, +-inf), float-to-int.
#include "compiler/backend/js/JsFrame.h"

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
static_assert(sizeof(kForms) / sizeof(kForms[0]) == ir::kNumOps, "every op needs a JS form");
constexpr bool formsInOrder() {
    for (int i = 0; i < ir::kNumOps; ++i)
        if (static_cast<int>(kForms[i].op) != i) return false;
    return true;
}
static_assert(formsInOrder(), "kForms follows the order of Ops.def");

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

class Emitter {
  public:
    explicit Emitter(const ir::Function& f) : f_(f) {}

    std::string run() {
        out_ = fmt::format("(() => {{\n\"use strict\";\n// Generated by moire from the frame IR "
                           "({} outputs).\n{}return (literals, time, out) => {{\n",
                           f_.numOutputs, kPrelude);
        block(0, 1);
        out_ += "};\n})()";
        return out_;
    }

  private:
    std::string v(ValueId id) const { return fmt::format("v{}", id); }
    void line(int depth, const std::string& text) {
        out_ += std::string(2 * depth, ' ') + text + "\n";
    }
    void define(int depth, ValueId id, const std::string& expr) {
        line(depth, fmt::format("const {} = {};", v(id), expr));
    }

    std::string expression(const ir::Inst& inst) const {
        const char* form = kForms[static_cast<int>(inst.op)].js;
        std::string s;
        for (const char* p = form; *p; ++p) {
            if (*p == '$' && p[1] >= '0' && p[1] <= '2') {
                s += v(inst.args.at(p[1] - '0'));
                ++p;
            } else if (*p == '$' && p[1] == 'i') {
                s += std::to_string(inst.iimm);
                ++p;
            } else {
                s += *p;
            }
        }
        return s;
    }

    // x^n by the same binary exponentiation as Semantics.h's semPowI, so the roundings agree.
    std::string powi(const ir::Inst& inst, int depth) {
        const int64_t n = inst.iimm;
        uint64_t e = static_cast<uint64_t>(n < 0 ? -n : n);
        if (e == 0) return "1";
        std::string cur = fmt::format("p{}", inst.results[0]);
        line(depth, fmt::format("const {} = {};", cur,
                                n < 0 ? fmt::format("1 / {}", v(inst.args[0])) : v(inst.args[0])));
        std::string acc;
        int step = 0;
        while (e) {
            if (e & 1) acc = acc.empty() ? cur : fmt::format("({} * {})", acc, cur);
            e >>= 1;
            if (e) {
                std::string next = fmt::format("p{}_{}", inst.results[0], ++step);
                line(depth, fmt::format("const {} = {} * {};", next, cur, cur));
                cur = next;
            }
        }
        return acc;
    }

    std::vector<ValueId> yields(ir::BlockId b) const { return f_.blocks[b].insts.back().args; }

    void block(ir::BlockId id, int depth) {
        for (const ir::Inst& inst : f_.blocks[id].insts) {
            if (inst.op == Op::Yield) break;
            instruction(inst, depth);
        }
    }

    void instruction(const ir::Inst& inst, int depth) {
        if (const char* why = refusal(inst.op))
            MOIRE_ICE("JavaScript frame program: '{}' cannot be translated: {}",
                      ir::spelling(inst.op), why);
        switch (inst.op) {
        case Op::ConstF:
            define(depth, inst.results[0], floatLiteral(inst.imm));
            return;
        case Op::ConstI:
            define(depth, inst.results[0], intLiteral(inst.iimm));
            return;
        case Op::ConstB:
            define(depth, inst.results[0], inst.iimm ? "true" : "false");
            return;
        case Op::PowI:
            define(depth, inst.results[0], powi(inst, depth));
            return;
        case Op::Output:
            line(depth, fmt::format("out[{}] = {};", inst.iimm, v(inst.args[0])));
            return;
        case Op::Tally:
            return;
        case Op::If: {
            for (ValueId r : inst.results) line(depth, fmt::format("let {};", v(r)));
            line(depth, fmt::format("if ({}) {{", v(inst.args[0])));
            branch(inst, inst.regions[0], depth + 1);
            line(depth, "} else {");
            branch(inst, inst.regions[1], depth + 1);
            line(depth, "}");
            return;
        }
        case Op::Loop:
            loop(inst, depth);
            return;
        case Op::Yield:
            MOIRE_ICE("stray yield");
        default:
            define(depth, inst.results[0], expression(inst));
            return;
        }
    }

    // An If's results are `let`s assigned in each branch, so the branch's own constants stay
    // in its block.
    void branch(const ir::Inst& inst, ir::BlockId region, int depth) {
        block(region, depth);
        const std::vector<ValueId> y = yields(region);
        for (size_t i = 0; i < y.size(); ++i)
            line(depth, fmt::format("{} = {};", v(inst.results[i]), v(y[i])));
    }

    void loop(const ir::Inst& inst, int depth) {
        const int id = loops_++;
        auto carried = [&](size_t i) { return fmt::format("l{}_{}", id, i); };
        for (size_t i = 0; i < inst.args.size(); ++i)
            line(depth, fmt::format("let {} = {};", carried(i), v(inst.args[i])));
        line(depth, "for (;;) {");
        const ir::Block& cond = f_.blocks[inst.regions[0]];
        const ir::Block& body = f_.blocks[inst.regions[1]];
        for (size_t i = 0; i < cond.params.size(); ++i)
            define(depth + 1, cond.params[i], carried(i));
        block(inst.regions[0], depth + 1);
        line(depth + 1, fmt::format("if (!{}) break;", v(yields(inst.regions[0])[0])));
        // The body sees the same carried values as the condition, under its own names.
        for (size_t i = 0; i < body.params.size(); ++i)
            define(depth + 1, body.params[i], carried(i));
        block(inst.regions[1], depth + 1);
        // The next values are constants of the body (its parameters are copies of the carried
        // variables), so writing one carried variable cannot change the next one read.
        const std::vector<ValueId> next = yields(inst.regions[1]);
        for (size_t i = 0; i < next.size(); ++i)
            line(depth + 1, fmt::format("{} = {};", carried(i), v(next[i])));
        line(depth, "}");
        for (size_t i = 0; i < inst.results.size(); ++i) define(depth, inst.results[i], carried(i));
    }

    const ir::Function& f_;
    std::string out_;
    int loops_ = 0;
};

} // namespace

const char* refusal(Op op) {
    return kForms[static_cast<int>(op)].why;
}

std::string emitFrameJs(const ir::Function& frame) {
    return Emitter(frame).run();
}

} // namespace moire::js
