// The JavaScript frame backend on its own: every op of Ops.def is translated or refused with
// a reason, and what it writes, run by node, gives the interpreter's results for each op over
// awkward inputs (signed zeros, infinities, NaN, integer overflow) and for nested loops and
// branches. Scenes' frame programs against FrameEval: runtime/export/PiecePage_test.cpp.
#include "compiler/backend/js/JsFrame.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/ir/Semantics.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <limits>
#include <sstream>

using namespace moire;
using namespace moire::ir;
using optest::Kind;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A frame program with one output that applies `op` to literal slots 0 and 1 (and the clock),
// or null for the ops refused. Booleans and integers come out as 1/0 and as floats.
std::optional<Function> frameUsing(Op op, int64_t exponent = 3) {
    if (js::refusal(op)) return std::nullopt;
    return optest::build(1, [&](Builder& b) {
        ValueId x = b.param(0), y = b.param(1);
        auto number = [&](ValueId v) {
            switch (b.function().type(v)) {
            case Type::B:
                return b.select(v, b.constF(1.0), b.constF(0.0));
            case Type::I:
                return b.emit(Op::IToF, {v});
            default:
                return v;
            }
        };
        ValueId r = x;
        switch (optest::kindOf(op)) {
        case Kind::Leaf: // the constants: a value each that a careless spelling would change
            r = op == Op::ConstF   ? b.constF(-0.0)
                : op == Op::ConstI ? b.constI((int64_t(1) << 32) - 5)
                                   : b.constB(true);
            break;
        case Kind::FrameLeaf:
            r = op == Op::Time ? b.leaf(Op::Time) : b.param(1);
            break;
        case Kind::FloatUnary:
            r = b.emit(op, {x});
            break;
        case Kind::PowI:
            r = b.powi(x, exponent);
            break;
        case Kind::FloatBinary:
        case Kind::Compare:
            r = b.emit(op, {x, y});
            break;
        case Kind::Select:
            r = b.select(b.le(x, y), y, x);
            break;
        case Kind::Logic: {
            ValueId p = b.lt(x, y), q = b.emit(Op::Ne, {x, x});
            r = op == Op::Not ? b.emit(op, {p}) : b.emit(op, {p, q});
            break;
        }
        case Kind::IntArith:
        case Kind::IntCompare:
        case Kind::FToI:
        case Kind::IToF: {
            ValueId i = b.emit(Op::FToI, {x}), j = b.emit(Op::FToI, {y});
            r = optest::kindOf(op) == Kind::FToI || optest::kindOf(op) == Kind::IToF
                    ? i
                    : b.emit(op, {i, j});
            break;
        }
        case Kind::Control: // a loop counting x up to y in whole steps, inside an if
            r = b.ifThenElse(
                b.emit(Op::And, {b.lt(x, y), b.lt(b.sub(y, x), b.constF(1000.0))}),
                [&] {
                    return b.loop(
                        {x, b.constI(0)},
                        [&](std::span<const ValueId> p) {
                            return std::vector<ValueId>{b.lt(p[0], y)};
                        },
                        [&](std::span<const ValueId> p) {
                            return std::vector<ValueId>{b.add(p[0], b.constF(1.0)),
                                                        b.emit(Op::IAdd, {p[1], b.constI(1)})};
                        });
                },
                [&] {
                    return std::vector<ValueId>{b.constF(-1.0), b.constI(-1)};
                })[1];
            break;
        case Kind::Counter:
            b.emitSink(Op::Tally, {}, 0);
            break;
        case Kind::Sink:
        case Kind::Marker:
            break;
        }
        b.output(0, number(r));
    });
}

// Runs `program` (JavaScript) with node; its standard output, or nothing (with a skip) where
// there is no node.
std::optional<std::string> runNode(const std::string& program) {
    if (test::runCommand("command -v node").status != 0) {
        test::skip("node is not installed: the JavaScript is written, not run");
        return std::nullopt;
    }
    test::TempDir dir("jsframe");
    dir.write("run.js", program);
    test::CommandResult r = test::runCommand("node " + dir.file("run.js"));
    INFO(r.err);
    REQUIRE(r.status == 0);
    return r.out;
}

