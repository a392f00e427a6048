// DiagEngine::located(): each diagnostic resolved to its file, line and column (counted in
// characters, by hand below), byte offset and length, message id and suggestion, with the
// same text render() prints.
#include "compiler/diag/Diagnostics.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

TEST_CASE("located diagnostics: lines and columns count characters, ranges may span lines") {
    SourceManager sm;
    // "\xC3\xA9" is one character (e acute) of two bytes.
    const std::string text = "x = \xC3\xA9 + bad\n\tnext\n";
    uint32_t id = sm.add("u.moire", text);
    DiagEngine diags(sm);
    diags.error({{id, 9}, 3}, Msg::UnknownName, "bad", ""); // "bad"
    diags.note({{id, 9}, 7}, Msg::FirstDefinedHere);        // "bad\n\tnex"
    diags.error({{id, static_cast<uint32_t>(text.size())}, 1}, Msg::Expected, "'}'",
                "end of file"); // just past the end
    std::vector<LocatedDiagnostic> all = diags.located();
    REQUIRE(all.size() == 3);

    const LocatedDiagnostic& a = all[0];
    CHECK(a.severity == Severity::Error);
    CHECK(a.id == "UnknownName");
    CHECK(a.message == "unknown name 'bad'");
    REQUIRE(a.range.has_value());
    CHECK(a.range->file == "u.moire");
    CHECK(a.range->offset == 9);
    CHECK(a.range->length == 3);
    CHECK(a.range->start.line == 1);
    CHECK(a.range->start.column == 9); // x, space, =, space, e acute, space, +, space, b
    CHECK(a.range->end.line == 1);
    CHECK(a.range->end.column == 12);
    CHECK_FALSE(a.suggestion.has_value());

    const LocatedDiagnostic& b = all[1];
    CHECK(b.severity == Severity::Note);
    CHECK(b.id == "FirstDefinedHere");
    CHECK(b.range->end.line == 2);
    CHECK(b.range->end.column == 4); // after the tab, 'n' and 'e'

    const LocatedDiagnostic& c = all[2];
    CHECK(c.range->start.line == 3);
    CHECK(c.range->start.column == 1);
    CHECK(c.range->length == 0); // nothing of the text is past its end

    std::string joined;
    for (const LocatedDiagnostic& d : all) joined += d.rendered;
    CHECK(joined == diags.render());
}

TEST_CASE("located diagnostics: a hint's replacement becomes the suggestion") {
    SourceManager sm;
    uint32_t id = sm.add("h.moire", "rotation = 30dg\n");
    DiagEngine diags(sm);
    // Replacing the diagnostic's own range, and another range (the whole number).
    diags.error({{id, 11}, 4}, Msg::UnknownName, "30dg", suggest("30deg"));
    diags.error({{id, 13}, 2}, Msg::UnknownUnit, "dg", suggest("30deg", {{id, 11}, 4}));
    // A hint that only explains proposes nothing.
    diags.error({{id, 13}, 2}, Msg::UnknownUnit, "dg", Hint("; to multiply, write 30 * dg"));
    std::vector<LocatedDiagnostic> all = diags.located();
    REQUIRE(all.size() == 3);
    for (int i : {0, 1}) {
        CAPTURE(i);
        REQUIRE(all[i].suggestion.has_value());
        CHECK(all[i].suggestion->replacement == "30deg");
        CHECK(all[i].suggestion->range.offset == 11);
        CHECK(all[i].suggestion->range.length == 4);
        CHECK(all[i].suggestion->range.start.column == 12);
        CHECK(all[i].suggestion->range.end.column == 16);
        CHECK(all[i].message.ends_with("; did you mean '30deg'?"));
    }
    CHECK(all[1].range->start.column == 14); // the diagnostic itself points at the unit
    CHECK_FALSE(all[2].suggestion.has_value());
    CHECK(all[2].message.ends_with("; to multiply, write 30 * dg"));
}

TEST_CASE("located diagnostics: errors over the cap end with the note that counts them") {
    SourceManager sm;
    uint32_t id = sm.add("m.moire", "q\n");
    DiagEngine diags(sm);
    for (int i = 0; i < DiagEngine::kMaxErrors + 2; ++i)
        diags.error({{id, 0}, 1}, Msg::UnknownName, "q", "");
    std::vector<LocatedDiagnostic> all = diags.located();
    REQUIRE(all.size() == DiagEngine::kMaxErrors + 1);
    CHECK(all.back().id == "MoreErrors");
    CHECK(all.back().severity == Severity::Note);
    CHECK_FALSE(all.back().range.has_value());
    CHECK(all.back().rendered == "moire: note: 2 more errors not shown\n");
}
