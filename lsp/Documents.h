// The documents the client has open: their text (kept up to date from full or incremental
// changes) and their analysis, made again on demand after a change.
#pragma once

#include "lsp/Analysis.h"
#include "lsp/Protocol.h"

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace moire::lsp {

using Clock = std::chrono::steady_clock;

struct Document {
    std::string uri;
    std::string path; // the name diagnostics give it (uriToPath)
    std::string text;
    int version = 0;
    // The analysis of `text`, or null when a change made it stale.
    std::shared_ptr<const Analysis> analysis;
    // When the diagnostics of the latest change are due (debounced), if they are.
    std::optional<Clock::time_point> diagnosticsDue;
};

class DocumentStore {
  public:
    Document& open(const std::string& uri, std::string text, int version);
    // Applies one contentChanges entry: {"text"} replaces the whole text, {"range", "text"}
    // a part of it. Throws RpcError(InvalidParams) on a wrong shape.
    void change(Document& doc, const Json& change);
    void close(const std::string& uri) { docs_.erase(uri); }
    Document* find(const std::string& uri);
    // The document's analysis, made now when stale.
    const Analysis& analysis(Document& doc);
    std::map<std::string, Document>& all() { return docs_; }

  private:
    std::map<std::string, Document> docs_;
};

} // namespace moire::lsp
