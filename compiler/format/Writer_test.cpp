// The formatter's writer: indentation, spaces, blank lines, columns, and going back to a mark.
#include "compiler/format/Writer.h"

#include <doctest/doctest.h>

using namespace moire::format;

TEST_CASE("format writer: lines begin at the indentation, words follow after one space") {
    Writer w;
    w.put("scene", false);
    w.put("{", true);
    w.indent = 4;
    w.newline();
    w.put("size", false);
    w.put("=", true);
    CHECK(w.column() == 10);
    CHECK(w.lineIndent() == 4);
    w.newline();
    w.indent = 0;
    w.put("}", false);
    CHECK(w.finish() == "scene {\n    size =\n}\n");
}

TEST_CASE("format writer: one blank line at most, none at the start or just inside a brace") {
    Writer w;
    w.blank(); // nothing yet
    w.put("a", false);
    w.blank();
    w.blank();
    w.put("b", false);
    w.put("{", true);
    w.blank(); // just inside the brace
    w.indent = 4;
    w.put("c", false);
    CHECK(w.finish() == "a\n\nb {\n    c\n");
}

TEST_CASE("format writer: a required break ends the line before the next word") {
    Writer w;
    w.put("a", false);
    w.put("// note", true);
    w.requireBreak();
    CHECK_FALSE(w.lineOpen());
    w.indent = 2;
    w.put("b", true);
    CHECK(w.finish() == "a // note\n  b\n");
}

TEST_CASE("format writer: columns count characters, and a block comment's last line") {
    CHECK(Writer::width("abc") == 3);
    CHECK(Writer::width("\xC3\xA9t\xC3\xA9") == 3); // "été"
    Writer w;
    w.put("x", false);
    w.put("/* one\n   two */", true);
    CHECK(w.column() == 9);
    CHECK(w.linesEnded() == 1);
}

TEST_CASE("format writer: reset forgets everything put since the mark") {
    Writer w;
    w.put("layer", false);
    Writer::Mark m = w.mark();
    w.put("{", true);
    w.newline();
    w.put("x", false);
    w.reset(m);
    w.put("again", true);
    CHECK(w.finish() == "layer again\n");
}
