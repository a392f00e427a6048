// Parameters (`param`) and `-D`: a value set in a param's literal slots (what a slider does)
// draws what the same value written into the scene draws, the kernel never changes, and
// `-D` on the command line is the same as editing the file.
#include "compiler/Parameters.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>

using namespace moire;

namespace {

// Every type a param takes, each used by a layer so that it reaches the pixels.
const char* kScene = R"(scene { size = (48, 32) }
param gap = 6 in 2 .. 12 step 0.5 unit px
param tilt = 10deg in 0deg .. 45deg
param shift = (4, -2) in -20 .. 20
param ink = #203040
param bold = false
param wide = gap * 1.5
layer a { family = circles; spacing = gap; color = ink }
layer b { family = lines; spacing = wide; rotation = tilt; origin = shift
          stroke = select(bold, 4, 1) }
)";

const Parameter& named(const SceneProgram& p, const std::string& name) {
    for (const Parameter& q : p.parameters)
        if (q.name == name) return q;
    FAIL("no param ", name);
    return p.parameters.front();
}

// The scene with `name`'s default replaced by `text`: the independent way to get a value.
std::string edited(const std::string& scene, const std::string& name, const std::string& text) {
    std::string decl = "param " + name + " = ";
    size_t at = scene.find(decl);
    REQUIRE(at != std::string::npos);
    at += decl.size();
    size_t end = scene.find_first_of(" \n", at);
    if (scene[at] == '(') end = scene.find(')', at) + 1;
    return scene.substr(0, at) + text + scene.substr(end);
}

Defines defineOf(const std::string& target, const std::string& value) {
    Defines d;
    d.commandLine = "moire render s.moire -D " + target + "=" + value;
    Define def;
    def.target = target;
    def.value = value;
    def.targetOffset = d.commandLine.size() - value.size() - 1 - target.size();
    def.valueOffset = d.commandLine.size() - value.size();
    d.list.push_back(def);
    return d;
}

struct Case {
    const char* name;
    const char* text;          // the value as source
    std::vector<double> value; // the same value as a slider sets it
};
const Case kCases[] = {
    {"gap", "9.5", {9.5}},         {"tilt", "30deg", {30.0 * std::numbers::pi / 180.0}},
    {"shift", "(-7, 3)", {-7, 3}}, {"ink", "#c02010", {192 / 255.0, 32 / 255.0, 16 / 255.0, 1.0}},
    {"bold", "true", {1.0}},
};

} // namespace

TEST_CASE("params: what tools see of each declaration") {
    auto program = test::compileOk(kScene);
    REQUIRE(program->parameters.size() == 6);
    const Parameter& gap = named(*program, "gap");
    CHECK(gap.type == ast::Type::Num);
    CHECK(gap.components == 1);
    CHECK(*gap.min == 2);
    CHECK(*gap.max == 12);
    CHECK(*gap.step == 0.5);
    CHECK(gap.unitLabel == "px");
    const Parameter& tilt = named(*program, "tilt");
    CHECK(tilt.type == ast::Type::Angle);
    CHECK(tilt.unit == Unit::Deg);
    CHECK(*tilt.max == doctest::Approx(std::numbers::pi / 4));
    CHECK(named(*program, "shift").components == 2);
    CHECK(named(*program, "ink").components == 4);
    CHECK_FALSE(named(*program, "ink").min);
    CHECK(named(*program, "bold").type == ast::Type::Bool);
    // `0..5` reads as two numbers and a `..`, with no spaces needed.
    auto tight = test::compileOk("param a = 1 in 0..5 step .25\nlayer { family = circles; "
                                 "spacing = 4 + a }\n");
    CHECK(*tight->parameters[0].min == 0);
    CHECK(*tight->parameters[0].max == 5);
    CHECK(*tight->parameters[0].step == 0.25);
    // The default's text, as a write-back replaces it.
    const Parameter& shift = named(*program, "shift");
    CHECK(std::string_view(kScene).substr(shift.valueRange.begin.offset, shift.valueRange.length) ==
          "(4, -2)");
}

