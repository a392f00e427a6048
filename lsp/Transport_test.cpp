// The framing reader: whole messages however the bytes arrive, and a malformed header reported
// and skipped so that the next message is still read.
#include "lsp/Transport.h"

#include <doctest/doctest.h>
#include <vector>

using namespace moire::lsp;

namespace {
std::vector<Frame> drain(FrameReader& r) {
    std::vector<Frame> out;
    while (auto f = r.next()) out.push_back(*f);
    return out;
}
} // namespace

TEST_CASE("lsp transport: messages arrive whole whether fed at once or byte by byte") {
    std::string wire = frameMessage(R"({"a":1})") + frameMessage("{\"b\":\"\xc3\xa9\"}");
    FrameReader whole;
    whole.feed(wire);
    std::vector<Frame> a = drain(whole);
    REQUIRE(a.size() == 2);
    CHECK(a[0].body == R"({"a":1})");
    CHECK(a[1].body == "{\"b\":\"\xc3\xa9\"}"); // Content-Length counts bytes, not characters

    FrameReader bytewise;
    std::vector<Frame> b;
    for (char c : wire) {
        bytewise.feed(std::string_view(&c, 1));
        for (Frame& f : drain(bytewise)) b.push_back(f);
    }
    REQUIRE(b.size() == 2);
    CHECK(b[1].body == a[1].body);
    CHECK(bytewise.pending() == 0);
}

TEST_CASE("lsp transport: header fields are case-insensitive and Content-Type is allowed") {
    FrameReader r;
    r.feed(
        "content-length: 2\r\nContent-Type: application/vscode-jsonrpc; charset=utf-8\r\n\r\n{}");
    std::vector<Frame> f = drain(r);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == Frame::Kind::Message);
    CHECK(f[0].body == "{}");
}

TEST_CASE("lsp transport: a malformed header is reported and the next message still read") {
    for (std::string bad : {"Content-Length: twelve\r\n\r\n{}", "X-Whatever: 1\r\n\r\n{}",
                            "Content-Length: -3\r\n\r\n", "garbage with no header end\n"}) {
        FrameReader r;
        r.feed(bad + frameMessage(R"({"ok":true})"));
        std::vector<Frame> f = drain(r);
        REQUIRE(f.size() >= 2);
        CHECK(f.front().kind == Frame::Kind::BadHeader);
        CHECK(!f.front().error.empty());
        CHECK(f.back().kind == Frame::Kind::Message);
        CHECK(f.back().body == R"({"ok":true})");
    }
}

TEST_CASE("lsp transport: a header that never ends, or a body too long, is refused") {
    FrameReader r;
    r.feed(std::string(kMaxHeaderBytes + 10, 'x'));
    std::vector<Frame> f = drain(r);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == Frame::Kind::BadHeader);
    CHECK(r.pending() < 64);

    FrameReader big;
    big.feed("Content-Length: 999999999999\r\n\r\nabc");
    f = drain(big);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == Frame::Kind::BadHeader);
    CHECK(big.pending() == 0); // its bytes are dropped, not kept
}
