// The server's session: diagnostics exactly as `moire check --format=json` gives them (the
// real binary is the oracle, over every case of tests/errors/), debounced after changes,
// initialize and shutdown as LSP orders them, and malformed frames answered.
#include "lsp/SessionHelper_test.h"

using namespace moire;
using namespace moire::lsp;
using namespace moire::lsp::test;

namespace {

bool validUtf8(const std::string& text) {
    uint32_t cp = 0;
    for (size_t i = 0, n = 0; i < text.size(); i += n)
        if ((n = decodeUtf8(text, i, cp)) == 0) return false;
    return true;
}

} // namespace

TEST_CASE("lsp server: diagnostics are moire check's, message for message and range for range") {
    std::vector<std::string> cases = sceneFiles("tests/errors");
    REQUIRE(cases.size() > 50);
    std::string command = moire::test::moireBinary() + " check --format=json";
    for (const std::string& c : cases) command += " '" + c + "'";
    moire::test::CommandResult check = moire::test::runCommand(command);
    Json scenes = Json::parse(check.out)["scenes"];
    REQUIRE(scenes.size() == cases.size());
    for (const Json& scene : scenes) {
        const std::string path = scene["scene"];
        CAPTURE(path);
        // A file that is not UTF-8 cannot reach a server: JSON carries text.
        const std::string text = moire::test::readFile(path);
        if (!validUtf8(text)) continue;
        Server server;
        Json got = openDocument(server, text, pathToUri(path));
        const Json& want = scene["diagnostics"];
        REQUIRE(got.size() == want.size());
        for (size_t i = 0; i < want.size(); ++i) {
            CHECK(got[i]["message"] == want[i]["message"]);
            CHECK(got[i]["code"] == want[i]["id"]);
            CHECK(got[i]["severity"] == (want[i]["severity"] == "error" ? 1 : 3));
            const Json& r = want[i]["range"];
            if (r.is_null() || r["file"] != path) continue;
            // check counts 1-based lines and characters; LSP 0-based lines and UTF-16 units
            // (the same as characters in these files, which hold nothing beyond the BMP).
            CHECK(got[i]["range"]["start"]["line"] == r["start"]["line"].get<int>() - 1);
            CHECK(got[i]["range"]["start"]["character"] == r["start"]["column"].get<int>() - 1);
            CHECK(got[i]["range"]["end"]["line"] == r["end"]["line"].get<int>() - 1);
            CHECK(got[i]["range"]["end"]["character"] == r["end"]["column"].get<int>() - 1);
            // The "did you mean" replacement rides along for the quick fix.
            if (!want[i]["suggestion"].is_null())
                CHECK(got[i]["data"]["replacement"] == want[i]["suggestion"]["replacement"]);
        }
    }
}

TEST_CASE("lsp server: a change is diagnosed once the typing pauses, with its version") {
    Server server(std::chrono::milliseconds(40));
    Json first = openDocument(server, "layer { family = circles }\n");
    CHECK(first.empty());
    Clock::time_point t0 = Clock::now();
    Json change{{"textDocument", {{"uri", kUri}, {"version", 2}}},
                {"contentChanges",
                 {{{"range",
                    {{"start", {{"line", 0}, {"character", 17}}},
                     {"end", {{"line", 0}, {"character", 24}}}}},
                   {"text", "circels"}}}}};
    CHECK(notify(server, "textDocument/didChange", change, t0).empty()); // not yet
    REQUIRE(server.nextDue());
    CHECK(*server.nextDue() == t0 + std::chrono::milliseconds(40));
    CHECK(server.due(t0 + std::chrono::milliseconds(39)).empty());
    std::vector<std::string> out = server.due(t0 + std::chrono::milliseconds(40));
    REQUIRE(out.size() == 1);
    Json published = Json::parse(out[0])["params"];
    CHECK(published["version"] == 2);
    REQUIRE(published["diagnostics"].size() == 1);
    CompileResult direct = compileScene("/scenes/test.moire", "layer { family = circels }\n");
    REQUIRE(direct.diagnosticList.size() == 1);
    CHECK(published["diagnostics"][0]["message"] == direct.diagnosticList[0].message);
    CHECK(!server.nextDue()); // published once
}

