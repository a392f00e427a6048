#include "compiler/format/Formatter.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/format/Layout.h"
#include "compiler/format/SameTree.h"
#include "compiler/format/TokenList.h"
#include "compiler/parse/Ast.h"
#include "compiler/parse/Parser.h"

#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <vector>

namespace moire::format {

namespace {
// The compiler reads stdlib/*.moire as library modules (Compile.cpp); a file in a folder
// named stdlib is formatted the same way, so that its builtin families parse.
bool isLibraryFile(std::string_view fileName) {
    return std::filesystem::path(fileName).parent_path().filename() == "stdlib";
}

// The comments of a file, in order, as the layout writes them.
std::vector<std::string> commentsOf(const SourceManager& sm, uint32_t id) {
    std::vector<std::string> out;
    TokenList tokens(sm, id);
    for (const GapComment& c : tokens.comments()) out.push_back(c.text);
    return out;
}
} // namespace

FormatResult formatSource(std::string_view fileName, std::string_view text) {
    FormatResult result;
    bool library = isLibraryFile(fileName);
    SourceManager sm;
    uint32_t id = sm.add(std::string(fileName), std::string(text), library);
    DiagEngine diags(sm);
    ast::Module before = Parser(sm, id, diags).parseModule();
    if (diags.hasErrors()) {
        result.diagnostics = diags.render();
        return result;
    }
    auto internalError = [&] {
        result.diagnostics = fmt::format(
            "moire: internal error: formatting '{}' would change it; the file is left as it "
            "was. Please report this with the file.\n",
            fileName);
        return result;
    };
    std::string formatted;
    try {
        TokenList tokens(sm, id);
        formatted = Layout(tokens).format();
    } catch (const std::exception&) { // a token the layout did not expect (out of range)
        return internalError();
    }

    // The formatted text must mean what the file meant. A difference is a bug in the layout,
    // which must not reach the user's file.
    uint32_t again = sm.add(std::string(fileName), formatted, library);
    DiagEngine check(sm);
    ast::Module after = Parser(sm, again, check).parseModule();
    if (check.hasErrors() || !sameModule(before, after) ||
        commentsOf(sm, id) != commentsOf(sm, again))
        return internalError();
    result.ok = true;
    result.text = std::move(formatted);
    return result;
}

} // namespace moire::format
