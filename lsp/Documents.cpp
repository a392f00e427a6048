#include "lsp/Documents.h"

namespace moire::lsp {

Document& DocumentStore::open(const std::string& uri, std::string text, int version) {
    Document& d = docs_[uri];
    d.uri = uri;
    d.path = uriToPath(uri);
    d.text = std::move(text);
    d.version = version;
    d.analysis.reset();
    return d;
}

void DocumentStore::change(Document& doc, const Json& change) {
    if (!change.is_object() || !change.contains("text") || !change["text"].is_string())
        throw RpcError(ErrorCode::InvalidParams, "a content change has a text");
    const std::string& text = change["text"].get_ref<const std::string&>();
    if (!change.contains("range")) {
        doc.text = text;
    } else {
        LineIndex index(doc.text);
        uint32_t begin = index.offset(positionFrom(change["range"].at("start")));
        uint32_t end = index.offset(positionFrom(change["range"].at("end")));
        if (end < begin) std::swap(begin, end);
        doc.text.replace(begin, end - begin, text);
    }
    doc.analysis.reset();
}

Document* DocumentStore::find(const std::string& uri) {
    auto it = docs_.find(uri);
    return it == docs_.end() ? nullptr : &it->second;
}

const Analysis& DocumentStore::analysis(Document& doc) {
    if (!doc.analysis) doc.analysis = std::make_shared<const Analysis>(analyze(doc.path, doc.text));
    return *doc.analysis;
}

} // namespace moire::lsp
