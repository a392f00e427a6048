// `moire lsp`: the language server. Server is the protocol's state machine (initialize, the
// open documents, the debounced diagnostics, shutdown and exit), fed whole frames and handing
// back the messages to send, so that tests drive it without a process; runServer() is the
// loop that reads standard input and writes standard output.
#pragma once

#include "lsp/Documents.h"
#include "lsp/JsonRpc.h"
#include "lsp/Transport.h"

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace moire::lsp {

class Server {
  public:
    // How long the diagnostics wait after a change for the next one (the typing goes on).
    explicit Server(std::chrono::milliseconds debounce = std::chrono::milliseconds(40));

    // Handles one frame; the message bodies to send in answer (a response, diagnostics).
    std::vector<std::string> receive(const Frame& frame, Clock::time_point now = Clock::now());
    // The diagnostics due by `now`, as publishDiagnostics notifications.
    std::vector<std::string> due(Clock::time_point now);
    // When the next diagnostics are due, if any are waiting.
    std::optional<Clock::time_point> nextDue() const;

    bool exited() const { return exited_; }
    // The status to exit with: 0 after shutdown, else 1 (as LSP asks).
    int exitStatus() const { return shutdown_ ? 0 : 1; }

    DocumentStore& documents() { return docs_; }

  private:
    void registerHandlers();
    Json initialize(const Json& params);
    Document& document(const Json& params); // params.textDocument.uri, open
    std::string publish(Document& doc);

    Dispatcher rpc_;
    DocumentStore docs_;
    std::chrono::milliseconds debounce_;
    Clock::time_point now_;
    bool initialized_ = false, shutdown_ = false, exited_ = false;
    std::vector<std::string> pushed_; // notifications a handler sends besides its answer
};

// Serves the protocol on two file descriptors until `exit` or the end of the input; returns
// the exit status.
int runServer(int inFd, int outFd);

} // namespace moire::lsp
