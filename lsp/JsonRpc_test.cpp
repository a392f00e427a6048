// The dispatcher: every malformed message gets the error the specification names, and a
// handler's failure is that request's error, not the session's end.
#include "lsp/JsonRpc.h"

#include <doctest/doctest.h>

using namespace moire::lsp;

namespace {
Dispatcher make() {
    Dispatcher d;
    d.onRequest("add", [](const Json& p) { return p.at("a").get<int>() + p.at("b").get<int>(); });
    d.onRequest("refuse",
                [](const Json&) -> Json { throw RpcError(ErrorCode::RequestFailed, "no"); });
    d.onRequest("bug", [](const Json&) -> Json { throw std::logic_error("a bug"); });
    return d;
}
int code(const std::optional<Json>& r) {
    return r->at("error").at("code").get<int>();
}
} // namespace

TEST_CASE("lsp json-rpc: a request is answered with its id and result") {
    Dispatcher d = make();
    auto r = d.handle(R"({"jsonrpc":"2.0","id":7,"method":"add","params":{"a":2,"b":3}})");
    REQUIRE(r);
    CHECK((*r)["id"] == 7);
    CHECK((*r)["result"] == 5);
    r = d.handle(R"({"jsonrpc":"2.0","id":"x","method":"add","params":{"a":1,"b":1}})");
    CHECK((*r)["id"] == "x");
}

TEST_CASE("lsp json-rpc: malformed messages get the specification's errors") {
    Dispatcher d = make();
    CHECK(code(d.handle("{not json")) == ErrorCode::ParseError);
    CHECK(code(d.handle("[1,2]")) == ErrorCode::InvalidRequest);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":{},"method":"add"})")) ==
          ErrorCode::InvalidRequest);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":1})")) == ErrorCode::InvalidRequest);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":1,"method":"nope"})")) ==
          ErrorCode::MethodNotFound);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":1,"method":"add","params":{"a":"2"}})")) ==
          ErrorCode::InvalidParams);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":1,"method":"refuse"})")) ==
          ErrorCode::RequestFailed);
    CHECK(code(d.handle(R"({"jsonrpc":"2.0","id":1,"method":"bug"})")) == ErrorCode::InternalError);
    // Still answering after all that.
    CHECK((*d.handle(
              R"({"jsonrpc":"2.0","id":2,"method":"add","params":{"a":1,"b":2}})"))["result"] == 3);
}

TEST_CASE("lsp json-rpc: notifications are never answered, even when they fail") {
    Dispatcher d = make();
    int seen = 0;
    d.onNotification("ping", [&](const Json& p) { seen += p.at("n").get<int>(); });
    CHECK(!d.handle(R"({"jsonrpc":"2.0","method":"ping","params":{"n":2}})"));
    CHECK(seen == 2);
    CHECK(!d.handle(R"({"jsonrpc":"2.0","method":"ping","params":{}})"));
    CHECK(!d.handle(R"({"jsonrpc":"2.0","method":"$/cancelRequest","params":{"id":1}})"));
    CHECK(!d.handle(R"({"jsonrpc":"2.0","id":5,"result":null})")); // a client's response
}

TEST_CASE("lsp json-rpc: text that is not UTF-8 is replaced, not refused, when sent") {
    std::string s = dumpJson(Json{{"m", std::string("a\xff"
                                                    "b")}});
    CHECK(s == "{\"m\":\"a\xef\xbf\xbd"
               "b\"}");
}
