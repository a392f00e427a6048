// The formatter's token list: which comments lie before which token, how many line breaks
// come before each, and the bracket pairs.
#include "compiler/format/TokenList.h"

#include <doctest/doctest.h>

using namespace moire;
using namespace moire::format;

namespace {
struct Listed {
    SourceManager sm;
    uint32_t id;
    explicit Listed(const std::string& text) : id(sm.add("t.moire", text)) {}
};
} // namespace

TEST_CASE("format tokens: comments go with the token after them, line breaks are counted") {
    Listed f("a = 1 // one\n\n/* two */ b = (2)\r\n// three\r");
    TokenList t(f.sm, f.id);
    REQUIRE(t.size() == 9); // a = 1 b = ( 2 ) End
    CHECK(t[3].spelling == "b");
    CHECK(t[3].endComment - t[3].firstComment == 2);
    CHECK(t.comments()[0].text == "// one");
    CHECK(t.comments()[0].linesBefore == 0);
    CHECK(t.comments()[1].text == "/* two */");
    CHECK(t.comments()[1].linesBefore == 2);
    CHECK(t[3].linesBefore == 0); // on the line of the comment before it
    CHECK(t[3].gapBreak);
    CHECK(t.comments()[2].text == "// three"); // before End, its CR dropped
    CHECK(t[8].kind == Tok::End);
    CHECK(t[8].firstComment == 2);
    CHECK(t[5].match == 7);
    CHECK(t[7].match == 5);
    CHECK(t.sameLine(3, 7));
    CHECK_FALSE(t.sameLine(0, 3));
    CHECK(t.commentsBetween(2, 3));
    CHECK_FALSE(t.commentsBetween(3, 7));
}
