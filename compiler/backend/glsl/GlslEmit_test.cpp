// The GLSL emitter on its own: every op of Ops.def is handled (a kernel using it becomes GLSL
// that glslang compiles and spirv-val accepts for Vulkan 1.2, or, for the ops that cannot be
// in a kernel, an internal error), and the structure of what it writes: one variable per SSA
// value, loops whose carried values are all read before any is written, nested regions, and
// powi by binary exponentiation. Results are checked by running the shader where a Vulkan
// device is available; where none is, the shader is still compiled and validated.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/ir/Semantics.h"

#include <algorithm>
#include <bit>
#include <doctest/doctest.h>
#include <map>
#include <regex>
#include <set>
#include <sstream>

using namespace moire;
using namespace moire::ir;
using optest::build;
using optest::Kind;

namespace {

// The shader compiles and passes spirv-val; returns its SPIR-V disassembly.
std::string compilesAndValidates(const Function& f) {
    std::vector<uint32_t> spirv;
    REQUIRE_NOTHROW(spirv = glsl::compileSpirv(f));
    std::string message;
    INFO("spirv-val: ", message);
    CHECK(glsl::validateSpirv(spirv, &message));
    return glsl::disassembleSpirv(spirv);
}

// The Vulkan backend, or null (with a message) where there is no device.
std::unique_ptr<Backend> vulkanOrNull() {
    auto vk = test::makeBackendOrSkip("vulkan");
    if (!vk) MESSAGE("no Vulkan backend here: the shaders are compiled and validated, not run");
    return vk;
}

// A kernel whose one output uses `op` on uniforms 0 and 1, whatever the op's kind; the
// result is converted to float so every kind has the same output.
Function kernelUsing(Op op) {
    return build(1, [&](Builder& b) {
        ValueId a = b.uniform(0), c = b.uniform(1);
        auto asFloat = [&](ValueId v) {
            Type t = b.function().type(v);
            return t == Type::B   ? b.select(v, b.constF(1.0), b.constF(0.0))
                   : t == Type::I ? b.emit(Op::IToF, {v})
                                  : v;
        };
        auto toInt = [&](ValueId v) { return b.emit(Op::FToI, {v}); };
        ValueId r = kNoValue;
        switch (optest::kindOf(op)) {
        case Kind::Leaf:
            r = op == Op::ConstF    ? b.constF(0.25)
                : op == Op::ConstI  ? b.constI(-7)
                : op == Op::ConstB  ? b.constB(true)
                : op == Op::Uniform ? b.uniform(2)
                                    : b.leaf(op);
            break;
        case Kind::FrameLeaf:
            r = op == Op::Param ? b.param(0) : b.leaf(op);
            break;
        case Kind::Marker:
            r = b.emit(op, {a}, 0.0, 0);
            break;
        case Kind::FloatUnary:
        case Kind::PowI:
            r = b.emit(op, {a}, 0.0, 5);
            break;
        case Kind::FloatBinary:
        case Kind::Compare:
            r = b.emit(op, {a, c});
            break;
        case Kind::Select:
            r = b.select(b.lt(a, c), a, c);
            break;
        case Kind::Logic:
            r = op == Op::Not ? b.emit(op, {b.lt(a, c)}) : b.emit(op, {b.lt(a, c), b.gt(a, c)});
            break;
        case Kind::IntArith:
        case Kind::IntCompare:
            r = b.emit(op, {toInt(a), toInt(c)});
            break;
        case Kind::FToI:
        case Kind::IToF:
            r = b.emit(Op::IToF, {toInt(a)});
            break;
        case Kind::Control: // if and loop (each with its yields)
            r = b.ifThenElse(
                b.lt(a, c), [&] { return std::vector<ValueId>{a}; },
                [&] {
                    return b.loop(
                        {c},
                        [&](std::span<const ValueId> p) {
                            return std::vector<ValueId>{b.lt(p[0], a)};
                        },
                        [&](std::span<const ValueId> p) {
                            return std::vector<ValueId>{b.add(p[0], b.constF(1.0))};
                        });
                })[0];
            break;
        case Kind::Sink: // output: every kernel has one
            r = a;
            break;
        case Kind::Counter:
            b.emitSink(op, {}, 0);
            r = a;
            break;
        }
        b.output(0, asFloat(r));
    });
}

bool uses(const Function& f, Op op) {
    for (const Block& blk : f.blocks)
        for (const Inst& inst : blk.insts)
            if (inst.op == op) return true;
    return false;
}

} // namespace

