// IR -> GLSL: a 4.50 compute shader for Vulkan, or a GLSL ES 3.00 fragment shader for WebGL2
// (`moire export`). Every value becomes a local variable named after its id;
// regions become GLSL blocks; a loop becomes `while (true)` over its carried variables.
// Pure ops are spelled from one table (kForms), whose entries follow Ops.def: the semantics
// of Semantics.h, including the clamps at singular points, are written out in the prelude's
// helper functions, since GLSL's built-ins leave some of those cases undefined. The two
// dialects share the table, the prelude and the body; only the shader's interface (how the
// uniforms and the pixel come in and the outputs go out) differs.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/backend/StructuredText.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>

namespace moire::glsl {

using ir::Op;
using ir::ValueId;

namespace {

// The GLSL form of every op: "$0", "$1", "$2" are its operands, "$i" its integer immediate.
// An empty form means the emitter writes the op by hand (leaves, control flow, sinks).
// `webgl`, where set, replaces `glsl` in the WebGL dialect.
struct Form {
    Op op;
    const char* glsl;
    const char* webgl = nullptr;
};
constexpr Form kForms[] = {
    {Op::ConstF, ""},
    {Op::ConstI, ""},
    {Op::ConstB, ""},
    {Op::PixelX, "pixelX"},
    {Op::PixelY, "pixelY"},
    {Op::ImageW, "imageW"},
    {Op::ImageH, "imageH"},
    {Op::Time, ""},
    {Op::Param, ""},
    {Op::Uniform, "U.u[$i]"},
    {Op::Indep, "$0"},
    {Op::DerivX, ""},
    {Op::DerivY, ""},
    {Op::Detach, "$0"},
    {Op::Add, "($0 + $1)"},
    {Op::Sub, "($0 - $1)"},
    {Op::Mul, "($0 * $1)"},
    {Op::MulZ, "m_mulz($0, $1)"},
    {Op::Div, "($0 / $1)"},
    {Op::Neg, "(-$0)"},
    {Op::Abs, "abs($0)"},
    {Op::Sign, "m_sign($0)"},
    {Op::Floor, "floor($0)"},
    {Op::Round, "floor($0 + 0.5)"},
    {Op::Fract, "($0 - floor($0))"},
    {Op::Mod, "m_mod($0, $1)"},
    {Op::Min, "m_min($0, $1)"},
    {Op::Max, "m_max($0, $1)"},
    {Op::Sqrt, "sqrt(m_max($0, 0.0))"},
    {Op::Exp, "exp($0)"},
    {Op::Log, "log(m_max($0, 1e-30))"},
    {Op::Pow, "m_pow($0, $1)"},
    {Op::PowI, ""},
    {Op::Sin, "sin(m_turns($0))", "m_sin(m_turns($0))"},
    {Op::Cos, "cos(m_turns($0))", "m_cos(m_turns($0))"},
    {Op::Tan, "tan(m_turns($0))", "m_tan(m_turns($0))"},
    {Op::Asin, "asin(m_min(m_max($0, -1.0), 1.0))"},
    {Op::Acos, "acos(m_min(m_max($0, -1.0), 1.0))"},
    {Op::Atan, "m_atan($0)"},
    {Op::Atan2, "m_atan2($0, $1)"},
    {Op::Hypot, "m_hypot($0, $1)"},
    {Op::Select, "($0 ? $1 : $2)"},
    {Op::Lt, "($0 < $1)"},
    {Op::Le, "($0 <= $1)"},
    {Op::Gt, "($0 > $1)"},
    {Op::Ge, "($0 >= $1)"},
    {Op::Eq, "($0 == $1)"},
    {Op::Ne, "m_ne($0, $1)"},
    {Op::And, "($0 && $1)"},
    {Op::Or, "($0 || $1)"},
    {Op::Not, "(!$0)"},
    {Op::IAdd, "($0 + $1)"},
    {Op::ISub, "($0 - $1)"},
    {Op::IMul, "($0 * $1)"},
    {Op::ILt, "($0 < $1)"},
    {Op::ILe, "($0 <= $1)"},
    {Op::IEq, "($0 == $1)"},
    {Op::FToI, "m_ftoi($0)"},
    {Op::IToF, "float($0)"},
    {Op::If, ""},
    {Op::Loop, ""},
    {Op::Yield, ""},
    {Op::Output, ""},
    {Op::Tally, ""},
};
static_assert(backend::formsFollowOps(kForms), "kForms has a GLSL form per op, in Ops.def's order");

// Without this execution mode Vulkan lets the driver assume that no value is NaN or infinite
// and ignore the sign of zero (and drivers do: without it lavapipe's atan(NaN) is 0).
// Semantics.h defines all three, so the shader asks for them to be kept:
// SignedZeroInfNanPreserve for 32-bit floats (SPIR-V 1.4 core, Vulkan 1.2 float controls),
// spelled in GLSL through GL_EXT_spirv_intrinsics; 4466 is the capability, 4461 the
// execution mode. A device must report shaderSignedZeroInfNanPreserveFloat32 to run it.
constexpr const char* kFloatControls =
    "#extension GL_EXT_spirv_intrinsics : require\n"
    "spirv_execution_mode(capabilities = [4466], 4461, 32); // SignedZeroInfNanPreserve\n";

// Semantics.h, in GLSL. NaN and infinity come from bit patterns: GLSL has no literal for them.
// Each helper spells out the cases where GLSL's built-in is undefined or differs from C
// (IEEE 754): min/max and comparisons with NaN, atan2 on the axes and at infinity, pow with
// a negative or zero base or an infinite exponent, float-to-int of NaN and out of range. The
// sign bit is read from the bits (m_neg), since -0.0 < 0.0 is false.
// m_precise is `precise` where the dialect has it (GLSL ES 3.00 has not).
constexpr const char* kPrelude = R"(#define m_nan uintBitsToFloat(0x7fc00000u)
#define m_inf uintBitsToFloat(0x7f800000u)
#define m_pi 3.14159274
bool m_neg(float a) { return floatBitsToInt(a) < 0; }
float m_copysign(float mag, float s) { return m_neg(s) ? -mag : mag; }
float m_min(float a, float b) { return b < a ? b : a; }
float m_max(float a, float b) { return b > a ? b : a; }
float m_mulz(float a, float b) { return mix(a * b, 0.0, any(equal(vec2(a, b), vec2(0.0)))); }
// Through integers: written with selects (a > 0 ? 1 : a < 0 ? -1 : 0), it gave -0 at 0 and
// at NaN on lavapipe (Mesa 22.3), with SignedZeroInfNanPreserve or without.
float m_sign(float a) { return float(int(a > 0.0) - int(a < 0.0)); }
// No fused multiply-add: the product is rounded before the subtraction, as in C.
float m_mod(float a, float b) { m_precise float p = b * floor(a / b); m_precise float r = a - p; return r; }
bool m_ne(float a, float b) { return isnan(a) || isnan(b) || a != b; }
// Vulkan bounds the error of sin and cos only on [-pi, pi] (absolute, 2^-11); outside it a
// driver owes nothing. So arguments are first reduced by whole turns, Cody-Waite style: 2 pi
// is split into four 7-bit parts and a float, so that k times each part is exact and only
// the last two subtractions round (2^-22 in all), for |k| < 2^17 turns (|x| < about 800000).
// Within [-pi, pi] (k = 0) the argument is passed on unchanged, sign of zero included.
float m_turns(float x) {
    float k = floor(x * 0.159154937 + 0.5);
    if (k == 0.0) return x;
    return ((((x - k * 6.25) - k * 0.03271484375) - k * 0.000469207763671875) -
            k * 1.2516975402832031e-06) - k * 3.96837452e-09;
}
// lavapipe's atan(-0.0) is +0.0.
float m_atan(float a) { return a == 0.0 ? a : atan(a); }
float m_atan2(float y, float x) {
    if (isnan(x) || isnan(y)) return m_nan;
    if (y == 0.0) return m_neg(x) ? m_copysign(m_pi, y) : y;
    if (isinf(x)) {
        if (isinf(y)) return m_copysign(m_neg(x) ? 2.3561945 : 0.785398185, y);
        return m_neg(x) ? m_copysign(m_pi, y) : m_copysign(0.0, y);
    }
    if (isinf(y) || x == 0.0) return m_copysign(1.57079637, y);
    return atan(y, x);
}
// sqrt(x^2 + y^2), with both sides first scaled by a power of two (exact) where the larger
// is so large that a square would overflow, or so small that it would lose precision. No
// division and no branch: the scaled-quotient form (big * sqrt(1 + q^2)) with early returns
// cost lavapipe, which runs lanes in step, a quarter of a two-ring frame. An infinite side
// wins over NaN, as in C.
float m_hypot(float a, float b) {
    vec2 v = abs(vec2(a, b));
    float big = max(v.x, v.y);
    bool large = big > 1.15292150e18, small = big < 8.67361738e-19;
    float s = mix(mix(1.0, 1.26765060e30, small), 8.27180613e-25, large);
    float back = mix(mix(1.0, 7.88860905e-31, small), 1.20892582e24, large);
    vec2 w = v * s;
    return mix(sqrt(w.x * w.x + w.y * w.y) * back, m_inf, any(isinf(v)));
}
float m_pow(float x, float y) {
    if (y == 0.0 || x == 1.0) return 1.0;
    if (isnan(x) || isnan(y)) return m_nan;
    float ax = abs(x);
    if (isinf(y)) return ax == 1.0 ? 1.0 : ((ax < 1.0) == (y < 0.0) ? m_inf : 0.0);
    bool integer = floor(y) == y;
    bool odd = integer && floor(y * 0.5) != y * 0.5;
    float r;
    if (ax == 0.0) r = y < 0.0 ? m_inf : 0.0;
    else if (isinf(ax)) r = y < 0.0 ? 0.0 : m_inf;
    else if (ax == 1.0) r = 1.0;
    else r = pow(ax, y);
    if (!m_neg(x)) return r;
    if (!integer) return (ax == 0.0 || isinf(ax)) ? r : m_nan;
    return odd ? -r : r;
}
int m_ftoi(float a) {
    if (isnan(a)) return 0;
    return int(clamp(floor(a), -1073741824.0, 1073741824.0));
}
)";

// WebGL's sin and cos are the browser's GPU's, held to nothing better than Vulkan's 2^-11 on
// [-pi, pi]; SwiftShader (Chromium without a GPU) was seen 1e-4 off, which moved the strokes
// of a walking family's far members by a visible fraction of a pixel. So the WebGL dialect
// computes them itself, to within a few ULP: the argument (already within [-pi, pi], from
// m_turns) is reduced by quarter turns, pi/2 split in three parts so that q times each is
// exact, and the minimax polynomials for [-pi/4, pi/4] of Cephes' sinf and cosf give the
// rest.
constexpr const char* kWebGlTrig = R"(float m_sinp(float x) {
    float z = x * x;
    return x + x * z * (-1.6666654611e-1 + z * (8.3321608736e-3 + z * -1.9515295891e-4));
}
float m_cosp(float x) {
    float z = x * x;
    return 1.0 - 0.5 * z +
           z * z * (4.166664568298827e-2 + z * (-1.388731625493765e-3 + z * 2.443315711809948e-5));
}
// The quarter turn of x (0 to 3) in q, what is left of x in r.
float m_quarter(float x, out int q) {
    float k = floor(x * 0.636619772 + 0.5);
    q = int(k) & 3;
    return ((x - k * 1.5703125) - k * 4.83751296997070312e-4) - k * 7.54978995489188216e-8;
}
float m_sin(float x) {
    int q;
    float r = m_quarter(x, q), s = m_sinp(r), c = m_cosp(r);
    return q == 0 ? s : q == 1 ? c : q == 2 ? -s : -c;
}
float m_cos(float x) {
    int q;
    float r = m_quarter(x, q), s = m_sinp(r), c = m_cosp(r);
    return q == 0 ? c : q == 1 ? -s : q == 2 ? -c : s;
}
float m_tan(float x) { return m_sin(x) / m_cos(x); }
)";

