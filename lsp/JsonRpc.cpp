#include "lsp/JsonRpc.h"

namespace moire::lsp {

std::string dumpJson(const Json& j) {
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Json Dispatcher::errorResponse(const Json& id, int code, const std::string& message) {
    return Json{{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}};
}

Json Dispatcher::resultResponse(const Json& id, Json result) {
    return Json{{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

std::optional<Json> Dispatcher::handle(std::string_view body) {
    Json msg = Json::parse(body, nullptr, /*allow_exceptions=*/false);
    if (msg.is_discarded()) return errorResponse(nullptr, ErrorCode::ParseError, "not JSON");
    if (!msg.is_object())
        return errorResponse(nullptr, ErrorCode::InvalidRequest, "a message is a JSON object");
    // A response to a request of ours: the server sends none that wait for an answer.
    if (!msg.contains("method") && (msg.contains("result") || msg.contains("error")))
        return std::nullopt;
    const bool isRequest = msg.contains("id");
    Json id = isRequest ? msg["id"] : Json(nullptr);
    if (isRequest && !id.is_number_integer() && !id.is_string()) {
        return errorResponse(nullptr, ErrorCode::InvalidRequest,
                             "a request's id is a number or a string");
    }
    if (!msg.contains("method") || !msg["method"].is_string()) {
        if (!isRequest) return std::nullopt; // nothing to answer a notification with
        return errorResponse(id, ErrorCode::InvalidRequest, "a request names its method");
    }
    const std::string method = msg["method"].get<std::string>();
    const Json params = msg.contains("params") ? msg["params"] : Json::object();
    try {
        if (gate_) gate_(method, isRequest);
        if (isRequest) {
            auto it = requests_.find(method);
            if (it == requests_.end())
                return errorResponse(id, ErrorCode::MethodNotFound, "no method " + method);
            return resultResponse(id, it->second(params));
        }
        auto it = notifications_.find(method);
        if (it != notifications_.end()) it->second(params);
        return std::nullopt; // unknown notifications ($/cancelRequest...) are ignored
    } catch (const RpcError& e) {
        if (!isRequest) return std::nullopt;
        return errorResponse(id, e.code(), e.what());
    } catch (const Json::exception& e) {
        // A param missing or of the wrong type, met while a handler read it.
        if (!isRequest) return std::nullopt;
        return errorResponse(id, ErrorCode::InvalidParams, std::string("bad params: ") + e.what());
    } catch (const std::exception& e) {
        // A bug in moire (InternalError) fails this request only; the session goes on.
        if (!isRequest) return std::nullopt;
        return errorResponse(id, ErrorCode::InternalError, e.what());
    }
}

} // namespace moire::lsp
