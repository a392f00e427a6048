// One list of reserved words, shared across the front end's layers (so this test sits above
// them): every declaration keyword begins a declaration, and every reserved word is refused
// as a user's name with the same message.
#include "compiler/Compile.h"
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Builtins.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>

using namespace moire;

TEST_CASE("keywords: each declaration keyword begins a declaration") {
    // A keyword the parser did not know would be "expected a declaration".
    for (const std::string& w : declarationKeywords()) {
        CAPTURE(w);
        CompileResult r = compileScene("kw.moire", w);
        REQUIRE(!r.diagnosticList.empty());
        CHECK(r.diagnosticList[0].message.find("expected a declaration") == std::string::npos);
    }
}

TEST_CASE("keywords: every reserved word is refused as a name, with the same message") {
    std::vector<std::string> words = declarationKeywords();
    words.push_back("let");
    for (const std::string& w : words) {
        CHECK(isKeyword(w));
        for (const char* form :
             {"field {} = 3", "family f({} = 1) = x", "family f {{ let {} = 1; phase = x }}",
              "timing {} {{ period = 1 }}"}) {
            std::string text = fmt::format(fmt::runtime(form), w);
            CAPTURE(text);
            CompileResult r = compileScene("kw.moire", text);
            REQUIRE(!r.diagnosticList.empty());
            CHECK(r.diagnosticList[0].id == "ReservedName");
            CHECK(r.diagnosticList[0].message ==
                  fmt::format("'{}' is a built-in name and cannot be redefined", w));
        }
    }
    CHECK_FALSE(isKeyword("circles"));
    CHECK_FALSE(isKeyword("builtin")); // a word of the standard library only
}

TEST_CASE("keywords: the lexer's built-in value names are the checker's") {
    for (const char* n : kBuiltinValueNames) {
        CAPTURE(n);
        REQUIRE(sema::lookupName(n).has_value());
        CHECK(std::string(sema::nameInfo(*sema::lookupName(n)).spelling) == n);
    }
    CHECK(sema::builtinNames().size() == std::size(kBuiltinValueNames));
    CHECK_FALSE(isBuiltinValueName("u"));
}
