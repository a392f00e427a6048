// Diagnostics exactly as `moire check --format=json` gives them: one LSP diagnostic per
// LocatedDiagnostic, in the same order, with the same message; notes are Information. The
// message's id is the code, and a "did you mean" replacement rides along in `data`.
#include "lsp/Features.h"

namespace moire::lsp {

namespace {

// The range of a located range in the document (its byte offset and length).
Json rangeOf(const DocView& doc, const LocatedRange& r) {
    return rangeJson(doc.index, r.offset, r.offset + r.length);
}

bool inDocument(const DocView& doc, const LocatedRange& r) {
    return r.file == doc.analysis.path && r.offset + r.length <= doc.text().size();
}

Json diagnosticJson(const DocView& doc, const LocatedDiagnostic& d) {
    Json j{{"severity", d.severity == Severity::Error ? 1 : 3},
           {"source", "moire"},
           {"code", d.id},
           {"message", d.message}};
    if (d.range && inDocument(doc, *d.range)) {
        j["range"] = rangeOf(doc, *d.range);
    } else {
        // About no place, or a place in the library: shown at the top of the document.
        j["range"] = rangeJson(doc.index, 0, 0);
        if (d.range && d.range->file.starts_with("<stdlib>/")) {
            Position s{d.range->start.line - 1, d.range->start.column - 1};
            Position e{d.range->end.line - 1, d.range->end.column - 1};
            j["relatedInformation"] =
                Json::array({{{"location",
                               {{"uri", stdlibUri(d.range->file)},
                                {"range", {{"start", toJson(s)}, {"end", toJson(e)}}}}},
                              {"message", "here in the library"}}});
        }
    }
    if (d.suggestion && inDocument(doc, d.suggestion->range))
        j["data"] = {{"replacement", d.suggestion->replacement},
                     {"range", rangeOf(doc, d.suggestion->range)}};
    return j;
}

} // namespace

Json diagnosticsJson(const DocView& doc) {
    Json out = Json::array();
    for (const LocatedDiagnostic& d : doc.analysis.diagnostics)
        out.push_back(diagnosticJson(doc, d));
    return out;
}

Json codeActions(const DocView& doc, uint32_t begin, uint32_t end) {
    Json out = Json::array();
    for (const LocatedDiagnostic& d : doc.analysis.diagnostics) {
        if (!d.suggestion || !inDocument(doc, d.suggestion->range)) continue;
        const LocatedRange& r = d.suggestion->range;
        const LocatedRange& at = d.range ? *d.range : r;
        // The fix is offered where the diagnostic or its replacement is.
        bool touches = (r.offset <= end && begin <= r.offset + r.length) ||
                       (at.offset <= end && begin <= at.offset + at.length);
        if (!touches) continue;
        Json edit{{"range", rangeOf(doc, r)}, {"newText", d.suggestion->replacement}};
        out.push_back({{"title", "Change to '" + d.suggestion->replacement + "'"},
                       {"kind", "quickfix"},
                       {"isPreferred", true},
                       {"diagnostics", Json::array({diagnosticJson(doc, d)})},
                       {"edit", {{"changes", {{doc.uri, Json::array({edit})}}}}}});
    }
    return out;
}

Json locationJson(const DocView& doc, SourceRange r) {
    const SceneProgram* fe = doc.analysis.frontEnd();
    const SourceFile& file = fe->sources->file(r.begin.file);
    if (r.begin.file == doc.analysis.userFile())
        return {{"uri", doc.uri},
                {"range", rangeJson(doc.index, r.begin.offset, r.begin.offset + r.length)}};
    LineIndex index(file.text());
    return {{"uri", file.isStdlib() ? stdlibUri(file.path()) : pathToUri(file.path())},
            {"range", rangeJson(index, r.begin.offset, r.begin.offset + r.length)}};
}

} // namespace moire::lsp
