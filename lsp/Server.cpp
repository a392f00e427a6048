#include "lsp/Server.h"

#include "lsp/Features.h"

#include <cerrno>
#include <csignal>
#include <poll.h>
#include <unistd.h>

#ifndef MOIRE_VERSION
#define MOIRE_VERSION "dev"
#endif

namespace moire::lsp {

namespace {

Json notification(const std::string& method, Json params) {
    return Json{{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}};
}

std::string uriOf(const Json& params) {
    return params.at("textDocument").at("uri").get<std::string>();
}

} // namespace

Server::Server(std::chrono::milliseconds debounce) : debounce_(debounce) {
    registerHandlers();
}

Json Server::initialize(const Json& params) {
    if (!params.is_object()) throw RpcError(ErrorCode::InvalidParams, "initialize takes an object");
    initialized_ = true;
    Json caps{
        {"positionEncoding", "utf-16"},
        {"textDocumentSync", {{"openClose", true}, {"change", 2 /* incremental */}}},
        {"hoverProvider", true},
        {"completionProvider", {{"triggerCharacters", {"=", "("}}, {"resolveProvider", false}}},
        {"definitionProvider", true},
        {"referencesProvider", true},
        {"renameProvider", {{"prepareProvider", true}}},
        {"documentSymbolProvider", true},
        {"codeActionProvider", {{"codeActionKinds", {"quickfix"}}}},
        {"semanticTokensProvider", {{"legend", semanticTokensLegend()}, {"full", true}}},
        {"foldingRangeProvider", true},
        {"documentFormattingProvider", true},
        // The library's files, read-only: workspace/textDocumentContent (LSP 3.18) answers
        // for moire-stdlib:/// URIs.
        {"workspace", {{"textDocumentContent", {{"schemes", {"moire-stdlib"}}}}}},
    };
    return Json{{"capabilities", std::move(caps)},
                {"serverInfo", {{"name", "moire"}, {"version", MOIRE_VERSION}}}};
}

Document& Server::document(const Json& params) {
    std::string uri = uriOf(params);
    Document* d = docs_.find(uri);
    if (!d) throw RpcError(ErrorCode::InvalidParams, "the document " + uri + " is not open");
    return *d;
}

std::string Server::publish(Document& doc) {
    doc.diagnosticsDue.reset();
    Json diagnostics = Json::array();
    // The library's own files, opened read-only, are no scene of their own.
    if (!doc.uri.starts_with(kStdlibScheme))
        diagnostics = diagnosticsJson(DocView(doc.uri, docs_.analysis(doc)));
    return dumpJson(
        notification("textDocument/publishDiagnostics",
                     {{"uri", doc.uri}, {"version", doc.version}, {"diagnostics", diagnostics}}));
}

void Server::registerHandlers() {
    rpc_.setGate([this](const std::string& method, bool isRequest) {
        if (method == "exit") return;
        if (shutdown_) throw RpcError(ErrorCode::InvalidRequest, "the server is shutting down");
        if (!initialized_ && method != "initialize")
            throw RpcError(ErrorCode::ServerNotInitialized, "initialize first");
    });
    rpc_.onRequest("initialize", [this](const Json& p) { return initialize(p); });
    rpc_.onNotification("initialized", [](const Json&) {});
    rpc_.onRequest("shutdown", [this](const Json&) {
        shutdown_ = true;
        return Json(nullptr);
    });
    rpc_.onNotification("exit", [this](const Json&) { exited_ = true; });

    rpc_.onNotification("textDocument/didOpen", [this](const Json& p) {
        const Json& td = p.at("textDocument");
        Document& d = docs_.open(td.at("uri").get<std::string>(), td.at("text").get<std::string>(),
                                 td.value("version", 0));
        d.diagnosticsDue = now_; // at once: the editor shows the file's state as it opens
    });
    rpc_.onNotification("textDocument/didChange", [this](const Json& p) {
        Document& d = document(p);
        for (const Json& change : p.at("contentChanges")) docs_.change(d, change);
        d.version = p.at("textDocument").value("version", d.version);
        d.diagnosticsDue = now_ + debounce_;
    });
    rpc_.onNotification("textDocument/didClose", [this](const Json& p) {
        std::string uri = uriOf(p);
        if (docs_.find(uri)) {
            docs_.close(uri);
            pushed_.push_back(notification("textDocument/publishDiagnostics",
                                           {{"uri", uri}, {"diagnostics", Json::array()}})
                                  .dump());
        }
    });
    rpc_.onNotification("textDocument/didSave", [](const Json&) {});

    // A request about a place: the document's analysis (made now if a change made it stale)
    // and the place as a byte offset into the analysed text.
    auto at = [this](const Json& p, auto&& feature) {
        Document& d = document(p);
        DocView view(d.uri, docs_.analysis(d));
        uint32_t offset = view.index.offset(positionFrom(p.at("position")));
        return feature(view, offset);
    };
    rpc_.onRequest("textDocument/hover", [at](const Json& p) { return at(p, hover); });
    rpc_.onRequest("textDocument/completion", [at](const Json& p) { return at(p, completion); });
    rpc_.onRequest("textDocument/definition", [at](const Json& p) { return at(p, definition); });
    rpc_.onRequest("textDocument/references", [at](const Json& p) {
        bool decl = p.contains("context") && p["context"].value("includeDeclaration", false);
        return at(p, [&](const DocView& v, uint32_t o) { return references(v, o, decl); });
    });
    rpc_.onRequest("textDocument/prepareRename",
                   [at](const Json& p) { return at(p, prepareRename); });
    rpc_.onRequest("textDocument/rename", [at](const Json& p) {
        std::string name = p.at("newName").get<std::string>();
        return at(p, [&](const DocView& v, uint32_t o) { return rename(v, o, name); });
    });
    auto whole = [this](const Json& p, auto&& feature) {
        Document& d = document(p);
        return feature(DocView(d.uri, docs_.analysis(d)));
    };
    rpc_.onRequest("textDocument/documentSymbol",
                   [whole](const Json& p) { return whole(p, documentSymbols); });
    rpc_.onRequest("textDocument/semanticTokens/full",
                   [whole](const Json& p) { return whole(p, semanticTokens); });
    rpc_.onRequest("textDocument/foldingRange",
                   [whole](const Json& p) { return whole(p, foldingRanges); });
    rpc_.onRequest("textDocument/formatting",
                   [whole](const Json& p) { return whole(p, formatting); });
    rpc_.onRequest("textDocument/codeAction", [this](const Json& p) {
        Document& d = document(p);
        DocView view(d.uri, docs_.analysis(d));
        uint32_t b = view.index.offset(positionFrom(p.at("range").at("start")));
        uint32_t e = view.index.offset(positionFrom(p.at("range").at("end")));
        return codeActions(view, b, e);
    });
    rpc_.onRequest("workspace/textDocumentContent", [](const Json& p) {
        std::string uri = p.at("uri").get<std::string>();
        const std::string_view* text = stdlibText(uri);
        if (!text) throw RpcError(ErrorCode::InvalidParams, "no library file " + uri);
        return Json{{"text", std::string(*text)}};
    });
}

std::vector<std::string> Server::receive(const Frame& frame, Clock::time_point now) {
    now_ = now;
    std::vector<std::string> out;
    if (frame.kind == Frame::Kind::BadHeader) {
        out.push_back(dumpJson(Dispatcher::errorResponse(nullptr, ErrorCode::ParseError,
                                                         "bad header: " + frame.error)));
        return out;
    }
    std::optional<Json> response = rpc_.handle(frame.body);
    if (response) out.push_back(dumpJson(*response));
    for (std::string& s : pushed_) out.push_back(std::move(s));
    pushed_.clear();
    // A document opened is answered with its diagnostics straight away.
    for (std::string& s : due(now)) out.push_back(std::move(s));
    return out;
}

std::vector<std::string> Server::due(Clock::time_point now) {
    std::vector<std::string> out;
    for (auto& [uri, doc] : docs_.all())
        if (doc.diagnosticsDue && *doc.diagnosticsDue <= now) out.push_back(publish(doc));
    return out;
}

std::optional<Clock::time_point> Server::nextDue() const {
    std::optional<Clock::time_point> next;
    for (auto& [uri, doc] : const_cast<DocumentStore&>(docs_).all())
        if (doc.diagnosticsDue && (!next || *doc.diagnosticsDue < *next)) next = doc.diagnosticsDue;
    return next;
}

namespace {

bool writeAll(int fd, const std::string& bytes) {
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<size_t>(n);
    }
    return true;
}

} // namespace