std::string typeName(ir::Type t) {
    switch (t) {
    case ir::Type::F:
        return "float";
    case ir::Type::I:
        return "int";
    case ir::Type::B:
        return "bool";
    default:
        MOIRE_ICE("GLSL: no type for {}", ir::typeSpelling(t));
    }
}

std::string floatLiteral(double v) {
    float f = static_cast<float>(v);
    if (std::isnan(f)) return "m_nan";
    if (std::isinf(f)) return f > 0 ? "m_inf" : "(-m_inf)";
    // Nine significant digits round-trip a float; make sure the literal reads as a float.
    std::string s = fmt::format("{:.9g}", f);
    if (s.find_first_of(".eE") == std::string::npos) s += ".0";
    return f < 0 || std::signbit(f) ? "(" + s + ")" : s;
}

// The IR's integers are 32-bit: the immediate's low 32 bits, as the JIT takes them. The most
// negative one has no literal in GLSL (2147483648 does not fit an int before the minus).
std::string intLiteral(int64_t v) {
    const int32_t i = static_cast<int32_t>(static_cast<uint32_t>(v));
    return i == INT32_MIN ? "(-2147483647 - 1)" : fmt::format("{}", i);
}

class Emitter : backend::StructuredText {
  public:
    Emitter(const ir::Function& f, Dialect d) : StructuredText(f, Syntax{}), dialect_(d) {}

