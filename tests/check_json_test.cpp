// `moire check --format=json`, run as a tool runs it: the JSON read back says what the text
// diagnostics of `moire check` say (each header line, each caret, in the same order), with
// the same exit status.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

using namespace moire;
using Json = nlohmann::json;

namespace {

test::CommandResult check(const std::string& args) {
    return test::runMoireInSourceRoot("check " + args);
}

// The header line a diagnostic's JSON stands for, built from its fields alone.
std::string header(const Json& d) {
    std::string tail =
        fmt::format("{}: {}", d["severity"].get<std::string>(), d["message"].get<std::string>());
    if (d["range"].is_null()) return "moire: " + tail;
    const Json& r = d["range"];
    return fmt::format("{}:{}:{}: {}", r["file"].get<std::string>(), r["start"]["line"].get<int>(),
                       r["start"]["column"].get<int>(), tail);
}

} // namespace

TEST_CASE("moire check --format=json: the diagnostics are the text ones, field by field") {
    // Lexer, parser and checker errors, a note, a suggestion, and errors found only when the
    // frame is evaluated.
    for (const char* name : {"unknown_unit", "duplicate_property", "bad_size", "bad_zoom",
                             "unknown_property_family", "unknown_name", "bad_mode"}) {
        CAPTURE(name);
        const std::string scene = fmt::format("tests/errors/{}.moire", name);
        test::CommandResult text = check(scene);
        test::CommandResult json = check("--format=json " + scene);
        CHECK(text.status == 1);
        CHECK(json.status == text.status);
        CHECK(json.err.empty());
        Json doc = Json::parse(json.out);
        REQUIRE(doc["scenes"].size() == 1);
        const Json& entry = doc["scenes"][0];
        CHECK(entry["scene"] == scene);
        CHECK(entry["read"] == true);
        CHECK(entry["ok"] == false);

        // The text diagnostics: each begins with a header line and holds its source and caret
        // lines. The JSON's headers, in order, are those lines, and its rendered texts joined
        // are the whole text.
        std::string rendered;
        std::vector<std::string> headers;
        for (const Json& d : entry["diagnostics"]) {
            rendered += d["rendered"].get<std::string>();
            headers.push_back(header(d));
            CHECK(test::lines(d["rendered"].get<std::string>()).at(0) == headers.back());
            if (!d["range"].is_null()) {
                // The caret sits under the start column.
                std::vector<std::string> ls = test::lines(d["rendered"].get<std::string>());
                REQUIRE(ls.size() == 3);
                CHECK(ls[2].find('^') - 8 + 1 == d["range"]["start"]["column"].get<size_t>());
            }
        }
        CHECK(rendered == text.err);
        std::vector<std::string> textHeaders;
        for (const std::string& l : test::lines(text.err))
            if (!l.starts_with(" ")) textHeaders.push_back(l);
        CHECK(headers == textHeaders);
        CHECK(!headers.empty());
    }
}

TEST_CASE("moire check --format=json: ids, suggestions, good scenes and unreadable ones") {
    test::TempDir dir("check-json");
    dir.write("good.moire", "layer { family = circles }\n");
    dir.write("typo.moire", "layer { family = circles; strok = 2 }\n");
    const std::string missing = dir.file("missing.moire");
    test::CommandResult r = check(fmt::format(
        "--format=json '{}' '{}' '{}'", dir.file("good.moire"), dir.file("typo.moire"), missing));
    CHECK(r.status == 1);
    Json doc = Json::parse(r.out);
    REQUIRE(doc["scenes"].size() == 3);
    CHECK(doc["scenes"][0]["ok"] == true);
    CHECK(doc["scenes"][0]["diagnostics"].empty());

    const Json& typo = doc["scenes"][1]["diagnostics"];
    REQUIRE(typo.size() == 1);
    CHECK(typo[0]["id"] == "UnknownProperty");
    CHECK(typo[0]["severity"] == "error");
    CHECK(typo[0]["range"]["start"]["line"] == 1);
    CHECK(typo[0]["range"]["start"]["column"] == 27);
    CHECK(typo[0]["range"]["end"]["column"] == 32);
    CHECK(typo[0]["suggestion"]["replacement"] == "stroke");
    CHECK(typo[0]["suggestion"]["range"]["offset"] == 26);
    CHECK(typo[0]["suggestion"]["range"]["length"] == 5);

    // A file that cannot be read is said on standard error, as in text mode.
    CHECK(doc["scenes"][2]["read"] == false);
    CHECK(doc["scenes"][2]["ok"] == false);
    CHECK(r.err.find("cannot read") != std::string::npos);

    // Good scenes alone exit 0.
    CHECK(check(fmt::format("--format=json '{}'", dir.file("good.moire"))).status == 0);
    // An unknown format is a usage error.
    CHECK(check(fmt::format("--format=xml '{}'", dir.file("good.moire"))).status == 2);
}
