// The language server on `param` declarations: hover, completion, the outline, references,
// rename and semantic tokens, each against the compiler's own view of the params
// (compiler/Parameters.h, the symbol table) or a value worked out by hand.
#include "compiler/Parameters.h"
#include "compiler/sema/Builtins.h"
#include "lsp/SessionHelper_test.h"

#include <fmt/format.h>
#include <map>
#include <set>

using namespace moire;
using namespace moire::lsp;
using namespace moire::lsp::test;

namespace {

const std::string kScene = R"(// How far apart the rings are.
param gap = 6 in 2 .. 12 step 0.5 unit px
param tilt = 10deg in 0deg .. 45deg
param shift = (4, -2) in -20 .. 20
param bold = false
param wide = gap * 1.5 + step(1, t)
layer a { family = circles; spacing = gap }
layer b { family = lines; spacing = wide; rotation = tilt; origin = shift
          stroke = select(bold, 4, 1) }
)";

// The character where `word` first appears on `line` of the scene, at or after `from`.
int column(int line, const std::string& word, size_t from = 0) {
    size_t start = 0;
    for (int i = 0; i < line; ++i) start = kScene.find('\n', start) + 1;
    std::string text = kScene.substr(start, kScene.find('\n', start) - start);
    size_t at = text.find(word, from);
    REQUIRE(at != std::string::npos);
    return static_cast<int>(at);
}

const Parameter& named(const SceneProgram& p, const std::string& name) {
    for (const Parameter& q : p.parameters)
        if (q.name == name) return q;
    FAIL("no param ", name);
    return p.parameters.front();
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// The scene with each edit applied (edits refer to the text before any of them).
std::string applied(const Json& edits, const std::string& text) {
    std::vector<std::tuple<uint32_t, uint32_t, std::string>> spans;
    LineIndex index(text);
    for (const Json& e : edits)
        spans.push_back({index.offset(positionFrom(e["range"]["start"])),
                         index.offset(positionFrom(e["range"]["end"])), e["newText"]});
    std::sort(spans.rbegin(), spans.rend());
    std::string out = text;
    for (const auto& [b, e, t] : spans) out.replace(b, e - b, t);
    return out;
}

} // namespace

TEST_CASE("lsp params: hover gives the type, value, range, step and unit the compiler read") {
    CompileResult r = compileScene("/scenes/test.moire", kScene);
    REQUIRE(r.program);
    Server s;
    REQUIRE(openDocument(s, kScene).empty());
    const Parameter& gap = named(*r.program, "gap");
    REQUIRE(gap.min);
    // At the declaration and at a use: the same words.
    std::string decl = hoverText(s, 1, column(1, "gap"));
    std::string use = hoverText(s, 6, column(6, "gap"));
    // (At the use, the layer's spacing it gives on the first frame follows: the default, 6.)
    CHECK(use.starts_with(decl));
    CHECK(has(use, "Value at t = 0: `6`"));
    CHECK(has(decl, "param gap = 6 in 2 .. 12 step 0.5 unit px"));
    CHECK(has(decl, "a number"));
    CHECK(has(decl, fmt::format("from {:g} to {:g}", *gap.min, *gap.max)));
    CHECK(has(decl, fmt::format("in steps of {:g}", *gap.step)));
    CHECK(has(decl, "shown in " + gap.unitLabel));
    CHECK(has(decl, "How far apart the rings are.")); // the comment above
    CHECK(!has(decl, "Value at t = 0"));              // a plain number is its own value
    // An angle, a vector whose range holds per component, a boolean.
    CHECK(has(hoverText(s, 7, column(7, "tilt")), "an angle"));
    CHECK(has(hoverText(s, 3, column(3, "shift")), "(each component)"));
    CHECK(has(hoverText(s, 8, column(8, "bold")), "a boolean"));
    // An expression of another param and t: its value on the first frame, by hand
    // 6 * 1.5 + step(1, 0) = 9.
    std::string wide = hoverText(s, 7, column(7, "wide"));
    CHECK(has(wide, "param wide = gap * 1.5 + step(1, t)"));
    CHECK(has(wide, "Value at t = 0: `9`"));
    // The words after a value, and the function step inside one.
    CHECK(has(hoverText(s, 1, column(1, "step")), "the step of a param's slider"));
    CHECK(has(hoverText(s, 1, column(1, "unit")), "a label shown beside"));
    CHECK(has(hoverText(s, 1, column(1, "in")), "the range a param's slider covers"));
    CHECK(has(hoverText(s, 5, column(5, "step")), sema::fnInfo(sema::Fn::Step).doc));
}