    std::string run() { return dialect_ == Dialect::Vulkan ? vulkanCompute() : webglFragment(); }

  private:
    std::string vulkanCompute() {
        const int n = f_.numOutputs;
        const bool quads = n % 4 == 0;
        out_ = fmt::format(
            "#version 450\n"
            "// Generated by moire from the kernel IR ({} outputs).\n"
            "{}"
            "layout(local_size_x = {}, local_size_y = {}, local_size_z = 1) in;\n"
            "layout(std430, set = 0, binding = 0) readonly buffer Uniforms {{ float u[]; }} U;\n"
            "layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ {} o[]; }} O;\n"
            "layout(push_constant) uniform Frame {{ int imageW; int imageH; int x0; int y0; int w; "
            "int h; }} F;\n"
            "#define m_precise precise\n"
            "{}\n"
            "void main() {{\n"
            "    int gx = int(gl_GlobalInvocationID.x), gy = int(gl_GlobalInvocationID.y);\n"
            "    bool inside = all(lessThan(ivec2(gx, gy), ivec2(F.w, F.h)));\n"
            "    gx = min(gx, F.w - 1);\n"
            "    gy = min(gy, F.h - 1);\n"
            "    float pixelX = float(F.x0 + gx) + 0.5, pixelY = float(F.y0 + gy) + 0.5;\n"
            "    float imageW = float(F.imageW), imageH = float(F.imageH);\n",
            n, kFloatControls, kLocalSizeX, kLocalSizeY, quads ? "vec4" : "float", kPrelude);
        // An invocation past the rectangle's edge (the last workgroups of a row or column)
        // shades the edge pixel again and only skips the store: returning early instead put
        // the whole kernel under divergent control flow, and lavapipe, which runs the lanes
        // of a workgroup in step, then masks every operation and loads each uniform lane by
        // lane; the two ring families ran at half the speed of the same maths without it.
        // The outputs are gathered in variables and stored together at the end, four to a
        // vec4 store where they come in fours: such a driver scatters each store lane by
        // lane, so one store of four floats costs what one float did.
        for (int k = 0; k < n; ++k) line(1, fmt::format("float r{} = 0.0;", k));
        block(0, 1);
        line(1, "if (!inside) return;");
        if (quads) {
            line(1, fmt::format("int base = (gy * F.w + gx) * {};", n / 4));
            for (int k = 0; k < n; k += 4)
                line(1, fmt::format("O.o[base + {}] = vec4(r{}, r{}, r{}, r{});", k / 4, k, k + 1,
                                    k + 2, k + 3));
        } else {
            line(1, fmt::format("int base = (gy * F.w + gx) * {};", n));
            for (int k = 0; k < n; ++k) line(1, fmt::format("O.o[base + {}] = r{};", k, k));
        }
        out_ += "}\n";
        return out_;
    }

