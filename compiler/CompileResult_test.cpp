// compileScene's diagnostics for tools: the structured list (severity, place, message id,
// suggestion) says what the rendered text says. The oracle is the rendered text itself, read
// back: the `path:line:col: severity: message` line and the caret line under the source.
#include "compiler/Compile.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <string>
#include <vector>

using namespace moire;

namespace {

// Checks one located diagnostic against its own rendered text: the header names the same
// place, severity and message, and the caret line marks its columns.
void checkAgainstRendered(const LocatedDiagnostic& d) {
    CAPTURE(d.rendered);
    std::vector<std::string> ls = test::lines(d.rendered);
    REQUIRE(!ls.empty());
    const std::string kind = severityName(d.severity);
    if (!d.range) {
        CHECK(ls[0] == "moire: " + kind + ": " + d.message);
        CHECK(ls.size() == 1);
        return;
    }
    CHECK(ls[0] == fmt::format("{}:{}:{}: {}: {}", d.range->file, d.range->start.line,
                               d.range->start.column, kind, d.message));
    REQUIRE(ls.size() == 3);
    CHECK(ls[1].starts_with(fmt::format("{:>5} | ", d.range->start.line)));
    // The marks are ASCII (with the line's tabs kept): one byte a character of the line.
    const std::string marks = ls[2].substr(8);
    size_t caret = marks.find('^');
    REQUIRE(caret != std::string::npos);
    CHECK(caret + 1 == d.range->start.column);
    size_t run = marks.find_first_not_of("^~", caret);
    run = (run == std::string::npos ? marks.size() : run) - caret;
    if (d.range->end.line == d.range->start.line && d.range->length > 0)
        CHECK(run == d.range->end.column - d.range->start.column);
}

} // namespace

TEST_CASE("compile result: every error case's structured diagnostics match its rendered text") {
    int cases = 0, withSuggestion = 0;
    for (const auto& entry :
         std::filesystem::directory_iterator(test::sourcePath("tests/errors"))) {
        if (entry.path().extension() != ".moire") continue;
        std::string path = "tests/errors/" + entry.path().filename().string();
        CAPTURE(path);
        CompileResult r = compileScene(path, test::readFile(entry.path().string()));
        std::string joined;
        for (const LocatedDiagnostic& d : r.diagnosticList) {
            checkAgainstRendered(d);
            CHECK(!d.id.empty());
            joined += d.rendered;
            withSuggestion += d.suggestion.has_value();
        }
        CHECK(joined == r.diagnostics);
        if (!r.program) CHECK(!r.diagnosticList.empty());
        ++cases;
    }
    CHECK(cases >= 40);
    CHECK(withSuggestion >= 5);
}

TEST_CASE("compile result: the message id, severity and order are the engine's") {
    CompileResult r = compileScene("ids.moire", "field a = 1\nfield a = 2\n");
    REQUIRE(r.diagnosticList.size() == 2);
    CHECK(r.diagnosticList[0].id == "DuplicateDecl");
    CHECK(r.diagnosticList[0].severity == Severity::Error);
    CHECK(r.diagnosticList[0].message == "there is already a field named 'a'");
    CHECK(r.diagnosticList[0].range->start.line == 2);
    CHECK(r.diagnosticList[0].range->start.column == 7);
    CHECK(r.diagnosticList[1].id == "FirstDefinedHere");
    CHECK(r.diagnosticList[1].severity == Severity::Note);
    CHECK(r.diagnosticList[1].range->start.line == 1);
    CHECK(r.partial != nullptr);
    CHECK(&r.frontEnd() == r.partial.get());
}

TEST_CASE(
    "compile result: a 'did you mean' hint carries its replacement and the text it replaces") {
    struct Case {
        const char* text;
        const char* id;
        const char* replacement;
        const char* replaced; // the source text the replacement is for
    };
    const Case cases[] = {
        {"layer { family = circels }", "UnknownFamily", "circles", "circels"},
        {"feild a = 1", "Expected", "field", "feild"},
        {"layer { family = circles; rotation = 30dg }", "UnknownUnit", "30deg", "30dg"},
        {"timing d { period = 2; mode = bounce }", "BadMode", "pingpong", "bounce"},
        {"field a = sinn(x)", "UnknownFunction", "sin", "sinn"},
        {"layer { family = circles; strok = 2 }", "UnknownProperty", "stroke", "strok"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.text);
        CompileResult r = compileScene("hint.moire", c.text);
        REQUIRE(r.diagnosticList.size() == 1);
        const LocatedDiagnostic& d = r.diagnosticList[0];
        CHECK(d.id == c.id);
        CHECK(d.message.ends_with(fmt::format("; did you mean '{}'?", c.replacement)));
        REQUIRE(d.suggestion.has_value());
        CHECK(d.suggestion->replacement == c.replacement);
        const std::string text = c.text;
        const size_t at = text.find(c.replaced);
        CHECK(d.suggestion->range.file == "hint.moire");
        CHECK(d.suggestion->range.offset == at);
        CHECK(d.suggestion->range.length == std::string(c.replaced).size());
        CHECK(d.suggestion->range.start.line == 1);
        CHECK(d.suggestion->range.start.column == at + 1);
        CHECK(d.suggestion->range.end.column == at + 1 + std::string(c.replaced).size());
    }
    // A hint that only explains proposes no replacement.
    CompileResult r = compileScene("hint.moire", "layer { family = circles; spacing = 2x }");
    REQUIRE(r.diagnosticList.size() == 1);
    CHECK(r.diagnosticList[0].message.ends_with("; to multiply, write 2 * x"));
    CHECK_FALSE(r.diagnosticList[0].suggestion.has_value());
}

TEST_CASE("compile result: errors past the limit end the list with the note that counts them") {
    std::string text = "field a = 0";
    for (int i = 0; i < DiagEngine::kMaxErrors + 3; ++i) text += fmt::format(" + qq{}", i);
    CompileResult r = compileScene("many.moire", text);
    REQUIRE(r.diagnosticList.size() == DiagEngine::kMaxErrors + 1);
    const LocatedDiagnostic& last = r.diagnosticList.back();
    CHECK(last.id == "MoreErrors");
    CHECK(last.severity == Severity::Note);
    CHECK_FALSE(last.range.has_value());
    CHECK(last.rendered == "moire: note: 3 more errors not shown\n");
    CHECK(r.diagnostics.ends_with(last.rendered));
}

TEST_CASE("compile result: a good scene has no diagnostics and its front end is the program's") {
    CompileResult r = compileScene("good.moire", "layer { family = circles }");
    REQUIRE(r.program != nullptr);
    CHECK(r.diagnosticList.empty());
    CHECK(r.partial == nullptr);
    CHECK(&r.frontEnd() == r.program.get());
}