TEST_CASE("glsl: every op becomes GLSL that glslang compiles and spirv-val accepts") {
    for (int i = 0; i < kNumOps; ++i) {
        const Op op = static_cast<Op>(i);
        std::string opName = spelling(op);
        CAPTURE(opName);
        Function f = kernelUsing(op);
        REQUIRE(uses(f, op));
        const Kind kind = optest::kindOf(op);
        if (kind == Kind::FrameLeaf || op == Op::DerivX || op == Op::DerivY) {
            // time and param belong to the frame program; derivative markers are removed by
            // the AD pass. A kernel holding one is a bug upstream: say so, emit nothing.
            CHECK_THROWS_AS(glsl::emitGlsl(f), InternalError);
            CHECK_THROWS_AS(glsl::compileSpirv(f), InternalError);
            continue;
        }
        std::string source;
        REQUIRE_NOTHROW(source = glsl::emitGlsl(f));
        CAPTURE(source);
        compilesAndValidates(f);
    }
}

TEST_CASE("glsl: the shader keeps NaN, infinities and signed zeros, and rounds mod's product") {
    // Semantics.h relies on all three; without SignedZeroInfNanPreserve a Vulkan driver may
    // assume there are none (lavapipe's atan(NaN) is then 0).
    std::string spirv = compilesAndValidates(kernelUsing(Op::Add));
    CHECK(spirv.find("OpCapability SignedZeroInfNanPreserve") != std::string::npos);
    CHECK(spirv.find("OpExecutionMode %main SignedZeroInfNanPreserve 32") != std::string::npos);
    // mod is a - b floor(a / b) with the product rounded, as in C: no fused multiply-add.
    CHECK(compilesAndValidates(kernelUsing(Op::Mod)).find("NoContraction") != std::string::npos);
    CHECK(compilesAndValidates(kernelUsing(Op::Sub)).find("NoContraction") == std::string::npos);
}

TEST_CASE("glsl: integer constants are the IR's 32-bit values, the extremes included") {
    const std::vector<int64_t> values = {0, -1, 2147483647, -2147483648LL, int64_t(1) << 32};
    Function f = build(static_cast<int>(values.size()), [&](Builder& b) {
        for (size_t i = 0; i < values.size(); ++i)
            b.output(static_cast<int>(i), b.emit(Op::IToF, {b.constI(values[i])}));
    });
    compilesAndValidates(f);
    if (auto vk = vulkanOrNull()) {
        std::vector<float> got = optest::runPixel(*vk->compile(f), {});
        for (size_t i = 0; i < values.size(); ++i) {
            CAPTURE(values[i]);
            CHECK(got[i] ==
                  static_cast<float>(static_cast<int32_t>(static_cast<uint32_t>(values[i]))));
        }
    }
}

TEST_CASE("glsl: every SSA value becomes exactly one variable") {
    // Nested regions: a loop whose body holds an if whose branch holds a loop.
    Function f = build(2, [](Builder& b) {
        ValueId n = b.emit(Op::FToI, {b.uniform(0)});
        auto outer = b.loop(
            {b.constI(0), b.constF(0.0)},
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.emit(Op::ILt, {p[0], n})};
            },
            [&](std::span<const ValueId> p) {
                ValueId i = p[0];
                auto term = b.ifThenElse(
                    b.emit(Op::IEq,
                           {b.emit(Op::IMul,
                                   {b.emit(Op::FToI, {b.mul(b.emit(Op::IToF, {i}), b.constF(0.5))}),
                                    b.constI(2)}),
                            i}),
                    [&] { // i even: the sum of j for j < i, by an inner loop
                        auto inner = b.loop(
                            {b.constI(0), b.constF(0.0)},
                            [&](std::span<const ValueId> q) {
                                return std::vector<ValueId>{b.emit(Op::ILt, {q[0], i})};
                            },
                            [&](std::span<const ValueId> q) {
                                return std::vector<ValueId>{b.emit(Op::IAdd, {q[0], b.constI(1)}),
                                                            b.add(q[1], b.emit(Op::IToF, {q[0]}))};
                            });
                        return std::vector<ValueId>{inner[1]};
                    },
                    [&] {
                        return std::vector<ValueId>{b.neg(b.emit(Op::IToF, {i}))};
                    }); // i odd: -i
                return std::vector<ValueId>{b.emit(Op::IAdd, {i, b.constI(1)}),
                                            b.add(p[1], term[0])};
            });
        b.output(0, outer[1]);
        b.output(1, b.emit(Op::IToF, {outer[0]}));
    });
    const std::string source = glsl::emitGlsl(f);
    CAPTURE(source);
    // The values the IR defines: every result and every block parameter.
    std::set<ValueId> defined;
    for (const Block& blk : f.blocks) {
        defined.insert(blk.params.begin(), blk.params.end());
        for (const Inst& inst : blk.insts) defined.insert(inst.results.begin(), inst.results.end());
    }
    // The variables the GLSL declares for them: "<type> v<id>" once each.
    std::map<ValueId, int> declared;
    const std::regex decl(R"((?:float|int|bool) v(\d+)\b)");
    for (auto it = std::sregex_iterator(source.begin(), source.end(), decl);
         it != std::sregex_iterator(); ++it)
        ++declared[static_cast<ValueId>(std::stoul((*it)[1]))];
    CHECK(declared.size() == defined.size());
    for (ValueId v : defined) {
        CAPTURE(v);
        CHECK(declared[v] == 1);
    }
    compilesAndValidates(f);
    if (auto vk = vulkanOrNull()) {
        auto k = vk->compile(f);
        for (int n : {0, 1, 2, 5, 10}) {
            CAPTURE(n);
            double want = 0.0; // even i: i (i - 1) / 2; odd i: -i
            for (int i = 0; i < n; ++i) want += i % 2 == 0 ? i * (i - 1) / 2.0 : -i;
            std::vector<float> got = optest::runPixel(*k, {double(n)});
            CHECK(got[0] == want);
            CHECK(got[1] == n);
        }
    }
}

