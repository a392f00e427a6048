// The names `moire names` prints, each held to what the compiler does with it: a name listed
// as a family compiles as a layer's family, a property is no unknown property of its block,
// and so on, while a made-up name of each kind is refused. So the list the editors highlight
// can neither miss a name the compiler knows nor offer one it does not.
#include "compiler/Compile.h"
#include "compiler/LanguageNames.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>

using namespace moire;

namespace {

// The ids of the diagnostics of `text`.
std::vector<std::string> diagnosticIds(const std::string& text) {
    std::vector<std::string> ids;
    for (const LocatedDiagnostic& d : compileScene("names.moire", text).diagnosticList)
        ids.push_back(d.id);
    return ids;
}

bool has(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

// `text` compiles with no error at all.
void compilesClean(const std::string& text) {
    CAPTURE(text);
    CompileResult r = compileScene("names.moire", text);
    CHECK(r.diagnostics == "");
}

const char* kLayer = "layer { family = circles }\n";

} // namespace

TEST_CASE("names: every keyword is reserved, and each group is non-empty") {
    LanguageNames n = languageNames();
    for (const std::string& k : n.keywords) {
        CAPTURE(k);
        CHECK(has(diagnosticIds(fmt::format("field {} = 1\n{}", k, kLayer)), "ReservedName"));
    }
    for (const auto* group : {&n.keywords, &n.properties, &n.functions, &n.fields, &n.easings,
                              &n.constants, &n.variables, &n.words, &n.units})
        CHECK(!group->empty());
    CHECK(!n.families.empty());
}

TEST_CASE("names: each block's properties are its own, and a made-up one is not") {
    LanguageNames n = languageNames();
    auto blockText = [](const std::string& kind, const std::string& prop) {
        if (kind == "layer") return fmt::format("layer {{ family = circles; {} = 1 }}", prop);
        if (kind == "family")
            return fmt::format("family f {{ {} = x }}\nlayer {{ family = circles }}", prop);
        if (kind == "timing") return fmt::format("timing a {{ {} = 1 }}\n{}", prop, kLayer);
        return fmt::format("{} {{ {} = 1 }}\n{}", kind, prop, kLayer);
    };
    REQUIRE(n.blocks.size() == 5);
    for (const BlockNames& b : n.blocks) {
        CAPTURE(b.kind);
        CHECK(has(diagnosticIds(blockText(b.kind, "zzz_not_one")), "UnknownProperty"));
        for (const std::string& p : b.properties) {
            CAPTURE(p);
            CHECK_FALSE(has(diagnosticIds(blockText(b.kind, p)), "UnknownProperty"));
            CHECK(has(n.properties, p));
        }
    }
}

TEST_CASE("names: families, fields, easings, functions and words are what the compiler takes") {
    LanguageNames n = languageNames();
    for (const FamilyNames& f : n.families) {
        compilesClean(fmt::format("layer {{ family = {} }}", f.name));
        for (const std::string& p : f.params) {
            // A parameter the family does not have would be an unknown property.
            CAPTURE(p);
            CHECK_FALSE(
                has(diagnosticIds(fmt::format("layer {{ family = {}; {} = 1 }}", f.name, p)),
                    "UnknownProperty"));
        }
    }
    CHECK(has(diagnosticIds("layer { family = zzz_not_one }"), "UnknownFamily"));
    for (const std::string& f : n.fields)
        compilesClean(fmt::format("layer {{ family = circles; field = {} }}", f));
    for (const std::string& e : n.easings)
        compilesClean(fmt::format("timing a {{ period = 1; easing = {} }}\n{}", e, kLayer));
    CHECK(has(diagnosticIds(fmt::format("timing a {{ period = 1; easing = zzz }}\n{}", kLayer)),
              "NotAnEasing"));
    for (const std::string& f : n.functions) {
        CAPTURE(f);
        if (f == "morph") { // a layer's family only, never in an expression
            compilesClean("timing a { period = 1 }\nlayer { family = morph(a, circles, lines) }");
            continue;
        }
        CHECK_FALSE(
            has(diagnosticIds(fmt::format("field a = {}(1)\n{}", f, kLayer)), "UnknownFunction"));
    }
    CHECK(has(diagnosticIds(fmt::format("field a = zzz(1)\n{}", kLayer)), "UnknownFunction"));
    // The bare words: a timing's modes, the views, the overlay's switch, the filters.
    int taken = 0;
    for (const std::string& w : n.words) {
        CompileResult mode = compileScene(
            "w.moire", fmt::format("timing a {{ period = 1; mode = {} }}\n{}", w, kLayer));
        CompileResult view =
            compileScene("w.moire", fmt::format("scene {{ view = {} }}\n{}", w, kLayer));
        CompileResult over =
            compileScene("w.moire", fmt::format("scene {{ overlay = {} }}\n{}", w, kLayer));
        CompileResult filter =
            compileScene("w.moire", fmt::format("scene {{ filter = {} }}\n{}", w, kLayer));
        CAPTURE(w);
        CHECK((mode.diagnostics.empty() || view.diagnostics.empty() || over.diagnostics.empty() ||
               filter.diagnostics.empty()));
        ++taken;
    }
    CHECK(taken == static_cast<int>(n.words.size()));
}

TEST_CASE("names: constants, variables and units") {
    LanguageNames n = languageNames();
    for (const std::string& c : n.constants)
        compilesClean(fmt::format("field a = {}\n{}", c, kLayer));
    for (const std::string& v : n.variables) {
        // x, y, r, theta and t anywhere; u in an easing; spacing in a family's phase.
        CompileResult anywhere =
            compileScene("v.moire", fmt::format("field a = {}\n{}", v, kLayer));
        CompileResult easing = compileScene("v.moire", fmt::format("easing a = {}\n{}", v, kLayer));
        CompileResult family =
            compileScene("v.moire", fmt::format("family f {{ phase = x + {} }}\n{}", v, kLayer));
        CAPTURE(v);
        CHECK((anywhere.diagnostics.empty() || easing.diagnostics.empty() ||
               family.diagnostics.empty()));
    }
    CHECK(has(diagnosticIds(fmt::format("field a = zzz\n{}", kLayer)), "UnknownName"));
    for (const std::string& u : n.units)
        compilesClean(fmt::format("layer {{ family = circles; rotation = 3{} }}", u));
    CHECK(has(diagnosticIds("layer { family = circles; rotation = 3grad }"), "UnknownUnit"));
}