int runServer(int inFd, int outFd) {
    // A client gone away is the end of the session, not a signal that kills moire.
    std::signal(SIGPIPE, SIG_IGN);
    Server server;
    FrameReader reader;
    std::vector<char> buf(1 << 16);
    auto send = [&](const std::vector<std::string>& bodies) {
        for (const std::string& b : bodies)
            if (!writeAll(outFd, frameMessage(b))) return false;
        return true;
    };
    while (!server.exited()) {
        if (!send(server.due(Clock::now()))) return 1;
        if (auto frame = reader.next()) {
            if (!send(server.receive(*frame))) return 1;
            continue;
        }
        int timeout = -1;
        if (auto next = server.nextDue()) {
            auto wait = std::chrono::ceil<std::chrono::milliseconds>(*next - Clock::now());
            timeout = static_cast<int>(std::max<int64_t>(0, wait.count()));
        }
        pollfd p{inFd, POLLIN, 0};
        int r = ::poll(&p, 1, timeout);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) return 1;
        if (r == 0) continue; // diagnostics due: sent at the top of the loop
        ssize_t n = ::read(inFd, buf.data(), buf.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break; // the client closed its end
        reader.feed(std::string_view(buf.data(), static_cast<size_t>(n)));
    }
    return server.exitStatus();
}

} // namespace moire::lsp