TEST_CASE("lsp params: completion offers params with the fields, and the words after a value") {
    Server s;
    // The lines that do not parse come last, so that the params before them are read.
    const std::string text = "param gap = 6\n"
                             "param q = 3 \n"
                             "param q2 = 3 in 0 .. 5 \n"
                             "param q3 = 3 step 1 \n"
                             "param q6 = sin(t) \n"
                             "layer a { family = circles; spacing =  }\n"
                             "param q4 = 3 in 0 \n"
                             "param q7 = \n"
                             "param q5 = 3 unit \n";
    openDocument(s, text);
    auto at_end = [&](int line) {
        size_t start = 0;
        for (int i = 0; i < line; ++i) start = text.find('\n', start) + 1;
        return at(line, static_cast<int>(text.find('\n', start) - start));
    };
    using Set = std::set<std::string>;
    CHECK(labels(request(s, 30, "textDocument/completion", at_end(1))) ==
          Set{"in", "step", "unit"});
    CHECK(labels(request(s, 31, "textDocument/completion", at_end(2))) == Set{"step", "unit"});
    CHECK(labels(request(s, 32, "textDocument/completion", at_end(3))) == Set{"unit"});
    CHECK(labels(request(s, 33, "textDocument/completion", at_end(4))) ==
          Set{"in", "step", "unit"});
    CHECK(labels(request(s, 34, "textDocument/completion", at_end(6))).empty()); // `..` next
    CHECK(labels(request(s, 35, "textDocument/completion", at_end(8))).empty()); // a label
    // In a layer's value and in a param's: the functions (step among them) and the params.
    for (int line : {5, 7}) {
        Set value =
            labels(request(s, 36, "textDocument/completion", line == 5 ? at(5, 38) : at_end(7)));
        CHECK(value.count("gap"));
        CHECK(value.count("q6"));
        CHECK(value.count("step"));
        CHECK(value.count("select"));
        CHECK(!value.count("in"));
    }
}

TEST_CASE("lsp params: the outline, references and rename follow the symbol table") {
    Server s;
    openDocument(s, kScene);
    Json symbols = request(s, 40, "textDocument/documentSymbol",
                           {{"textDocument", {{"uri", kUri}}}})["result"];
    std::map<std::string, int> kinds;
    for (const Json& sym : symbols) kinds[sym["name"]] = sym["kind"];
    for (const char* p : {"gap", "tilt", "shift", "bold", "wide"}) CHECK(kinds[p] == 14);

    CompileResult r = compileScene("/scenes/test.moire", kScene);
    const sema::Symbol* gap = r.symbols.find(sema::SymbolKind::SceneParam, "gap");
    REQUIRE(gap);
    REQUIRE(gap->references.size() == 2); // in wide, and layer a's spacing
    Json refs = request(s, 41, "textDocument/references",
                        {{"textDocument", {{"uri", kUri}}},
                         {"position", {{"line", 6}, {"character", column(6, "gap")}}},
                         {"context", {{"includeDeclaration", true}}}})["result"];
    CHECK(refs.size() == gap->references.size() + 1);
    std::set<int> lines;
    for (const Json& loc : refs) lines.insert(loc["range"]["start"]["line"].get<int>());
    CHECK(lines == std::set<int>{1, 5, 6});
    Json def = request(s, 42, "textDocument/definition", at(5, column(5, "gap")))["result"];
    CHECK(def["range"]["start"]["line"] == 1);

    // Renamed, the scene compiles to the same kernel, with the same params under the new name.
    Json prep = request(s, 43, "textDocument/prepareRename", at(6, column(6, "gap")))["result"];
    CHECK(prep["placeholder"] == "gap");
    auto rename = [&](const std::string& name) {
        return request(s, 44, "textDocument/rename",
                       {{"textDocument", {{"uri", kUri}}},
                        {"position", {{"line", 1}, {"character", column(1, "gap")}}},
                        {"newName", name}});
    };
    Json edits = rename("ring_gap")["result"]["changes"][kUri];
    CHECK(edits.size() == 3);
    std::string renamed = applied(edits, kScene);
    CompileResult after = compileScene("/scenes/test.moire", renamed);
    REQUIRE(after.program);
    CHECK(after.program->kernelHash == r.program->kernelHash);
    CHECK(named(*after.program, "ring_gap").max == named(*r.program, "gap").max);
    // Another param's name, and a boolean's: refused.
    CHECK(rename("wide")["error"]["code"] == ErrorCode::RequestFailed);
    CHECK(rename("true")["error"]["code"] == ErrorCode::RequestFailed);
    // The library's family the scene names shares the space of names: refused too (taken,
    // the param would hide the family layer a draws).
    CHECK(rename("circles")["error"]["code"] == ErrorCode::RequestFailed);
    // `in` and `unit` are free names elsewhere: a param may take one.
    CHECK(rename("unit")["result"]["changes"][kUri].size() == 3);
}

TEST_CASE("lsp params: semantic tokens tell a param's words from the function step") {
    Server s;
    openDocument(s, kScene);
    DecodedTokens decoded = semanticTokensOf(s);
    auto& types = decoded.types;
    auto& mods = decoded.modifiers;
    CHECK(types[{1, 0}] == "keyword");                     // param
    CHECK(types[{1, column(1, "gap")}] == "variable");     // declared
    CHECK((mods[{1, column(1, "gap")}] & 1) == 1);         // ... with the declaration modifier
    CHECK(types[{1, column(1, " in") + 1}] == "keyword");  // in
    CHECK(types[{1, column(1, "step")}] == "keyword");     // step, the word
    CHECK(types[{1, column(1, "unit")}] == "keyword");     // unit
    CHECK(types[{1, column(1, "px")}] == "string");        // its label
    CHECK(types[{5, column(5, "step")}] == "function");    // step, the function
    CHECK(types[{5, column(5, "gap")}] == "variable");     // a use
    CHECK(types[{8, column(8, "bold")}] == "variable");    // a use in a layer
    CHECK(types[{4, column(4, "false")}] == "enumMember"); // a boolean
}
