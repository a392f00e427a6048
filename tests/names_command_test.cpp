// `moire names`: the language's names by kind, as text and as JSON for the editor packages
// (scripts/gen-editor-names.mjs reads the JSON). The names themselves are held to the
// compiler in compiler/LanguageNames_test.cpp; here, the command: both forms say the same,
// and it keeps the command line's conventions.
#include "compiler/lex/Keywords.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

using namespace moire;

namespace {

// "kind: a b c" lines of the text form, as kind -> words.
std::map<std::string, std::vector<std::string>> textGroups(const std::string& text) {
    std::map<std::string, std::vector<std::string>> out;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        const size_t colon = line.find(": ");
        REQUIRE(colon != std::string::npos);
        std::istringstream words(line.substr(colon + 2));
        std::string w;
        while (words >> w) out[line.substr(0, colon)].push_back(w);
    }
    return out;
}

} // namespace

TEST_CASE("names: the JSON and the text list the same names, grouped by kind") {
    test::CommandResult json = test::runMoireInSourceRoot("names --json");
    REQUIRE(json.status == 0);
    CHECK(json.err.empty());
    // In the order printed: "properties" lists the blocks' in their order.
    const nlohmann::ordered_json j = nlohmann::ordered_json::parse(json.out);
    test::CommandResult text = test::runMoireInSourceRoot("names");
    REQUIRE(text.status == 0);
    auto groups = textGroups(text.out);

    for (const char* kind : {"keywords", "functions", "fields", "easings", "constants", "variables",
                             "words", "units"}) {
        CAPTURE(kind);
        REQUIRE(j.contains(kind));
        CHECK(j[kind].get<std::vector<std::string>>() == groups[kind]);
    }
    std::vector<std::string> properties;
    for (const auto& [block, props] : j["blocks"].items()) {
        CAPTURE(block);
        CHECK(props.get<std::vector<std::string>>() == groups[block + " properties"]);
        for (const std::string& p : props.get<std::vector<std::string>>())
            if (std::find(properties.begin(), properties.end(), p) == properties.end())
                properties.push_back(p);
    }
    CHECK(j["properties"].get<std::vector<std::string>>() == properties);
    // A family with its parameters: wave(amplitude, frequency, shift) in the text.
    std::vector<std::string> families;
    for (const auto& f : j["families"]) families.push_back(f["name"].get<std::string>());
    CHECK(families.size() == j["families"].size());
    CHECK(text.out.find("families: lines(angle) circles ") != std::string::npos);
    CHECK(std::find(families.begin(), families.end(), "hex_lattice") != families.end());
    for (const auto& f : j["families"])
        if (f["name"] == "hex_lattice") CHECK(f["builtin"] == true);
}

TEST_CASE("names: -q and -v, --help, and a wrong command line") {
    test::CommandResult verbose = test::runMoireInSourceRoot("names -v");
    CHECK(verbose.status == 0);
    // The declaration words and `let`.
    CHECK(verbose.err.find(fmt::format("moire: {} keywords, ", declarationKeywords().size() + 1)) ==
          0);
    CHECK(test::runMoireInSourceRoot("names -q").out == test::runMoireInSourceRoot("names").out);
    test::CommandResult help = test::runMoireInSourceRoot("names --help");
    CHECK(help.status == 0);
    CHECK(help.out.find("-q,--quiet") != std::string::npos);
    CHECK(help.out.find("Exit status:") != std::string::npos);
    CHECK(test::runMoireInSourceRoot("names --yaml").status == 2);
}
