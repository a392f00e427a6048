// The export page's parts against the engines `moire render` uses: for every example scene,
// the frame program as JavaScript (run by node) gives FrameEval's uniforms and settings at
// several instants, the kernel as GLSL ES is accepted by glslang, and the page carries both
// with the data its script reads. The page drawn in a browser: tests/web/export.test.js.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/backend/js/JsFrame.h"
#include "compiler/ir/OpTable_test.h"
#include "runtime/export/PiecePage.h"
#include "runtime/FrameEval.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sstream>

using namespace moire;

namespace {

std::unique_ptr<SceneProgram> compileExample(const std::string& path) {
    return test::compileOk(test::readFile(test::sourcePath(path)), {}, path);
}

// The JSON the page's script reads.
nlohmann::json pageData(const std::string& page) {
    const std::string open = "<script id=\"moire-data\" type=\"application/json\">";
    const size_t from = page.find(open);
    REQUIRE(from != std::string::npos);
    const size_t to = page.find("</script>", from);
    return nlohmann::json::parse(page.substr(from + open.size(), to - from - open.size()));
}

} // namespace

TEST_CASE("export: the frame program in JavaScript gives FrameEval's values for every example") {
    const std::vector<double> times = {0.0, 1.3, 7.1};
    std::string program = "const show = (v) => (Object.is(v, -0) ? \"-0\" : String(+v));\n";
    struct Expected {
        std::string scene;
        double t;
        std::vector<double> values; // the uniforms, then width, height and zoom
    };
    std::vector<Expected> expected;
    for (const std::string& scene : test::exampleScenes()) {
        CAPTURE(scene);
        std::unique_ptr<SceneProgram> p = compileExample(scene);
        REQUIRE(p);
        const int u = p->numUniforms;
        nlohmann::json literals = p->literals;
        program += fmt::format("{{ const f = {}; const lit = {}; const out = new "
                               "Float64Array({});\n",
                               js::emitFrameJs(p->frame), literals.dump(), p->frame.numOutputs);
        for (double t : times) {
            FrameValues fv;
            std::string diags;
            REQUIRE(evaluateFrame(*p, FrameRequest{t}, fv, diags));
            Expected e{scene, t, fv.uniforms};
            e.values.insert(e.values.end(), {double(fv.width), double(fv.height), fv.zoom});
            expected.push_back(std::move(e));
            using L = lower::OutputLayout;
            program +=
                fmt::format("f(lit, {}, out); console.log([...out.slice(0, {}), out[{}], "
                            "out[{}], out[{}]].map(show).join(' '));\n",
                            t, u, u + L::kSettingWidth, u + L::kSettingHeight, u + L::kSettingZoom);
        }
        program += "}\n";
    }
    if (test::runCommand("command -v node").status != 0) {
        test::skip("node is not installed: the JavaScript is written, not run");
        return;
    }
    test::TempDir dir("piece");
    dir.write("frames.js", program);
    test::CommandResult r = test::runCommand("node " + dir.file("frames.js"));
    INFO(r.err);
    REQUIRE(r.status == 0);
    std::vector<std::string> got = test::lines(r.out);
    REQUIRE(got.size() == expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        CAPTURE(expected[i].scene);
        CAPTURE(expected[i].t);
        std::istringstream words(got[i]);
        for (size_t k = 0; k < expected[i].values.size(); ++k) {
            CAPTURE(k);
            std::string word;
            REQUIRE(static_cast<bool>(words >> word));
            const double g = std::strtod(word.c_str(), nullptr), w = expected[i].values[k];
            // Both run in double; only libm's and V8's last place of sin, exp, ... may differ.
            if (std::isnan(w))
                CHECK(std::isnan(g));
            else
                CHECK(std::fabs(g - w) <= 1e-12 * std::max(1.0, std::fabs(w)));
        }
    }
}

TEST_CASE("export: every example's kernel is a GLSL ES shader glslang accepts") {
    for (const std::string& scene : test::exampleScenes()) {
        CAPTURE(scene);
        std::unique_ptr<SceneProgram> p = compileExample(scene);
        REQUIRE(p);
        std::string log;
        INFO(log);
        CHECK(glsl::validateGlslEs(glsl::emitGlsl(p->kernel, glsl::Dialect::WebGl), &log));
    }
}