TEST_CASE("params: a value set in the slots draws what the value written in the scene draws") {
    auto program = test::compileOk(kScene);
    for (const std::string& name : test::availableBackends()) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        auto kernel = backend->compile(program->kernel);
        for (const Case& c : kCases) {
            CAPTURE(std::string(c.name));
            const Parameter& p = named(*program, c.name);
            CHECK(checkParameterValue(p, c.value).empty());
            std::vector<double> literals = program->literals;
            setParameterValue(p, c.value, literals);
            Image slid = test::runWithLiterals(*program, *kernel, literals);
            auto written = test::compileOk(edited(kScene, c.name, c.text));
            // Numbers only moved: the kernel is the one already compiled.
            CHECK(written->kernelHash == program->kernelHash);
            Image expected = test::renderScene(*written, *backend);
            test::ImageDiff d = test::compareImages(slid, expected, 0.0);
            CHECK(d.maxAbs == 0.0);
            // And the value did change the picture (so the comparison means something).
            Image before = test::runWithLiterals(*program, *kernel, program->literals);
            CHECK(test::compareImages(slid, before, 1e-3).over > 0);
        }
    }
}

TEST_CASE("params: -D is the value written in the scene, and never a new kernel for a number") {
    auto program = test::compileOk(kScene);
    for (const Case& c : kCases) {
        CAPTURE(std::string(c.name));
        auto defined = test::compileOk(kScene, {.defines = defineOf(c.name, c.text)});
        auto written = test::compileOk(edited(kScene, c.name, c.text));
        CHECK(defined->kernelHash == program->kernelHash);
        FrameValues a, b;
        std::string diags;
        REQUIRE(evaluateFrame(*defined, {}, a, diags));
        REQUIRE(evaluateFrame(*written, {}, b, diags));
        CHECK(a.uniforms == b.uniforms);
        // The param's own value, as tools read it back.
        const size_t at = static_cast<size_t>(&named(*defined, c.name) - &defined->parameters[0]);
        for (size_t i = 0; i < c.value.size(); ++i)
            CHECK(a.parameters[at][i] == doctest::Approx(c.value[i]));
    }
    // A layer's property: set, or added where the layer had none.
    auto stroke = test::compileOk(kScene, {.defines = defineOf("a.stroke", "2.5")});
    auto strokeWritten = test::compileOk(std::string(kScene).replace(
        std::string(kScene).find("color = ink }"), 13, "color = ink; stroke = 2.5 }"));
    FrameValues a, b;
    std::string diags;
    REQUIRE(evaluateFrame(*stroke, {}, a, diags));
    REQUIRE(evaluateFrame(*strokeWritten, {}, b, diags));
    CHECK(a.uniforms == b.uniforms);
}

TEST_CASE("params: a default that is an expression follows its inputs, once per frame") {
    auto program = test::compileOk(kScene + std::string("param pulse = 3 + t\n"
                                                        "layer { family = circles; "
                                                        "spacing = pulse }\n"));
    const Parameter& wide = named(*program, "wide");
    const Parameter& gap = named(*program, "gap");
    const size_t wideAt = static_cast<size_t>(&wide - &program->parameters[0]);
    const size_t pulseAt = program->parameters.size() - 1;
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(*program, FrameRequest{.time = 2.0}, fv, diags));
    CHECK(fv.parameters[wideAt][0] == doctest::Approx(9.0));
    CHECK(fv.parameters[pulseAt][0] == doctest::Approx(5.0));
    // Moving gap moves wide, which is defined by it.
    std::vector<double> literals = program->literals;
    const double g = 4;
    setParameterValue(gap, std::span(&g, 1), literals);
    REQUIRE(evaluateFrame(*program, FrameRequest{.literals = &literals}, fv, diags));
    CHECK(fv.parameters[wideAt][0] == doctest::Approx(6.0));
    // Set directly, wide no longer follows gap; cleared, it does again.
    const double w = 11;
    setParameterValue(wide, std::span(&w, 1), literals);
    REQUIRE(evaluateFrame(*program, FrameRequest{.literals = &literals}, fv, diags));
    CHECK(fv.parameters[wideAt][0] == doctest::Approx(11.0));
    clearParameterValue(wide, literals);
    REQUIRE(evaluateFrame(*program, FrameRequest{.literals = &literals}, fv, diags));
    CHECK(fv.parameters[wideAt][0] == doctest::Approx(6.0));
}

