// JSON-RPC 2.0 as LSP uses it: requests (with an id) get exactly one response, notifications
// none. The dispatcher maps a method to its handler and turns everything that can go wrong
// with a message (not JSON, not a request, no such method, params of the wrong shape, a
// handler's refusal) into the error response the specification names, so that one bad message
// never ends the session.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>

namespace moire::lsp {

using Json = nlohmann::json;

// The error codes of JSON-RPC and of LSP.
namespace ErrorCode {
constexpr int ParseError = -32700;
constexpr int InvalidRequest = -32600;
constexpr int MethodNotFound = -32601;
constexpr int InvalidParams = -32602;
constexpr int InternalError = -32603;
constexpr int ServerNotInitialized = -32002;
constexpr int RequestFailed = -32803;
} // namespace ErrorCode

// Thrown by a handler to answer with an error (a malformed param, a refused rename).
class RpcError : public std::runtime_error {
  public:
    RpcError(int code, const std::string& message) : std::runtime_error(message), code_(code) {}
    int code() const { return code_; }

  private:
    int code_;
};

// The text of a message to send. Bytes that are not UTF-8 (a document of random bytes, quoted
// in a diagnostic) are replaced rather than refused.
std::string dumpJson(const Json& j);

class Dispatcher {
  public:
    using RequestHandler = std::function<Json(const Json& params)>;
    using NotificationHandler = std::function<void(const Json& params)>;
    // Runs before every handler with the method's name; it may throw RpcError to refuse
    // (a request before `initialize`, or after `shutdown`).
    using Gate = std::function<void(const std::string& method, bool isRequest)>;

    void onRequest(const std::string& method, RequestHandler h) { requests_[method] = h; }
    void onNotification(const std::string& method, NotificationHandler h) {
        notifications_[method] = h;
    }
    void setGate(Gate g) { gate_ = std::move(g); }

    // Handles one message body; the response to send, if it needs one.
    std::optional<Json> handle(std::string_view body);

    static Json errorResponse(const Json& id, int code, const std::string& message);
    static Json resultResponse(const Json& id, Json result);

  private:
    std::unordered_map<std::string, RequestHandler> requests_;
    std::unordered_map<std::string, NotificationHandler> notifications_;
    Gate gate_;
};

} // namespace moire::lsp