TEST_CASE("glsl: a loop's carried values are all read before any is written") {
    // Each turn swaps (x, y) and rotates (a, b, c) -> (b, c, a). A loop that wrote one
    // carried variable before reading the next would duplicate a value instead.
    Function f = build(5, [](Builder& b) {
        ValueId n = b.emit(Op::FToI, {b.uniform(0)});
        std::vector<ValueId> init = {b.constI(0)};
        for (int slot = 1; slot <= 5; ++slot) init.push_back(b.uniform(slot));
        auto res = b.loop(
            init,
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{b.emit(Op::ILt, {p[0], n})};
            },
            [&](std::span<const ValueId> p) {
                return std::vector<ValueId>{
                    b.emit(Op::IAdd, {p[0], b.constI(1)}), p[2], p[1], p[4], p[5], p[3]};
            });
        for (int i = 0; i < 5; ++i) b.output(i, res[i + 1]);
    });
    compilesAndValidates(f);
    if (auto vk = vulkanOrNull()) {
        auto k = vk->compile(f);
        const std::vector<double> xy = {10.0, 20.0}, abc = {30.0, 40.0, 50.0};
        for (int n : {0, 1, 2, 3, 4, 7}) {
            CAPTURE(n);
            std::vector<float> got =
                optest::runPixel(*k, {double(n), 10.0, 20.0, 30.0, 40.0, 50.0});
            for (int slot = 0; slot < 2; ++slot) CHECK(got[slot] == xy[(slot + n) % 2]);
            for (int slot = 0; slot < 3; ++slot) CHECK(got[2 + slot] == abc[(slot + n) % 3]);
        }
    }
}

TEST_CASE("glsl: ne(x, x) is true exactly for NaN") {
    // The IR's NaN test (Builder::denan) is spelled isnan(x): the one comparison a driver
    // that assumed x == x could fold away.
    Function f = build(1, [](Builder& b) {
        ValueId x = b.uniform(0);
        b.output(0, b.select(b.emit(Op::Ne, {x, x}), b.constF(1.0), b.constF(0.0)));
    });
    CHECK(glsl::emitGlsl(f).find("isnan(v") != std::string::npos);
    compilesAndValidates(f);
    if (auto vk = vulkanOrNull()) {
        auto k = vk->compile(f);
        const double inf = std::numeric_limits<double>::infinity();
        for (double x : {0.0, -0.0, 1.0, -3.5, 1e30, inf, -inf}) {
            CAPTURE(x);
            CHECK(optest::runPixel(*k, {x})[0] == 0.0f);
        }
        CHECK(optest::runPixel(*k, {std::numeric_limits<double>::quiet_NaN()})[0] == 1.0f);
    }
}

