// For the server's tests: a Server driven by JSON values, as a client would drive it.
#pragma once

#include "lsp/Server.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace moire::lsp::test {

inline std::vector<Json> send(Server& s, const Json& message,
                              Clock::time_point now = Clock::now()) {
    std::vector<Json> out;
    for (const std::string& body : s.receive({Frame::Kind::Message, dumpJson(message), {}}, now))
        out.push_back(Json::parse(body));
    return out;
}

inline Json request(Server& s, int id, const std::string& method, Json params) {
    for (Json& m :
         send(s, {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}}))
        if (m.contains("id") && m["id"] == id) return m;
    FAIL("no response to " << method);
    return nullptr;
}

inline std::vector<Json> notify(Server& s, const std::string& method, Json params,
                                Clock::time_point now = Clock::now()) {
    return send(s, {{"jsonrpc", "2.0"}, {"method", method}, {"params", params}}, now);
}

// The .moire files of a folder of the source tree (recursively), sorted.
inline std::vector<std::string> sceneFiles(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e :
         std::filesystem::recursive_directory_iterator(moire::test::sourcePath(dir)))
        if (e.is_regular_file() && e.path().extension() == ".moire") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

inline const std::string kUri = "file:///scenes/test.moire";

// An initialised server with `text` open as kUri; the diagnostics it published on opening.
inline Json openDocument(Server& s, const std::string& text, const std::string& uri = kUri) {
    request(s, 1, "initialize", Json::object());
    notify(s, "initialized", Json::object());
    std::vector<Json> out =
        notify(s, "textDocument/didOpen",
               {{"textDocument",
                 {{"uri", uri}, {"languageId", "moire"}, {"version", 1}, {"text", text}}}});
    REQUIRE(out.size() == 1);
    REQUIRE(out[0]["method"] == "textDocument/publishDiagnostics");
    return out[0]["params"]["diagnostics"];
}

inline Json at(int line, int character, const std::string& uri = kUri) {
    return {{"textDocument", {{"uri", uri}}},
            {"position", {{"line", line}, {"character", character}}}};
}

// The hover's text at a place of kUri ("" when there is none).
inline std::string hoverText(Server& s, int line, int character) {
    Json r = request(s, 20, "textDocument/hover", at(line, character));
    return r["result"].is_null() ? "" : r["result"]["contents"]["value"].get<std::string>();
}

// The labels of a completion response.
inline std::set<std::string> labels(const Json& completion) {
    std::set<std::string> out;
    for (const Json& item : completion["result"]["items"]) out.insert(item["label"]);
    return out;
}

// kUri's semantic tokens, decoded: the type and the modifiers of the token at each (line,
// character).
struct DecodedTokens {
    std::map<std::pair<int, int>, std::string> types;
    std::map<std::pair<int, int>, int> modifiers;
};
inline DecodedTokens semanticTokensOf(Server& s) {
    Json legend = request(
        s, 71, "initialize",
        Json::object())["result"]["capabilities"]["semanticTokensProvider"]["legend"]["tokenTypes"];
    Json data = request(s, 72, "textDocument/semanticTokens/full",
                        {{"textDocument", {{"uri", kUri}}}})["result"]["data"];
    REQUIRE(data.size() % 5 == 0);
    DecodedTokens out;
    int line = 0, ch = 0;
    for (size_t i = 0; i < data.size(); i += 5) {
        line += data[i].get<int>();
        ch = data[i].get<int>() ? data[i + 1].get<int>() : ch + data[i + 1].get<int>();
        out.types[{line, ch}] = legend[data[i + 3].get<int>()];
        out.modifiers[{line, ch}] = data[i + 4].get<int>();
    }
    return out;
}

} // namespace moire::lsp::test
