// textDocument/formatting against `moire fmt`'s own formatter on the same text.
#include "compiler/format/Formatter.h"
#include "lsp/SessionHelper_test.h"

using namespace moire;
using namespace moire::lsp;
using namespace moire::lsp::test;

TEST_CASE("lsp formatting: one edit to the formatter's text, none when already formatted") {
    const std::string messy = "layer a {family=circles;spacing = 6\n  stroke=1.7}\n\n\n"
                              "layer   b { family = lines; spacing = 5 } // kept\n";
    Server s;
    openDocument(s, messy);
    Json r = request(s, 2, "textDocument/formatting",
                     {{"textDocument", {{"uri", kUri}}}, {"options", {{"tabSize", 4}}}});
    REQUIRE(r.contains("result"));
    REQUIRE(r["result"].size() == 1);
    const Json& edit = r["result"][0];
    format::FormatResult want = format::formatSource("test.moire", messy);
    REQUIRE(want.ok);
    CHECK(edit["newText"].get<std::string>() == want.text);
    CHECK(edit["range"]["start"] == Json{{"line", 0}, {"character", 0}});
    CHECK(edit["range"]["end"] == Json{{"line", 5}, {"character", 0}}); // past the last newline

    Server again;
    openDocument(again, want.text);
    Json none = request(again, 3, "textDocument/formatting", {{"textDocument", {{"uri", kUri}}}});
    CHECK(none["result"] == Json::array());
}

TEST_CASE("lsp formatting: a document that does not parse is refused with its diagnostics") {
    Server s;
    openDocument(s, "layer a { family = circles; spacing = }\n");
    Json r = request(s, 2, "textDocument/formatting", {{"textDocument", {{"uri", kUri}}}});
    REQUIRE(r.contains("error"));
    CHECK(r["error"]["code"].get<int>() == -32803);
    CHECK(r["error"]["message"].get<std::string>().find("error:") != std::string::npos);
}