TEST_CASE("lsp server: requests before initialize and after shutdown are refused") {
    Server server;
    Json early = request(server, 1, "textDocument/hover", at(0, 0));
    CHECK(early["error"]["code"] == ErrorCode::ServerNotInitialized);
    Json init = request(server, 2, "initialize", {{"capabilities", Json::object()}});
    CHECK(init["result"]["capabilities"]["hoverProvider"] == true);
    CHECK(init["result"]["capabilities"]["textDocumentSync"]["change"] == 2);
    CHECK(request(server, 3, "shutdown", nullptr)["result"].is_null());
    CHECK(request(server, 4, "textDocument/hover", at(0, 0))["error"]["code"] ==
          ErrorCode::InvalidRequest);
    CHECK(!server.exited());
    notify(server, "exit", nullptr);
    CHECK(server.exited());
    CHECK(server.exitStatus() == 0);

    Server abrupt;
    notify(abrupt, "exit", nullptr);
    CHECK(abrupt.exited());
    CHECK(abrupt.exitStatus() == 1); // exit without shutdown
}

TEST_CASE("lsp server: malformed frames and params are answered and the session goes on") {
    Server server;
    openDocument(server, "scene {}\n");
    std::vector<std::string> bad =
        server.receive({Frame::Kind::BadHeader, {}, "no Content-Length"});
    REQUIRE(bad.size() == 1);
    CHECK(Json::parse(bad[0])["error"]["code"] == ErrorCode::ParseError);
    bad = server.receive({Frame::Kind::Message, "{\"jsonrpc\": \"2.0\", \"id\": 3, ", {}});
    CHECK(Json::parse(bad[0])["error"]["code"] == ErrorCode::ParseError);
    CHECK(request(server, 5, "textDocument/hover",
                  {{"textDocument", {{"uri", kUri}}}})["error"]["code"] ==
          ErrorCode::InvalidParams);
    CHECK(request(server, 6, "textDocument/hover",
                  at(0, 0, "file:///not/open.moire"))["error"]["code"] == ErrorCode::InvalidParams);
    CHECK(request(server, 7, "moire/nothing", Json::object())["error"]["code"] ==
          ErrorCode::MethodNotFound);
    // A change that is not a content change, then one that is: the second applies.
    notify(server, "textDocument/didChange",
           {{"textDocument", {{"uri", kUri}, {"version", 2}}}, {"contentChanges", {{{"x", 1}}}}});
    notify(server, "textDocument/didChange",
           {{"textDocument", {{"uri", kUri}, {"version", 3}}},
            {"contentChanges", {{{"text", "camera {}\n"}}}}});
    CHECK(server.documents().find(kUri)->text == "camera {}\n");
    CHECK(request(server, 8, "shutdown", nullptr)["result"].is_null());
}

TEST_CASE("lsp server: closing a document clears its diagnostics") {
    Server server;
    Json d = openDocument(server, "layer { family = nothing }\n");
    CHECK(d.size() == 1);
    std::vector<Json> out =
        notify(server, "textDocument/didClose", {{"textDocument", {{"uri", kUri}}}});
    REQUIRE(out.size() == 1);
    CHECK(out[0]["params"]["diagnostics"].empty());
    CHECK(!server.documents().find(kUri));
}

TEST_CASE("lsp server: the library's files are served read-only by URI") {
    Server server;
    openDocument(server, "scene {}\n");
    Json r = request(server, 9, "workspace/textDocumentContent",
                     {{"uri", "moire-stdlib:///easings.moire"}});
    CHECK(r["result"]["text"].get<std::string>().find("easing cubic_in_out") != std::string::npos);
    CHECK(request(server, 10, "workspace/textDocumentContent",
                  {{"uri", "moire-stdlib:///x"}})["error"]["code"] == ErrorCode::InvalidParams);
}