// A JavaScript number as text that strtod reads back exactly (String() gives the shortest
// round trip, "-0" for negative zero, "NaN", "Infinity").
constexpr const char* kPrintNumber =
    "const show = (v) => (Object.is(v, -0) ? \"-0\" : String(+v));\n";

// A double as a JavaScript literal.
std::string jsNumber(double v) {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    return fmt::format("{}", v);
}

double parseNumber(const std::string& s) {
    return std::strtod(s.c_str(), nullptr);
}

bool sameOrNear(double got, double want, bool exact) {
    if (std::isnan(want)) return std::isnan(got);
    if (got == want) return exact ? std::signbit(got) == std::signbit(want) : true;
    // libm and V8's Math differ in the last place for the transcendental functions.
    return !exact && std::isfinite(want) && std::fabs(got - want) <= 4e-16 * std::fabs(want);
}

// The ops whose result libm and V8 may round differently; the rest must agree exactly.
bool exactOp(Op op) {
    static const Op kLibm[] = {Op::Exp,  Op::Log,  Op::Pow,  Op::Sin,   Op::Cos,  Op::Tan,
                               Op::Asin, Op::Acos, Op::Atan, Op::Atan2, Op::Hypot};
    return std::find(std::begin(kLibm), std::end(kLibm), op) == std::end(kLibm);
}

} // namespace

TEST_CASE("js: every op is translated, or refused with the reason") {
    for (int i = 0; i < kNumOps; ++i) {
        const Op op = static_cast<Op>(i);
        std::string name = spelling(op);
        CAPTURE(name);
        if (const char* why = js::refusal(op)) {
            // The refused ops are exactly those a frame program cannot hold: the pixel's
            // inputs, the kernel's uniforms, the AD markers.
            const Kind kind = optest::kindOf(op);
            CHECK((kind == Kind::Marker || op == Op::Uniform || op == Op::PixelX ||
                   op == Op::PixelY || op == Op::ImageW || op == Op::ImageH));
            Function f = optest::build(1, [&](Builder& b) {
                b.output(0, kind == Kind::Marker ? b.emit(op, {b.param(0)}) : b.leaf(op));
            });
            try {
                js::emitFrameJs(f);
                FAIL("no error for a refused op");
            } catch (const InternalError& e) {
                CHECK(std::string(e.what()).find(why) != std::string::npos);
            }
            continue;
        }
        std::optional<Function> f = frameUsing(op);
        REQUIRE(f);
        bool found = false;
        for (const Block& blk : f->blocks)
            for (const Inst& inst : blk.insts) found = found || inst.op == op;
        CHECK(found);
        CHECK_NOTHROW(js::emitFrameJs(*f));
    }
}

TEST_CASE("js: node gives the interpreter's result for every op over awkward inputs") {
    const std::vector<double> values = {0.0,  -0.0, 1.0,   -1.0,   0.5,   -2.5,
                                        3.0,  7.25, -0.75, 1e-300, 1e300, 2147483648.0,
                                        -3e9, kInf, -kInf, kNaN};
    struct Case {
        std::string op;
        double x, y;
        double want;
        bool exact;
    };
    std::vector<Case> cases;
    std::string program = kPrintNumber;
    program += "const literals = new Float64Array(2), out = new Float64Array(1);\n";
    auto add = [&](const Function& f, Op op, const std::string& label) {
        program += fmt::format("{{ const f = {};\n", js::emitFrameJs(f));
        for (double x : values)
            for (double y : values) {
                const double want = optest::interpret(f, {.params = {x, y}, .time = y}).at(0);
                cases.push_back({label, x, y, want, exactOp(op)});
                program += fmt::format("literals[0] = {}; literals[1] = {}; f(literals, {}, out); "
                                       "console.log(show(out[0]));\n",
                                       jsNumber(x), jsNumber(y), jsNumber(y));
            }
        program += "}\n";
    };
    for (int i = 0; i < kNumOps; ++i) {
        const Op op = static_cast<Op>(i);
        if (op == Op::PowI) {
            for (int64_t n : {-3, -1, 0, 1, 2, 5, 17})
                add(*frameUsing(op, n), op, fmt::format("powi {}", n));
        } else if (std::optional<Function> f = frameUsing(op)) {
            add(*f, op, spelling(op));
        }
    }
    std::optional<std::string> out = runNode(program);
    if (!out) return;
    std::vector<std::string> got = test::lines(*out);
    REQUIRE(got.size() == cases.size());
    int wrong = 0;
    for (size_t i = 0; i < cases.size() && wrong < 20; ++i) {
        const Case& c = cases[i];
        const double g = parseNumber(got[i]);
        if (sameOrNear(g, c.want, c.exact)) continue;
        ++wrong;
        FAIL_CHECK(c.op, "(", c.x, ", ", c.y, "): node gives ", got[i], ", the interpreter ",
                   fmt::format("{}", c.want));
    }
    CHECK(wrong == 0);
}

