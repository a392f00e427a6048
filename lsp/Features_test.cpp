// Each feature against the compiler's own answers: the tables the checks read, the symbol
// table, the parsed library, and the first frame's values.
#include "compiler/sema/Builtins.h"
#include "compiler/sema/Properties.h"
#include "compiler/stdlib/Embedded.h"
#include "lsp/SessionHelper_test.h"
#include "runtime/FrameEval.h"

#include <cmath>
#include <set>

using namespace moire;
using namespace moire::lsp;
using namespace moire::lsp::test;

namespace {

const std::string kScene = R"(// A test scene.
scene { size = (400, 300) }
camera { zoom = 1 + sin(t + 0.5) * 0.25 }
field bump = 3 * x + y
timing slow { period = 4; easing = cubic_in_out }
family mine(k = 2) {
    let w = k * 2
    phase = r * w
}
layer a {
    family = wave
    amplitude = 12
    spacing = ramp(slow, 8, 12)
    field = bump
}
layer b { family = mine; k = 3 }
)";

// The names of the library's declarations of a kind, from the compiler's parse of it.
std::set<std::string> libraryNames(ast::DeclKind kind) {
    CompileResult r = compileScene("x.moire", "scene {}\n");
    std::set<std::string> out;
    for (const auto& m : r.frontEnd().modules)
        if (m.get() != &r.frontEnd().userModule())
            for (const ast::DeclPtr& d : m->decls)
                if (d->kind == kind) out.insert(d->name);
    return out;
}

// The text a location covers, in the scene or the library.
std::string textAt(const Json& loc) {
    std::string uri = loc["uri"];
    std::string text = uri == kUri ? kScene : std::string(*stdlibText(uri));
    LineIndex index(text);
    uint32_t b = index.offset(positionFrom(loc["range"]["start"]));
    uint32_t e = index.offset(positionFrom(loc["range"]["end"]));
    return text.substr(b, e - b);
}

} // namespace

TEST_CASE("lsp hover: the meaning comes from the tables the checks read") {
    Server s;
    REQUIRE(openDocument(s, kScene).empty());
    // A property: its line in sema's table.
    std::string zoom = hoverText(s, 2, 10);
    CHECK(zoom.find(sema::propertySpec(sema::cameraProperties(), "zoom").doc) != std::string::npos);
    // A function: the doc line of Builtins.
    CHECK(hoverText(s, 2, 21).find(sema::fnInfo(sema::Fn::Sin).doc) != std::string::npos);
    CHECK(hoverText(s, 2, 21).find("sin(v: number | angle) -> number") != std::string::npos);
    // A built-in name, the timing's properties (a table of their own).
    CHECK(hoverText(s, 2, 25).find(sema::nameInfo(sema::Name::T).what) != std::string::npos);
    CHECK(hoverText(s, 4, 32).find(sema::propertySpec(sema::timingProperties(), "easing").doc) !=
          std::string::npos);
    // A library family: its declaration line and the comment above it in the library.
    std::string wave = hoverText(s, 10, 14);
    CHECK(wave.find("family wave(amplitude = 10, frequency = 1, shift = 0deg)") !=
          std::string::npos);
    CHECK(wave.find("Waves travelling along y") != std::string::npos);
    // A family's parameter set by a layer, and the user's own family's.
    CHECK(hoverText(s, 11, 6).find("a parameter of the family wave (default 10)") !=
          std::string::npos);
    CHECK(hoverText(s, 15, 26).find("a parameter of the family mine (default 2)") !=
          std::string::npos);
    // Nothing under the cursor: no hover.
    CHECK(hoverText(s, 8, 1).empty());
}

TEST_CASE("lsp hover: an expression's value at t = 0 is the first frame's") {
    Server s;
    REQUIRE(openDocument(s, kScene).empty());
    std::string zoom = hoverText(s, 2, 22);
    auto pos = zoom.find("Value at t = 0: `");
    REQUIRE(pos != std::string::npos);
    double shown = std::stod(zoom.substr(pos + 17));
    // The oracle: the zoom the frame program computes for the first frame.
    CompileResult r = compileScene("/scenes/test.moire", kScene);
    REQUIRE(r.program);
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(*r.program, FrameRequest{}, frame, diags));
    CHECK(shown == doctest::Approx(frame.zoom).epsilon(1e-5));
    CHECK(frame.zoom == doctest::Approx(1 + std::sin(0.5) * 0.25)); // and by hand
    // A value through a timing: ramp(slow, 8, 12) starts at 8.
    std::string spacing = hoverText(s, 12, 20);
    CHECK(spacing.find("Value at t = 0: `8`") != std::string::npos);
    // A value that depends on the position has none.
    CHECK(hoverText(s, 3, 16).find("Value at") == std::string::npos);
}