TEST_CASE("params: values a slider may not set") {
    auto program = test::compileOk(kScene);
    const Parameter& gap = named(*program, "gap");
    CHECK(checkParameterValue(gap, std::vector<double>{12.5}) ==
          "param 'gap' must be from 2 to 12, not 12.5");
    CHECK_FALSE(checkParameterValue(gap, std::vector<double>{1, 2}).empty());
    CHECK_FALSE(checkParameterValue(gap, std::vector<double>{NAN}).empty());
    CHECK_FALSE(checkParameterValue(named(*program, "bold"), std::vector<double>{0.5}).empty());
    CHECK_FALSE(
        checkParameterValue(named(*program, "ink"), std::vector<double>{0, 0, 1.5, 1}).empty());
    CHECK_FALSE(checkParameterValue(named(*program, "shift"), std::vector<double>{0, 21}).empty());
    CHECK(checkParameterValue(named(*program, "shift"), std::vector<double>{0, 20}).empty());
}

TEST_CASE("params: a value written back reads as the same value") {
    auto program = test::compileOk(kScene);
    const std::vector<std::pair<const char*, std::vector<double>>> values = {
        {"gap", {0.1 + 0.2 + 7}},      {"tilt", {0.3}}, {"shift", {-1.25, 1e-3}},
        {"ink", {1.0, 0.5, 0.0, 0.5}}, {"bold", {1.0}},
    };
    for (const auto& [name, value] : values) {
        CAPTURE(name);
        const Parameter& p = named(*program, name);
        std::string text = formatParameterValue(p, value);
        CAPTURE(text);
        auto back = test::compileOk(edited(kScene, name, text));
        const size_t at = static_cast<size_t>(&named(*back, name) - &back->parameters[0]);
        FrameValues fv;
        std::string diags;
        REQUIRE(evaluateFrame(*back, {}, fv, diags));
        for (size_t i = 0; i < value.size(); ++i) {
            // Colours are written in bytes; everything else exactly.
            const double tolerance = p.type == ast::Type::Color ? 0.5 / 255 : 1e-12;
            CHECK(std::fabs(fv.parameters[at][i] - value[i]) <= tolerance);
        }
    }
    CHECK(formatParameterValue(named(*program, "tilt"), std::vector<double>{std::numbers::pi / 6})
              .ends_with("deg"));
}

TEST_CASE("params: moire render -D equals the scene edited, for every type") {
    test::TempDir dir("params");
    dir.write("s.moire", kScene);
    for (const Case& c : kCases) {
        CAPTURE(std::string(c.name));
        dir.write("edited.moire", edited(kScene, c.name, c.text));
        auto run = [&](const std::string& args) {
            return test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                                    "' render -q " + args);
        };
        auto a = run("s.moire -o a.png -D '" + std::string(c.name) + "=" + c.text + "'");
        REQUIRE_MESSAGE(a.status == 0, a.err);
        auto b = run("edited.moire -o b.png");
        REQUIRE_MESSAGE(b.status == 0, b.err);
        Image ia = readImage(dir.file("a.png")), ib = readImage(dir.file("b.png"));
        CHECK(test::compareImages(ia, ib, 0.0).maxAbs == 0.0);
    }
    // Several at once, in either spelling of the option, on clip too.
    auto clip = test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                                 "' clip -q s.moire -o f_%02d.png --fps 1 --frames 1 "
                                 "--define gap=9.5 -Dbold=true");
    REQUIRE_MESSAGE(clip.status == 0, clip.err);
    dir.write("both.moire", edited(edited(kScene, "gap", "9.5"), "bold", "true"));
    auto both = test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                                 "' render -q both.moire -o both.png");
    REQUIRE(both.status == 0);
    // watch --once builds with the same values.
    auto watch = test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                                  "' watch --once -q s.moire -o w.png -D gap=9.5 -D bold=true");
    REQUIRE_MESSAGE(watch.status == 0, watch.err);
    CHECK(test::compareImages(readImage(dir.file("w.png")), readImage(dir.file("both.png")), 0.0)
              .maxAbs == 0.0);
    CHECK(test::compareImages(readImage(dir.file("f_00.png")), readImage(dir.file("both.png")), 0.0)
              .maxAbs == 0.0);
}

TEST_CASE("params: -D errors point into the command line and stop before any output") {
    test::TempDir dir("params");
    dir.write("s.moire", kScene);
    auto r = test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                              "' render s.moire -o out.png -D gap=40");
    CHECK(r.status == 1);
    CHECK(r.err.find("<command line>:1:40: error: param 'gap' must be from 2 to 12, not 40") !=
          std::string::npos);
    auto bad = test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() +
                                "' render s.moire -o out.png -D =3");
    CHECK(bad.status == 2);
    CHECK(bad.err.find("<command line>:1:") != std::string::npos);
    CHECK(dir.names() == std::vector<std::string>{"s.moire"});
}