    // WebGL2 has no storage buffers and no compute: one fragment per pixel of a canvas the
    // size of the image, the uniforms in a plain uniform array (four to a vec4: a float
    // array spends a whole vector register per element), the first four outputs as the
    // fragment's colour. gl_FragCoord counts rows from the bottom; the IR's pixel.y from the
    // top, so it is flipped (exactly: both are half-integers far below 2^24).
    std::string webglFragment() {
        const int n = f_.numOutputs;
        out_ =
            fmt::format("#version 300 es\n"
                        "// Generated by moire from the kernel IR ({} outputs).\n"
                        "precision highp float;\n"
                        "precision highp int;\n"
                        "uniform vec4 m_u[{}];\n"
                        "uniform vec2 m_image;\n"
                        "out vec4 m_color;\n"
                        "#define m_precise\n"
                        "{}{}\n"
                        "void main() {{\n"
                        "    float pixelX = gl_FragCoord.x, pixelY = m_image.y - gl_FragCoord.y;\n"
                        "    float imageW = m_image.x, imageH = m_image.y;\n",
                        n, uniformVectors(f_), kPrelude, kWebGlTrig);
        for (int k = 0; k < std::max(n, 4); ++k)
            line(1, fmt::format("float r{} = {};", k, k == 3 ? "1.0" : "0.0"));
        block(0, 1);
        line(1, "m_color = vec4(r0, r1, r2, r3);");
        out_ += "}\n";
        return out_;
    }