TEST_CASE("lsp completion: what fits the place, from the compiler's tables and library") {
    Server s;
    const std::string text = "timing slow { period = 4; easing =  }\n"
                             "layer a {\n"
                             "    family = wave\n"
                             "    \n"
                             "    spacing = 1 + \n"
                             "}\n"
                             "layer b { family =  }\n"
                             "\n";
    openDocument(s, text);
    // In a layer after `family = wave`: the layer's properties and wave's parameters, less
    // what the block already wrote; no scene property.
    std::set<std::string> props = labels(request(s, 30, "textDocument/completion", at(3, 4)));
    for (const sema::PropertySpec& p : sema::layerProperties())
        if (std::string(p.name) != "family" && std::string(p.name) != "spacing")
            CHECK(props.count(p.name));
    CHECK(props.count("amplitude"));
    CHECK(props.count("frequency"));
    CHECK(!props.count("family"));
    CHECK(!props.count("size"));
    // After `family =`: every family of the library.
    std::set<std::string> families = labels(request(s, 31, "textDocument/completion", at(6, 19)));
    for (const std::string& f : libraryNames(ast::DeclKind::Family)) CHECK(families.count(f));
    CHECK(!families.count("sin"));
    // After `easing =`: every easing.
    std::set<std::string> easings = labels(request(s, 32, "textDocument/completion", at(0, 35)));
    CHECK(easings == libraryNames(ast::DeclKind::Easing));
    // In an expression: the functions and names of Builtins.
    std::set<std::string> expr = labels(request(s, 33, "textDocument/completion", at(4, 18)));
    for (const std::string& f : sema::builtinFunctions()) CHECK(expr.count(f));
    for (const std::string& n : sema::builtinNames()) CHECK(expr.count(n));
    CHECK(!expr.count("spacing"));
    // At the top level: the declaration keywords.
    std::set<std::string> top = labels(request(s, 34, "textDocument/completion", at(7, 0)));
    CHECK(top == std::set<std::string>{"scene", "camera", "layer", "field", "family", "timing",
                                       "easing", "param"});
}

TEST_CASE("lsp navigation: definition and references follow the compiler's symbols") {
    Server s;
    openDocument(s, kScene);
    // `bump` in the layer: its declaration in the scene.
    Json def = request(s, 40, "textDocument/definition", at(13, 14))["result"];
    CHECK(def["uri"] == kUri);
    CHECK(textAt(def) == "bump");
    CHECK(def["range"]["start"]["line"] == 3);
    // `wave`: into the library, read-only.
    def = request(s, 41, "textDocument/definition", at(10, 15))["result"];
    CHECK(def["uri"] == "moire-stdlib:///families.moire");
    CHECK(textAt(def) == "wave");
    // `sin`: built in, nowhere to go.
    CHECK(request(s, 42, "textDocument/definition", at(2, 21))["result"].is_null());
    // The references to `k`: the let's use and the layer's setting.
    Json refs = request(s, 43, "textDocument/references",
                        {{"textDocument", {{"uri", kUri}}},
                         {"position", {{"line", 5}, {"character", 12}}},
                         {"context", {{"includeDeclaration", true}}}})["result"];
    CompileResult r = compileScene("/scenes/test.moire", kScene);
    const sema::Symbol* k = r.symbols.find(sema::SymbolKind::Param, "k");
    REQUIRE(k);
    CHECK(refs.size() == k->references.size() + 1);
    for (const Json& loc : refs) CHECK(textAt(loc) == "k");
}