TEST_CASE("glsl: powi is the binary exponentiation of semPowI") {
    std::vector<int64_t> exponents;
    for (int64_t n = -20; n <= 40; ++n) exponents.push_back(n);
    for (int64_t n : {63, 64, 100, 1000, 65537, 1048575}) exponents.push_back(n);
    auto vk = vulkanOrNull();
    const std::regex powiLine(R"(^\s*float (p\d+(_\d+)?|v\d+) = .*\bp\d+)");
    const std::vector<float> bases = {1.0001f, -0.9997f, 1.7f, -3.1f, 0.5f};
    for (int64_t n : exponents) {
        CAPTURE(n);
        Function f = build(1, [&](Builder& b) { b.output(0, b.powi(b.uniform(0), n)); });
        // Squarings for every bit below the top, and a product for every further set bit:
        // counted in the variables the emitter names after the result (p<id>, p<id>_<k>).
        const std::string source = glsl::emitGlsl(f);
        CAPTURE(source);
        const uint64_t e = static_cast<uint64_t>(n < 0 ? -n : n);
        const int want = e == 0 ? 0 : (std::bit_width(e) - 1) + (std::popcount(e) - 1);
        int multiplications = 0;
        std::istringstream lines(source);
        for (std::string line; std::getline(lines, line);)
            if (std::regex_search(line, powiLine))
                multiplications += static_cast<int>(std::count(line.begin(), line.end(), '*'));
        CHECK(multiplications == want);
        compilesAndValidates(f);
        if (!vk) continue;
        auto k = vk->compile(f);
        for (float x : bases) {
            CAPTURE(x);
            float got = optest::runPixel(*k, {x})[0];
            // Multiplications are correctly rounded on Vulkan, so the same order gives the same
            // float; a negative exponent starts from 1 / x, which may be 2.5 ULP off.
            if (n >= 0)
                CHECK(optest::sameValue(got, semPowI<float>(x, n)));
            else
                CHECK(optest::withinVulkanPrecision(Op::PowI, n, x, 0.0f, got));
        }
    }
}

// The WebGL dialect (`moire export`): a GLSL ES 3.00 fragment shader.
namespace {
void validEs(const std::string& source) {
    std::string log;
    INFO("glslang: ", log);
    CHECK(glsl::validateGlslEs(source, &log));
}
} // namespace

TEST_CASE("glsl: every op becomes a GLSL ES 3.00 fragment shader that glslang accepts") {
    for (int i = 0; i < kNumOps; ++i) {
        const Op op = static_cast<Op>(i);
        std::string opName = spelling(op);
        CAPTURE(opName);
        Function f = kernelUsing(op);
        const Kind kind = optest::kindOf(op);
        if (kind == Kind::FrameLeaf || op == Op::DerivX || op == Op::DerivY) {
            CHECK_THROWS_AS(glsl::emitGlsl(f, glsl::Dialect::WebGl), InternalError);
            continue;
        }
        std::string source;
        REQUIRE_NOTHROW(source = glsl::emitGlsl(f, glsl::Dialect::WebGl));
        CAPTURE(source);
        validEs(source);
    }
}

TEST_CASE(
    "glsl: the WebGL shader reads uniforms four to a vec4 and writes RGBA, nothing of Vulkan") {
    Function f = build(4, [](Builder& b) {
        for (int k = 0; k < 4; ++k)
            b.output(k, b.add(b.uniform(k + 2), b.mul(b.leaf(Op::PixelX), b.leaf(Op::PixelY))));
    });
    const std::string source = glsl::emitGlsl(f, glsl::Dialect::WebGl);
    CAPTURE(source);
    CHECK(glsl::uniformCount(f) == 6);
    CHECK(glsl::uniformVectors(f) == 2);
    CHECK(source.rfind("#version 300 es\n", 0) == 0);
    CHECK(source.find("uniform vec4 m_u[2];") != std::string::npos);
    for (const char* slot : {"m_u[0].z", "m_u[0].w", "m_u[1].x", "m_u[1].y"})
        CHECK(source.find(slot) != std::string::npos);
    CHECK(source.find("m_color = vec4(r0, r1, r2, r3);") != std::string::npos);
    // Rows from the top, as the IR counts them; gl_FragCoord counts from the bottom.
    CHECK(source.find("pixelY = m_image.y - gl_FragCoord.y") != std::string::npos);
    for (const char* vulkan : {"#extension", "layout(", "buffer", "gl_GlobalInvocationID", "U.u["})
        CHECK(source.find(vulkan) == std::string::npos);
    validEs(source);
    // The Vulkan shader of the same kernel is unchanged by the dialect's existence.
    CHECK(glsl::emitGlsl(f).find("U.u[5]") != std::string::npos);
    compilesAndValidates(f);
}

TEST_CASE("glsl: a shader glslang rejects as GLSL ES is reported with its log") {
    std::string log;
    CHECK_FALSE(glsl::validateGlslEs("#version 300 es\nprecision highp float;\nout vec4 c;\n"
                                     "void main() { c = vec4(undeclared); }\n",
                                     &log));
    CHECK(log.find("undeclared") != std::string::npos);
}
