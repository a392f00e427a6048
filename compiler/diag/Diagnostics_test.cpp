// Rendering of diagnostics: the location line, the source line, and a caret line that stays
// under the right characters with tabs, multi-byte characters, control bytes and ranges
// that run past the end of the line. Also the cap on the number of errors.
#include "compiler/diag/Diagnostics.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {

// Renders one error over `length` bytes at byte `offset` of `text`.
std::string renderAt(const std::string& text, uint32_t offset, uint32_t length) {
    SourceManager sm;
    uint32_t id = sm.add("d.moire", text);
    DiagEngine diags(sm);
    diags.error({{id, offset}, length}, Msg::UnknownName, "q", "");
    return diags.render();
}

} // namespace

TEST_CASE("diagnostics: location, source line and caret") {
    CHECK(renderAt("field f = 1\nfield g = abc + 1\n", 22, 3) ==
          "d.moire:2:11: error: unknown name 'q'\n"
          "    2 | field g = abc + 1\n"
          "      |           ^~~\n");
}

TEST_CASE("diagnostics: tabs in the source are kept in the caret line") {
    CHECK(renderAt("\tfield\tg = abc\n", 11, 3) == "d.moire:1:12: error: unknown name 'q'\n"
                                                   "    1 | \tfield\tg = abc\n"
                                                   "      | \t     \t    ^~~\n");
}

TEST_CASE("diagnostics: columns and carets count characters, not bytes") {
    // "π" and "é" are two bytes each; the caret under "abc" moves two columns, not four.
    CHECK(renderAt("// \xCF\x80\xC3\xA9\nx = \xC3\xA9 + abc\n", 17, 3) ==
          "d.moire:2:9: error: unknown name 'q'\n"
          "    2 | x = \xC3\xA9 + abc\n"
          "      |         ^~~\n");
    // A range over one two-byte character is one caret, no tilde.
    CHECK(renderAt("a \xC3\xA9 b", 2, 2) == "d.moire:1:3: error: unknown name 'q'\n"
                                            "    1 | a \xC3\xA9 b\n"
                                            "      |   ^\n");
}

TEST_CASE("diagnostics: control bytes and invalid UTF-8 are shown as U+FFFD") {
    std::string text = std::string("a\0b \xFF c", 7);
    CHECK(renderAt(text, 6, 1) == "d.moire:1:7: error: unknown name 'q'\n"
                                  "    1 | a\xEF\xBF\xBD"
                                  "b \xEF\xBF\xBD c\n"
                                  "      |       ^\n");
}

TEST_CASE("diagnostics: a range is cut at the end of its line") {
    CHECK(renderAt("ab (1,\n 2)\n", 3, 7) == "d.moire:1:4: error: unknown name 'q'\n"
                                             "    1 | ab (1,\n"
                                             "      |    ^~~\n");
    // A caret just past the last character (a missing '}').
    CHECK(renderAt("scene {\n", 7, 1) == "d.moire:1:8: error: unknown name 'q'\n"
                                         "    1 | scene {\n"
                                         "      |        ^\n");
    // Windows line ends: the '\r' is not part of the line shown.
    CHECK(renderAt("abc\r\ndef\r\n", 5, 3) == "d.moire:2:1: error: unknown name 'q'\n"
                                              "    2 | def\n"
                                              "      | ^~~\n");
}

TEST_CASE("diagnostics: errors stop at the cap, and so do the notes that belong to them") {
    SourceManager sm;
    uint32_t id = sm.add("d.moire", "x\n");
    DiagEngine diags(sm);
    for (int i = 0; i < DiagEngine::kMaxErrors + 5; ++i) {
        diags.error({{id, 0}, 1}, Msg::DuplicateDecl, "field", "x");
        diags.note({{id, 0}, 1}, Msg::FirstDefinedHere);
    }
    CHECK(diags.errorCount() == DiagEngine::kMaxErrors);
    CHECK(diags.all().size() == 2 * DiagEngine::kMaxErrors);
    CHECK(diags.all().back().severity == Severity::Note);
    std::string text = diags.render();
    CHECK(text.substr(text.rfind("moire:")) == "moire: note: 5 more errors not shown\n");
}

TEST_CASE("diagnostics: a diagnostic without a location names the program") {
    SourceManager sm;
    DiagEngine diags(sm);
    diags.error({}, Msg::BadZoom, 0.0);
    CHECK(diags.render() == "moire: error: camera zoom must be positive and finite, not 0\n");
}