TEST_CASE("lsp rename: the user's names change everywhere; built-ins and the library's refuse") {
    Server s;
    openDocument(s, kScene);
    Json prep = request(s, 50, "textDocument/prepareRename", at(4, 8))["result"];
    CHECK(prep["placeholder"] == "slow");
    Json edit = request(s, 51, "textDocument/rename",
                        {{"textDocument", {{"uri", kUri}}},
                         {"position", {{"line", 4}, {"character", 8}}},
                         {"newName", "gentle"}})["result"];
    Json edits = edit["changes"][kUri];
    CHECK(edits.size() == 2); // the declaration and ramp(slow, ...)
    // Applied, the scene still compiles to the same kernel.
    std::string renamed = kScene;
    std::vector<std::pair<uint32_t, uint32_t>> spans;
    LineIndex index(kScene);
    for (const Json& e : edits)
        spans.push_back({index.offset(positionFrom(e["range"]["start"])),
                         index.offset(positionFrom(e["range"]["end"]))});
    std::sort(spans.rbegin(), spans.rend());
    for (auto [b, e] : spans) renamed.replace(b, e - b, "gentle");
    CompileResult before = compileScene("a.moire", kScene),
                  after = compileScene("a.moire", renamed);
    REQUIRE(after.program);
    CHECK(after.program->kernelHash == before.program->kernelHash);

    CHECK(request(s, 52, "textDocument/prepareRename", at(2, 21))["error"]["code"] ==
          ErrorCode::RequestFailed);
    CHECK(request(s, 53, "textDocument/prepareRename", at(10, 15))["error"]["code"] ==
          ErrorCode::RequestFailed);
    Json clash = request(s, 54, "textDocument/rename",
                         {{"textDocument", {{"uri", kUri}}},
                          {"position", {{"line", 4}, {"character", 8}}},
                          {"newName", "sin"}});
    CHECK(clash["error"]["code"] == ErrorCode::RequestFailed);
}

TEST_CASE("lsp code action: the did-you-mean suggestion as a quick fix") {
    Server s;
    const std::string text = "layer { family = circels }\n";
    Json diags = openDocument(s, text);
    REQUIRE(diags.size() == 1);
    CompileResult r = compileScene("/scenes/test.moire", text);
    REQUIRE(r.diagnosticList.at(0).suggestion);
    Json actions = request(s, 60, "textDocument/codeAction",
                           {{"textDocument", {{"uri", kUri}}},
                            {"range", diags[0]["range"]},
                            {"context", {{"diagnostics", diags}}}})["result"];
    REQUIRE(actions.size() == 1);
    CHECK(actions[0]["kind"] == "quickfix");
    Json edit = actions[0]["edit"]["changes"][kUri][0];
    CHECK(edit["newText"] == r.diagnosticList[0].suggestion->replacement);
    CHECK(edit["range"]["start"]["character"] ==
          r.diagnosticList[0].suggestion->range.start.column - 1);
    // Elsewhere in the file: none.
    Json none = request(
        s, 61, "textDocument/codeAction",
        {{"textDocument", {{"uri", kUri}}},
         {"range",
          {{"start", {{"line", 1}, {"character", 0}}}, {"end", {{"line", 1}, {"character", 0}}}}},
         {"context", {{"diagnostics", Json::array()}}}})["result"];
    CHECK(none.empty());
}

TEST_CASE("lsp outline, semantic tokens and folding follow the parsed scene") {
    Server s;
    openDocument(s, kScene);
    Json symbols = request(s, 70, "textDocument/documentSymbol",
                           {{"textDocument", {{"uri", kUri}}}})["result"];
    std::vector<std::string> names;
    for (const Json& sym : symbols) names.push_back(sym["name"]);
    CHECK(names == std::vector<std::string>{"scene", "camera", "bump", "slow", "mine", "a", "b"});
    // The family `mine` holds its parameter, its let and its phase.
    std::set<std::string> children;
    for (const Json& c : symbols[4]["children"]) children.insert(c["name"]);
    CHECK(children == std::set<std::string>{"k", "w", "phase"});

    // Decoded: the type of the token at each (line, character).
    std::map<std::pair<int, int>, std::string> types = semanticTokensOf(s).types;
    CHECK(types[{0, 0}] == "comment");
    CHECK(types[{1, 0}] == "keyword");    // scene
    CHECK(types[{2, 20}] == "function");  // sin
    CHECK(types[{2, 24}] == "variable");  // t
    CHECK(types[{3, 6}] == "variable");   // bump, declared
    CHECK(types[{4, 7}] == "event");      // slow
    CHECK(types[{5, 12}] == "parameter"); // k
    CHECK(types[{10, 13}] == "type");     // wave
    CHECK(types[{11, 4}] == "property");  // amplitude
    CHECK(types[{11, 16}] == "number");   // 12

    Json folds =
        request(s, 73, "textDocument/foldingRange", {{"textDocument", {{"uri", kUri}}}})["result"];
    std::set<std::pair<int, int>> spans;
    for (const Json& f : folds) spans.insert({f["startLine"].get<int>(), f["endLine"].get<int>()});
    CHECK(spans == std::set<std::pair<int, int>>{{5, 8}, {9, 14}});
}