TEST_CASE("export: the page carries the shader, the frame program and what its script reads") {
    std::unique_ptr<SceneProgram> p = compileExample("examples/wave_over_lines.moire");
    REQUIRE(p);
    PieceOptions o;
    o.title = "waves <&> \"lines\"";
    o.width = 320;
    o.height = 200;
    o.time = 1.5;
    o.loop = 4.0;
    o.moves = true;
    const std::string page = piecePage(*p, o);
    // Every marker of the template is filled; the title is HTML, escaped.
    CHECK(page.find("@MOIRE_") == std::string::npos);
    CHECK(page.find("<title>waves &lt;&amp;&gt; &quot;lines&quot;</title>") != std::string::npos);
    CHECK(page.find("width=\"320\" height=\"200\"") != std::string::npos);
    CHECK(page.find(js::emitFrameJs(p->frame)) != std::string::npos);
    // The page's own script is there, and nothing but the three scripts closes a <script>.
    CHECK(page.find("window.moirePiece = api;") != std::string::npos);
    size_t closes = 0;
    for (size_t at = 0; (at = page.find("</script", at)) != std::string::npos; ++at) ++closes;
    CHECK(closes == 3);

    const nlohmann::json data = pageData(page);
    CHECK(data["title"] == o.title);
    CHECK(data["width"] == 320);
    CHECK(data["height"] == 200);
    CHECK(data["time"] == 1.5);
    CHECK(data["loop"] == 4.0);
    CHECK(data["numUniforms"] == p->numUniforms);
    CHECK(data["uniformVectors"] == glsl::uniformVectors(p->kernel));
    CHECK(4 * data["uniformVectors"].get<int>() >= p->numUniforms);
    CHECK(data["frameOutputs"] == p->frame.numOutputs);
    CHECK(data["literals"].size() == p->literals.size());
    // The shader survives the trip through JSON inside HTML ('<' escaped) unchanged.
    CHECK(data["shader"] == glsl::emitGlsl(p->kernel, glsl::Dialect::WebGl));
    // The checks name frame outputs past the uniforms: the zoom's, the timings', the layers'.
    REQUIRE(data["checks"].size() >= 4);
    for (const auto& c : data["checks"]) {
        CHECK(c["output"].get<int>() >= p->numUniforms);
        CHECK(c["output"].get<int>() < p->frame.numOutputs);
    }
}

TEST_CASE("export: each param becomes a slider's data: its kind, range, slots and value output") {
    std::unique_ptr<SceneProgram> p = test::compileOk(
        "scene { size = (64, 40) }\n"
        "param gap = 8 in 4 .. 20 step 0.5 unit px\n"
        "param tilt = 10deg in 0deg .. 45deg\n"
        "param shift = (10, 0) in -40 .. 40\n"
        "param ink = #18181c\n"
        "param bold = false\n"
        "param wide = gap * 1.5 + sin(t)\n"
        "layer a { family = circles; spacing = gap; color = ink }\n"
        "layer b { family = lines; spacing = wide; rotation = tilt; origin = shift; stroke = "
        "select(bold, 3, 1.5) }\n");
    REQUIRE(p);
    PieceOptions o;
    o.width = 64;
    o.height = 40;
    const nlohmann::json params = pageData(piecePage(*p, o))["parameters"];
    REQUIRE(params.size() == 6);
    const std::vector<std::pair<std::string, std::string>> kinds = {
        {"gap", "number"}, {"tilt", "angle"}, {"shift", "vector"},
        {"ink", "color"},  {"bold", "bool"},  {"wide", "number"}};
    // The frame program's value of each param, where the page reads it to place the slider.
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(*p, FrameRequest{2.0}, fv, diags));
    optest::InterpInputs in;
    in.params = p->literals;
    in.time = 2.0;
    const std::vector<double> out = optest::interpret(p->frame, in);
    for (size_t i = 0; i < kinds.size(); ++i) {
        CAPTURE(kinds[i].first);
        const nlohmann::json& j = params[i];
        CHECK(j["name"] == kinds[i].first);
        CHECK(j["type"] == kinds[i].second);
        CHECK(j["components"] == p->parameters[i].components);
        CHECK(j["valueSlot"] == p->parameters[i].valueSlot);
        CHECK(j["setSlot"] == p->parameters[i].setSlot);
        for (int k = 0; k < p->parameters[i].components; ++k)
            CHECK(out.at(j["output"].get<size_t>() + k) == fv.parameters[i][k]);
    }
    CHECK(params[0]["min"] == 4.0);
    CHECK(params[0]["max"] == 20.0);
    CHECK(params[0]["step"] == 0.5);
    CHECK(params[0]["label"] == "px");
    CHECK(params[1]["unit"] == "deg");
    CHECK(params[1]["max"].get<double>() == doctest::Approx(45.0 * 3.14159265358979 / 180.0));
    CHECK_FALSE(params[3].contains("min")); // a colour has no range
    // wide = 1.5 gap + sin(t), evaluated at t = 2 as the page would.
    CHECK(fv.parameters[5][0] == doctest::Approx(12.0 + std::sin(2.0)));
}
