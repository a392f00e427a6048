// The diagnostics catalogue: every case tests/errors/<name>.moire must give exactly the
// text in <name>.expected (written by hand: file:line:col, message, source line, caret).
// Two more tests keep the catalogue whole: every message of compiler/diag/Messages.def is
// shown by at least one case, and every case has both of its files.
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

using namespace moire;
namespace fs = std::filesystem;

namespace {

const std::string kDir = "tests/errors";

// The case names (file stems) with the given extension, sorted.
std::vector<std::string> stems(const std::string& extension) {
    std::vector<std::string> out;
    for (const auto& entry : fs::directory_iterator(test::sourcePath(kDir)))
        if (entry.path().extension() == extension) out.push_back(entry.path().stem().string());
    std::sort(out.begin(), out.end());
    return out;
}

// A message template as a regular expression for one rendered diagnostic line: the text
// is literal, and each {} or {:...} argument matches anything.
std::regex templateRegex(const std::string& tmpl) {
    static const std::string special = R"(\^$.|?*+()[]{})";
    std::string re = ".*: (error|note): ";
    for (size_t i = 0; i < tmpl.size(); ++i) {
        if (tmpl[i] == '{') {
            size_t close = tmpl.find('}', i);
            REQUIRE_MESSAGE(close != std::string::npos, "unbalanced '{' in template: ", tmpl);
            re += ".*";
            i = close;
            continue;
        }
        if (special.find(tmpl[i]) != std::string::npos) re += '\\';
        re += tmpl[i];
    }
    return std::regex(re);
}

std::string join(const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& s : v) out += (out.empty() ? "" : ", ") + s;
    return out;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

} // namespace

TEST_CASE("errors: every case gives exactly its expected diagnostics") {
    std::vector<std::string> cases = stems(".moire");
    REQUIRE(cases.size() >= 40); // a missing directory must not pass as "no cases, no failures"
    for (const std::string& name : cases) {
        CAPTURE(name);
        std::string path = kDir + "/" + name + ".moire";
        std::string expectedPath = test::sourcePath(kDir + "/" + name + ".expected");
        if (!fs::exists(expectedPath)) continue; // reported by the pairing test below
        std::string text = test::readFile(test::sourcePath(path));
        std::string expected = test::readFile(expectedPath);
        CHECK(test::compileErrors(text, path) == expected);
    }
}

TEST_CASE("errors: every message in Messages.def is shown by some case") {
    std::vector<std::string> expectedLines;
    for (const std::string& name : stems(".expected"))
        for (std::string& line :
             lines(test::readFile(test::sourcePath(kDir + "/" + name + ".expected"))))
            expectedLines.push_back(std::move(line));
    REQUIRE(messageCount() > 0);
    for (int i = 0; i < messageCount(); ++i) {
        Msg m = static_cast<Msg>(i);
        std::string name = messageName(m), tmpl = messageTemplate(m);
        CAPTURE(name);
        CAPTURE(tmpl);
        std::regex re = templateRegex(messageTemplate(m));
        bool shown =
            std::any_of(expectedLines.begin(), expectedLines.end(),
                        [&](const std::string& line) { return std::regex_match(line, re); });
        CHECK_MESSAGE(shown, "no case in tests/errors shows this message; add one");
    }
}

TEST_CASE("errors: the template matcher tells messages apart") {
    // The test above is only as good as this: a template matches its own rendering and not
    // another message's.
    std::regex arity = templateRegex(messageTemplate(Msg::Arity));
    CHECK(std::regex_match("a.moire:2:3: error: 'sin' takes 1 argument, but 2 were given", arity));
    CHECK_FALSE(
        std::regex_match("a.moire:2:3: error: 'sin' is a built-in value, not a function", arity));
    std::regex byte = templateRegex(messageTemplate(Msg::UnexpectedByte));
    CHECK(std::regex_match(
        "a.moire:1:1: error: unexpected byte 0xE9, which is not a printable character of "
        "UTF-8 text",
        byte));
    std::regex note = templateRegex(messageTemplate(Msg::FirstSeenHere));
    CHECK(std::regex_match("a.moire:4:5: note: first set here", note));
    CHECK_FALSE(std::regex_match("a.moire:4:5: note: first defined here", note));
}

TEST_CASE("errors: every case has both its .moire and its .expected") {
    std::vector<std::string> scenes = stems(".moire");
    std::vector<std::string> expected = stems(".expected");
    std::vector<std::string> onlyScene, onlyExpected;
    std::set_difference(scenes.begin(), scenes.end(), expected.begin(), expected.end(),
                        std::back_inserter(onlyScene));
    std::set_difference(expected.begin(), expected.end(), scenes.begin(), scenes.end(),
                        std::back_inserter(onlyExpected));
    CHECK_MESSAGE(onlyScene.empty(), "scenes without .expected: ", join(onlyScene));
    CHECK_MESSAGE(onlyExpected.empty(), ".expected without a scene: ", join(onlyExpected));
    // Nothing else belongs in the directory (a stray .txt would be a case nobody runs).
    for (const auto& entry : fs::directory_iterator(test::sourcePath(kDir))) {
        CAPTURE(entry.path().filename().string());
        std::string ext = entry.path().extension().string();
        CHECK((ext == ".moire" || ext == ".expected"));
    }
}
