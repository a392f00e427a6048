// The language features, one group a file, each a function of a document's analysis: the
// server (Server.cpp) reads the request's params and hands the place over as a byte offset
// into the analysed text. Results are the protocol's JSON.
#pragma once

#include "lsp/Analysis.h"
#include "lsp/Protocol.h"

#include <string>

namespace moire::lsp {

// A document as the features see it: its URI, analysis, and the index of the analysed text.
struct DocView {
    const std::string& uri;
    const Analysis& analysis;
    LineIndex index;
    DocView(const std::string& u, const Analysis& a) : uri(u), analysis(a), index(a.text()) {}
    const std::string& text() const { return analysis.text(); }
};

// The location (URI and range) of a range in any file of the analysis: the document's own,
// or a stdlib file under moire-stdlib:///.
Json locationJson(const DocView& doc, SourceRange r);

// Diagnostics.cpp: `moire check`'s diagnostics as LSP diagnostics, and the "did you mean"
// quick fixes among them that touch [begin, end].
Json diagnosticsJson(const DocView& doc);
Json codeActions(const DocView& doc, uint32_t begin, uint32_t end);

// Hover.cpp
Json hover(const DocView& doc, uint32_t offset);

// Completion.cpp
Json completion(const DocView& doc, uint32_t offset);

// Navigation.cpp: definition, references, rename and the outline.
Json definition(const DocView& doc, uint32_t offset);
Json references(const DocView& doc, uint32_t offset, bool includeDeclaration);
Json prepareRename(const DocView& doc, uint32_t offset);
Json rename(const DocView& doc, uint32_t offset, const std::string& newName);
Json documentSymbols(const DocView& doc);

// Tokens.cpp: semantic tokens (full) and their legend, and folding ranges.
Json semanticTokensLegend();
Json semanticTokens(const DocView& doc);
Json foldingRanges(const DocView& doc);

// Formatting.cpp: the document laid out as `moire fmt` lays it out (compiler/format), as
// TextEdits (none when it is already).
Json formatting(const DocView& doc);

} // namespace moire::lsp