    std::string floatLiteral(double v) const override { return glsl::floatLiteral(v); }
    std::string intLiteral(int64_t v) const override { return glsl::intLiteral(v); }
    std::string output(int64_t slot) const override { return fmt::format("r{}", slot); }
    std::string constant(ir::Type t) const override { return typeName(t); }
    std::string variable(ir::Type t) const override { return typeName(t); }
    const char* form(const ir::Inst& inst) const override {
        const Form& entry = kForms[static_cast<int>(inst.op)];
        return dialect_ == Dialect::WebGl && entry.webgl ? entry.webgl : entry.glsl;
    }

    bool special(const ir::Inst& inst, int depth) override {
        switch (inst.op) {
        case Op::Time:
        case Op::Param:
            MOIRE_ICE("'{}' belongs to the frame program, not the kernel", ir::spelling(inst.op));
        case Op::DerivX:
        case Op::DerivY:
            MOIRE_ICE("derivative markers must be removed by the AD pass");
        case Op::Ne:
            // NaN tests: x != x is the IR's NaN check, and isnan says so to every driver.
            if (inst.args[0] != inst.args[1]) return false;
            define(depth, inst.results[0], fmt::format("isnan({})", v(inst.args[0])));
            return true;
        case Op::Uniform:
            if (dialect_ != Dialect::WebGl) return false;
            define(depth, inst.results[0],
                   fmt::format("m_u[{}].{}", inst.iimm / 4, "xyzw"[inst.iimm % 4]));
            return true;
        default:
            return false;
        }
    }

    Dialect dialect_;
};

} // namespace

std::string emitGlsl(const ir::Function& kernel, Dialect dialect) {
    return Emitter(kernel, dialect).run();
}

int uniformCount(const ir::Function& kernel) {
    int n = 0;
    for (const ir::Block& b : kernel.blocks)
        for (const ir::Inst& inst : b.insts)
            if (inst.op == Op::Uniform) n = std::max(n, static_cast<int>(inst.iimm) + 1);
    return n;
}

int uniformVectors(const ir::Function& kernel) {
    return std::max(1, (uniformCount(kernel) + 3) / 4);
}

} // namespace moire::glsl