TEST_CASE("js: nested loops and branches, and carried values that trade places") {
    // The sum over i < n of (i odd: the sum of the squares below i, by an inner loop; even:
    // i / 2), while (a, b, c) turn to (b, c, a) each time round: a translation that wrote one
    // carried value before reading the next, or leaked a branch's value, gives other numbers.
    Function f = optest::build(4, [](Builder& b) {
        auto toFloat = [&](ValueId i) { return b.emit(Op::IToF, {i}); };
        auto squaresBelow = [&](ValueId limit) {
            auto counted = b.loop(
                {b.constI(0), b.constF(0.0)},
                [&](std::span<const ValueId> j) {
                    return std::vector<ValueId>{b.emit(Op::ILt, {j[0], limit})};
                },
                [&](std::span<const ValueId> j) {
                    ValueId square = b.mul(toFloat(j[0]), toFloat(j[0]));
                    return std::vector<ValueId>{b.emit(Op::IAdd, {j[0], b.constI(1)}),
                                                b.add(j[1], square)};
                });
            return std::vector<ValueId>{counted[1]};
        };
        ValueId n = b.emit(Op::FToI, {b.param(0)});
        auto cond = [&](std::span<const ValueId> p) {
            return std::vector<ValueId>{b.emit(Op::ILt, {p[0], n})};
        };
        auto body = [&](std::span<const ValueId> p) {
            ValueId i = p[0];
            ValueId odd =
                b.lt(b.constF(0.25), b.emit(Op::Fract, {b.mul(toFloat(i), b.constF(0.5))}));
            ValueId term = b.ifThenElse(
                odd, [&] { return squaresBelow(i); },
                [&] { return std::vector<ValueId>{b.mul(toFloat(i), b.constF(0.5))}; })[0];
            return std::vector<ValueId>{b.emit(Op::IAdd, {i, b.constI(1)}), b.add(p[1], term), p[3],
                                        p[4], p[2]};
        };
        auto outer = b.loop({b.constI(0), b.constF(0.0), b.param(1), b.param(2), b.leaf(Op::Time)},
                            cond, body);
        b.output(0, outer[1]);
        for (int k = 0; k < 3; ++k) b.output(1 + k, outer[2 + k]);
    });
    std::vector<std::vector<double>> want;
    std::string calls;
    for (int n : {0, 1, 2, 3, 4, 7, 10}) {
        calls += fmt::format(
            "f([{}, 10, 20], 30, out); console.log(Array.from(out, show).join(' '));\n", n);
        want.push_back(optest::interpret(f, {.params = {double(n), 10.0, 20.0}, .time = 30.0}));
        double sum = 0.0; // the same by hand: odd i adds (i - 1) i (2i - 1) / 6, even i adds i / 2
        for (int i = 0; i < n; ++i) sum += i % 2 ? (i - 1) * i * (2 * i - 1) / 6.0 : i / 2.0;
        CHECK(want.back()[0] == sum);
        CHECK(want.back()[1] == std::vector<double>{10, 20, 30}[n % 3]);
    }
    std::string program = kPrintNumber;
    program += fmt::format("const f = {};\nconst out = new Float64Array(4);\n{}",
                           js::emitFrameJs(f), calls);
    std::optional<std::string> out = runNode(program);
    if (!out) return;
    std::vector<std::string> got = test::lines(*out);
    REQUIRE(got.size() == want.size());
    for (size_t i = 0; i < want.size(); ++i) {
        std::istringstream words(got[i]);
        for (double w : want[i]) {
            std::string word;
            words >> word;
            CHECK(parseNumber(word) == w);
        }
    }
}
