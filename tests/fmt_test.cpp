// `moire fmt` over real files: the tree's own scenes are formatted (a file that is not fails
// here), formatting any scene of the fuzz corpus, as written and with its layout scrambled,
// gives a file that compiles to the same kernel and literal table and that formatting leaves
// alone; and the command line's behaviour (--check, in place, standard input, errors).
#include "compiler/Compile.h"
#include "compiler/format/Formatter.h"
#include "compiler/lex/Lexer.h"
#include "compiler/parse/Parser.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace moire;

namespace {

std::vector<std::string> moireFiles(const std::vector<std::string>& dirs) {
    std::vector<std::string> out;
    for (const std::string& d : dirs)
        for (const auto& e : fs::directory_iterator(test::sourcePath(d)))
            if (e.is_regular_file() && e.path().extension() == ".moire")
                out.push_back(d + "/" + e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

// The scenes the tree keeps formatted (docs/formatting.md): all but the diagnostics cases
// and the fuzz finds, which are kept byte for byte as they were found or written.
const std::vector<std::string> kFormattedDirs = {"examples", "stdlib", "docs/tutorial",
                                                 "docs/scenes", "bench/scenes"};

// The front end's fuzz corpus: the seeds fuzz/CMakeLists.txt copies and the regressions.
std::vector<std::string> corpus() {
    std::vector<std::string> dirs = kFormattedDirs;
    dirs.push_back("tests/errors");
    for (const auto& e : fs::directory_iterator(test::sourcePath("fuzz/regressions")))
        if (e.is_directory()) dirs.push_back("fuzz/regressions/" + e.path().filename().string());
    return moireFiles(dirs);
}

// The same tokens and comments laid out otherwise: `gap` between each two (a line comment
// is always followed by a line break). What it means is unchanged: the parser reads tokens.
std::string relaid(const std::string& text, const std::string& gap, bool moreComments) {
    SourceManager sm;
    uint32_t id = sm.add("x.moire", text);
    DiagEngine diags(sm);
    Lexer lexer(id, sm.file(id).text(), diags);
    std::vector<Comment> comments;
    lexer.keepComments(&comments);
    std::vector<std::pair<uint32_t, uint32_t>> pieces; // offset, length; comments and tokens
    for (Token t = lexer.next(); t.kind != Tok::End; t = lexer.next())
        pieces.push_back({t.offset, t.length});
    std::vector<bool> lineComment(pieces.size(), false);
    for (const Comment& c : comments) {
        pieces.push_back({c.offset, c.length});
        lineComment.push_back(!c.block);
    }
    std::vector<size_t> order(pieces.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return pieces[a].first < pieces[b].first; });
    std::string out;
    for (size_t n = 0; n < order.size(); ++n) {
        size_t i = order[n];
        out += text.substr(pieces[i].first, pieces[i].second);
        out += lineComment[i] ? "\n" : gap;
        if (moreComments && n % 3 == 0) out += "/* c */" + gap;
    }
    return out;
}

struct Parsed {
    bool ok = false;
    std::string tree;
};
Parsed parse(const std::string& path, const std::string& text) {
    SourceManager sm;
    bool library = fs::path(path).parent_path().filename() == "stdlib";
    uint32_t id = sm.add(path, text, library);
    DiagEngine diags(sm);
    ast::Module m = Parser(sm, id, diags).parseModule();
    return {!diags.hasErrors(), ast::printModule(m)};
}

} // namespace

TEST_CASE("fmt: the scenes of the tree are formatted (run moire fmt on one that is not)") {
    std::vector<std::string> files = moireFiles(kFormattedDirs);
    CHECK(files.size() > 30);
    for (const std::string& f : files) {
        CAPTURE(f);
        std::string text = test::readFile(test::sourcePath(f));
        format::FormatResult r = format::formatSource(f, text);
        INFO(r.diagnostics);
        REQUIRE(r.ok);
        CHECK(r.text == text);
    }
}

TEST_CASE("fmt: every corpus scene, relaid, formats to the same kernel and literals, once") {
    int formatted = 0, compiled = 0;
    for (const std::string& f : corpus()) {
        CAPTURE(f);
        std::string text = test::readFile(test::sourcePath(f));
        Parsed original = parse(f, text);
        if (!original.ok) {
            CHECK_FALSE(format::formatSource(f, text).ok); // what does not parse is refused
            continue;
        }
        CompileResult before = compileScene(f, text);
        for (const std::string& variant :
             {text, relaid(text, " ", false), relaid(text, "\n\n  ", true)}) {
            format::FormatResult r = format::formatSource(f, variant);
            INFO(r.diagnostics);
            REQUIRE(r.ok);
            ++formatted;
            format::FormatResult again = format::formatSource(f, r.text);
            REQUIRE(again.ok);
            CHECK(again.text == r.text); // idempotent
            Parsed after = parse(f, r.text);
            REQUIRE(after.ok);
            CHECK(after.tree == original.tree); // the same tree and literal table
            if (!before.program) continue;
            CompileResult now = compileScene(f, r.text);
            REQUIRE(now.program);
            CHECK(now.program->kernelHash == before.program->kernelHash);
            CHECK(now.program->literals == before.program->literals);
            ++compiled;
        }
    }
    CHECK(formatted > 100);
    CHECK(compiled > 80);
}
