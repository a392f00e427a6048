// No document crashes the server: the front end's fuzz corpus (the seeds fuzz/CMakeLists.txt
// gathers: the examples, the library, the diagnostics cases, and fuzz/regressions/), each cut
// short and with bytes spliced in, goes through every document feature at places all over it,
// and so do documents of random bytes. Every request gets an answer, never an internal error.
#include "lsp/SessionHelper_test.h"

#include <random>

using namespace moire;
using namespace moire::lsp;
using namespace moire::lsp::test;

namespace {

// The stdlib folder holds scenes/ too; the regressions are .moire files as well.
std::vector<std::string> corpus() {
    std::vector<std::string> out;
    for (const char* dir : {"examples", "stdlib", "tests/errors", "fuzz/regressions"})
        for (const std::string& path : sceneFiles(dir)) out.push_back(moire::test::readFile(path));
    return out;
}

// Every feature at `n` places spread over the document; each must answer without an error
// other than a refused rename.
void exercise(Server& s, const std::string& text, int n, int& id) {
    LineIndex index(text);
    const uint32_t lines = index.lineCount();
    auto answered = [&](const std::string& method, const Json& params) {
        Json r = request(s, ++id, method, params);
        bool ok = r.contains("result") ||
                  (r.contains("error") && r["error"]["code"] == ErrorCode::RequestFailed);
        if (!ok) FAIL_CHECK(method << " failed: " << r.dump());
    };
    const Json doc{{"textDocument", {{"uri", kUri}}}};
    answered("textDocument/documentSymbol", doc);
    answered("textDocument/semanticTokens/full", doc);
    answered("textDocument/foldingRange", doc);
    for (int i = 0; i < n; ++i) {
        uint32_t offset = text.empty() ? 0 : static_cast<uint32_t>(uint64_t(text.size()) * i / n);
        Position p = index.position(offset);
        Json place = at(int(p.line), int(p.character));
        answered("textDocument/hover", place);
        answered("textDocument/completion", place);
        answered("textDocument/definition", place);
        answered("textDocument/prepareRename", place);
        Json refs = place;
        refs["context"] = {{"includeDeclaration", true}};
        answered("textDocument/references", refs);
        Json rename = place;
        rename["newName"] = "renamed_name";
        answered("textDocument/rename", rename);
        answered(
            "textDocument/codeAction",
            {{"textDocument", {{"uri", kUri}}},
             {"range", {{"start", toJson(p)}, {"end", toJson({std::min(p.line + 1, lines), 0})}}},
             {"context", {{"diagnostics", Json::array()}}}});
    }
}

// Replaces the text; with no debounce, its diagnostics come back at once. Returns them.
Json change(Server& s, const std::string& text, int version) {
    std::vector<Json> out = notify(s, "textDocument/didChange",
                                   {{"textDocument", {{"uri", kUri}, {"version", version}}},
                                    {"contentChanges", {{{"text", text}}}}});
    REQUIRE(out.size() == 1); // no error answer to a notification, only the diagnostics
    CHECK(out[0]["method"] == "textDocument/publishDiagnostics");
    CHECK(out[0]["params"]["version"] == version);
    return out[0]["params"]["diagnostics"];
}

// JSON carries text, so bytes that are not UTF-8 reach the server as U+FFFD.
std::string asUtf8(const std::string& bytes) {
    return Json::parse(dumpJson(Json(bytes))).get<std::string>();
}

} // namespace

TEST_CASE("lsp robustness: the fuzz corpus, cut short and spliced, never breaks a feature") {
    std::vector<std::string> texts = corpus();
    REQUIRE(texts.size() > 100);
    std::mt19937 rng(16);
    Server s(std::chrono::milliseconds(0));
    openDocument(s, "");
    int id = 100, version = 1;
    for (const std::string& text : texts) {
        change(s, text, ++version);
        exercise(s, text, 6, id);
        // Cut short where the typing might be, and with a run of random bytes spliced in.
        for (int k = 1; k <= 3; ++k) {
            std::string cut = text.substr(0, text.size() * k / 4);
            change(s, cut, ++version);
            exercise(s, cut, 3, id);
            std::string spliced = cut;
            for (int j = 0; j < 8; ++j) spliced += static_cast<char>(rng() & 0xff);
            spliced += text.substr(cut.size());
            spliced = asUtf8(spliced);
            change(s, spliced, ++version);
            exercise(s, spliced, 3, id);
        }
    }
}

TEST_CASE("lsp robustness: documents of random bytes") {
    std::mt19937 rng(1234);
    Server s(std::chrono::milliseconds(0));
    openDocument(s, "");
    int id = 100;
    for (int round = 0; round < 40; ++round) {
        std::string bytes(rng() % 400, '\0');
        // Half of them in the language's alphabet, so that they get past the lexer.
        const std::string alphabet = "layer{}family=()+-*/^,;#0123456789.xyrt degrad\n//";
        for (char& c : bytes)
            c = round % 2 ? alphabet[rng() % alphabet.size()] : static_cast<char>(rng() & 0xff);
        std::string text = asUtf8(bytes);
        CHECK(change(s, text, round + 2).is_array());
        exercise(s, text, 5, id);
    }
}
