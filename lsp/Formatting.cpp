// textDocument/formatting: `moire fmt` on the open document, as one edit over the whole text.
// A document that does not parse is not formatted: the request fails with the diagnostics
// `moire fmt` and `moire check` print.
#include "compiler/format/Formatter.h"
#include "lsp/Features.h"
#include "lsp/JsonRpc.h"

namespace moire::lsp {

Json formatting(const DocView& doc) {
    const std::string& text = doc.text();
    format::FormatResult r = format::formatSource(doc.analysis.path, text);
    if (!r.ok) throw RpcError(ErrorCode::RequestFailed, r.diagnostics);
    if (r.text == text) return Json::array();
    const uint32_t end = static_cast<uint32_t>(text.size());
    return Json::array({{{"range", rangeJson(doc.index, 0, end)}, {"newText", r.text}}});
}

} // namespace moire::lsp
