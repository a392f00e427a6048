// The symbol table an editor asks for: declarations and references of the user's names, at
// the places a search of the scene's text finds them (the oracle), also when the scene has
// errors.
#include "compiler/Compile.h"
#include "compiler/sema/Symbols.h"

#include <cctype>
#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::sema;

namespace {

// The byte offsets of `word` as a whole word in `text`, in order.
std::vector<uint32_t> occurrences(const std::string& text, const std::string& word) {
    auto isWordChar = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    };
    std::vector<uint32_t> out;
    for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
        bool before = at > 0 && isWordChar(text[at - 1]);
        bool after = at + word.size() < text.size() && isWordChar(text[at + word.size()]);
        if (!before && !after) out.push_back(static_cast<uint32_t>(at));
    }
    return out;
}

std::vector<uint32_t> offsets(const std::vector<SourceRange>& ranges) {
    std::vector<uint32_t> out;
    for (SourceRange r : ranges) out.push_back(r.begin.offset);
    return out;
}

// The user's file id: the last one added.
uint32_t userFile(const CompileResult& r) {
    return r.frontEnd().sources->size() - 1;
}

} // namespace

TEST_CASE("symbols: a scene with an error still lists its declarations and references") {
    const std::string text =
        "field wobble = sin(x / 40)\n"
        "family rings(w = 2) {\n"
        "    let k = w * 2\n"
        "    phase = r + k * wobble\n"
        "}\n"
        "timing drift { period = 4; easing = cubic_in_out }\n"
        "layer a { family = rings; w = 3; rotation = ramp(drift, 0deg, 30deg) }\n"
        "layer b { family = circles; spacing = (wobble) + nosuch }\n";
    CompileResult r = compileScene("symbols.moire", text);
    REQUIRE(r.program == nullptr);
    REQUIRE(r.diagnosticList.size() == 1);
    CHECK(r.diagnosticList[0].id == "UnknownName");
    const uint32_t file = userFile(r);

    struct Expect {
        SymbolKind kind;
        std::string name;
        size_t notReferences = 0; // trailing occurrences that are not references
    };
    // The first whole-word occurrence is the declaration, the others the references; but the
    // layer's `w = 3` sets the parameter: a property's name, not a reference.
    for (const Expect& e : {Expect{SymbolKind::Field, "wobble"},
                            Expect{SymbolKind::Family, "rings"}, Expect{SymbolKind::Param, "w", 1},
                            Expect{SymbolKind::Let, "k"}, Expect{SymbolKind::Timing, "drift"},
                            Expect{SymbolKind::Layer, "a"}, Expect{SymbolKind::Layer, "b"}}) {
        CAPTURE(e.name);
        const Symbol* s = r.symbols.find(e.kind, e.name);
        REQUIRE(s != nullptr);
        std::vector<uint32_t> at = occurrences(text, e.name);
        REQUIRE(at.size() > e.notReferences);
        at.resize(at.size() - e.notReferences);
        CHECK(s->declaration.begin.file == file);
        CHECK(s->declaration.begin.offset == at[0]);
        CHECK(s->declaration.length == e.name.size());
        for (SourceRange ref : s->references) {
            CHECK(ref.begin.file == file);
            CHECK(ref.length == e.name.size());
        }
        CHECK(offsets(s->references) == std::vector<uint32_t>(at.begin() + 1, at.end()));
        // Asking at the declaration or a reference finds the same symbol.
        for (uint32_t o : at) CHECK(r.symbols.at(SourceLoc{file, o}) == s);
    }

    // Library symbols the scene names: their declarations are in the library, their references
    // in the scene.
    for (auto [kind, name] : {std::pair{SymbolKind::Family, "circles"},
                              std::pair{SymbolKind::Easing, "cubic_in_out"}}) {
        CAPTURE(name);
        const Symbol* s = r.symbols.find(kind, name);
        REQUIRE(s != nullptr);
        CHECK(r.frontEnd().sources->file(s->declaration.begin.file).isStdlib());
        CHECK(offsets(s->references) == occurrences(text, name));
    }
    // The unresolved name is nobody's reference, and the library's unused names are not listed.
    CHECK(r.symbols.at(SourceLoc{file, occurrences(text, "nosuch")[0]}) == nullptr);
    CHECK(r.symbols.find(SymbolKind::Family, "hexagons") == nullptr);

    // The checked tree is there too: both layers, the first resolved to its family.
    REQUIRE(r.partial != nullptr);
    const CheckedScene& checked = r.frontEnd().checked;
    REQUIRE(checked.layers.size() == 2);
    REQUIRE(checked.layers[0].family != nullptr);
    CHECK(checked.layers[0].family->decl->name == "rings");
}

TEST_CASE("symbols: a scene that does not parse lists the declarations read before the error") {
    const std::string text = "field depth = 3\n"
                             "family bowl(d = 1) = r * depth\n"
                             "layer { family = bowl; d = depth + }\n";
    CompileResult r = compileScene("broken.moire", text);
    REQUIRE(r.program == nullptr);
    REQUIRE(!r.diagnosticList.empty());
    CHECK(r.diagnosticList[0].id == "Expected");
    const Symbol* depth = r.symbols.find(SymbolKind::Field, "depth");
    REQUIRE(depth != nullptr);
    CHECK(depth->declaration.begin.offset == occurrences(text, "depth")[0]);
    CHECK(depth->references.empty()); // the checks did not run
    const Symbol* d = r.symbols.find(SymbolKind::Param, "d");
    REQUIRE(d != nullptr);
    CHECK(d->declaration.begin.offset == occurrences(text, "d")[0]);
    CHECK(r.symbols.find(SymbolKind::Family, "bowl") != nullptr);
}

TEST_CASE("symbols: a long chain of references is walked without recursion") {
    // A chain as long as this would overflow the stack of a recursive walk; the unknown
    // family stops the compile after the checks (lowering it is not what is tested).
    std::string text = "field a = 1\nfield b = a";
    for (int i = 0; i < 200000; ++i) text += " + a";
    text += "\nlayer { family = nosuch; spacing = b }\n";
    CompileResult r = compileScene("chain.moire", text);
    REQUIRE(r.program == nullptr);
    const Symbol* a = r.symbols.find(SymbolKind::Field, "a");
    REQUIRE(a != nullptr);
    CHECK(a->references.size() == 200001);
    CHECK(r.symbols.find(SymbolKind::Field, "b")->references.size() == 1);
}
