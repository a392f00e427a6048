#include "runtime/serve/Token.h"

#include <doctest/doctest.h>
#include <set>

using namespace moire::serve;

TEST_CASE("serve token: 32 hex digits, different every run") {
    std::set<std::string> seen;
    for (int i = 0; i < 64; ++i) {
        std::string t = makeToken();
        CHECK(t.size() == 32);
        CHECK(t.find_first_not_of("0123456789abcdef") == std::string::npos);
        seen.insert(t);
    }
    CHECK(seen.size() == 64);
}

TEST_CASE("serve token: only the exact token matches") {
    const std::string token = "0123456789abcdef0123456789abcdef";
    CHECK(sameToken(token, token));
    CHECK_FALSE(sameToken("", token));
    CHECK_FALSE(sameToken(token.substr(0, 31), token));
    CHECK_FALSE(sameToken(token + "0", token));
    CHECK_FALSE(sameToken("1123456789abcdef0123456789abcdef", token));
    CHECK_FALSE(sameToken("0123456789abcdef0123456789abcdeF", token));
    CHECK_FALSE(sameToken("", "")); // no token is never a match
}
