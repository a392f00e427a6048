#include "runtime/serve/Server.h"

#include "runtime/serve/PageFiles.h"
#include "runtime/serve/Requests.h"
#include "runtime/serve/Token.h"

#include <fmt/format.h>
#include <functional>
#include <httplib.h>
#include <nlohmann/json.hpp>

namespace moire::serve {

namespace {

using json = nlohmann::json;

// How often an idle event stream sends a comment: a closed page is noticed within this time
// (the write fails) and its thread freed.
constexpr auto kHeartbeat = std::chrono::milliseconds(1000);

constexpr const char* kFrameGone = "that frame is gone: a newer one replaced it";

void answerError(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(json{{"error", message}}.dump(-1, ' ', false, json::error_handler_t::replace),
                    "application/json");
}

void answerVersion(httplib::Response& res, uint64_t version) {
    res.set_content(json{{"version", version}}.dump(), "application/json");
}

void refuse(httplib::Response& res) {
    answerError(res, 403, "this page needs the token of the URL that moire serve printed");
}

using TokenCheck = std::function<bool(const httplib::Request&)>;

// A POST handler that applies a message to the session. The token is checked here, once the
// body has been read, not before routing: a refusal that left the body unread on a kept-alive
// connection would have it read as the next request.
template <class Apply>
httplib::Server::Handler message(Session& session, TokenCheck hasToken, Apply apply) {
    return [&session, hasToken, apply](const httplib::Request& req, httplib::Response& res) {
        if (!hasToken(req)) return refuse(res);
        try {
            answerVersion(res, apply(session, req.body));
        } catch (const RequestError& e) {
            answerError(res, 400, e.what());
        }
    };
}

} // namespace

Server::Server(Session& session, std::string token)
    : session_(session), token_(std::move(token)), http_(std::make_unique<httplib::Server>()) {
    routes();
}

Server::~Server() {
    stop();
}

int Server::bind(const std::string& host, int port) {
    const int bound =
        port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
    if (bound <= 0)
        throw std::runtime_error(
            fmt::format("cannot listen on {}:{}: {}", host, port,
                        port == 0 ? "no free port" : "the port is taken or not allowed"));
    return bound;
}

void Server::start() {
    thread_ = std::thread([this] { http_->listen_after_bind(); });
}

void Server::stop() {
    session_.channel().close(); // the event streams end, freeing their threads
    if (http_) http_->stop();
    if (thread_.joinable()) thread_.join();
}

std::string Server::url(const std::string& host, int port) const {
    const bool v6 = host.find(':') != std::string::npos;
    return fmt::format("http://{}{}{}:{}/?token={}", v6 ? "[" : "", host, v6 ? "]" : "", port,
                       token_);
}

void Server::routes() {
    httplib::Server& s = *http_;
    s.set_payload_max_length(kMaxMessageBytes);
    // A message is at most 64 KiB from this machine (or a trusted network): a client that
    // takes longer than this to send one holds a thread for nothing.
    s.set_read_timeout(2, 0);
    s.set_write_timeout(5, 0);
    s.set_keep_alive_timeout(5);
    // The library writes a response's head and body apart: with Nagle's algorithm the body
    // waits for the client's delayed ACK, 40 ms on Linux, on every answer.
    s.set_tcp_nodelay(true);

    // The token first: nothing else is looked at for a request without it. A request with a
    // body is refused by its handler (message), after the body is read.
    TokenCheck hasToken = [this](const httplib::Request& req) {
        std::string given = req.get_param_value("token");
        if (given.empty()) given = req.get_header_value("X-Moire-Token");
        return sameToken(given, token_);
    };
    s.set_pre_routing_handler([hasToken](const httplib::Request& req, httplib::Response& res) {
        if (hasToken(req) || req.method == "POST")
            return httplib::Server::HandlerResponse::Unhandled;
        refuse(res);
        return httplib::Server::HandlerResponse::Handled;
    });
    s.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
        // The token is in the URL: no page of another site may learn it from the referrer.
        res.set_header("Referrer-Policy", "no-referrer");
        res.set_header("X-Content-Type-Options", "nosniff");
        if (!res.has_header("Cache-Control")) res.set_header("Cache-Control", "no-store");
    });
    s.set_error_handler([](const httplib::Request&, httplib::Response& res) {
        if (!res.body.empty()) return;
        answerError(res, res.status,
                    res.status == 404 ? "no such page"
                    : res.status == 413
                        ? fmt::format("the message is longer than {} bytes", kMaxMessageBytes)
                        : fmt::format("HTTP status {}", res.status));
    });
    s.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
            std::string what = "unknown error";
            try {
                std::rethrow_exception(ep);
            } catch (const std::exception& e) {
                what = e.what();
            } catch (...) {
            }
            answerError(res, 500, "moire: internal error: " + what);
        });

    auto serveAsset = [this](const char* name) {
        return [this, name](const httplib::Request&, httplib::Response& res) {
            std::optional<page::Asset> a = page::asset(name);
            if (!a) return answerError(res, 404, "no such page");
            std::string text(a->text);
            // The page's own links carry the token; only a request that had it gets here.
            for (size_t at; (at = text.find("{{token}}")) != std::string::npos;)
                text.replace(at, 9, token_);
            res.set_content(text, a->contentType);
            res.set_header("Content-Security-Policy",
                           "default-src 'self'; img-src 'self' blob:; style-src 'self'");
        };
    };
    s.Get("/", serveAsset("index.html"));
    s.Get("/page.js", serveAsset("page.js"));
    s.Get("/page.css", serveAsset("page.css"));

    s.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
        res.set_content(session_.stateJson(), "application/json");
    });
    s.Post("/api/view", message(session_, hasToken, applyViewMessage));
    s.Post("/api/clock", message(session_, hasToken, applyClockMessage));
    s.Post("/api/param", message(session_, hasToken, applyParameterMessage));
    s.Get("/api/params", [this](const httplib::Request&, httplib::Response& res) {
        res.set_content(session_.parametersJson(), "application/json");
    });

    // A frame by id: as the page takes it (.rgba: the bytes, width x height x 4, the size in
    // the X-Frame-Width and X-Frame-Height headers), or as a PNG file.
    s.Get(R"(/frame/(\d{1,18})\.rgba)",
          [this](const httplib::Request& req, httplib::Response& res) {
              std::optional<Session::Frame> f = session_.frame(std::stoull(req.matches[1].str()));
              if (!f) return answerError(res, 404, kFrameGone);
              res.set_content(reinterpret_cast<const char*>(f->rgba->data()), f->rgba->size(),
                              "application/octet-stream");
              res.set_header("X-Frame-Width", std::to_string(f->width));
              res.set_header("X-Frame-Height", std::to_string(f->height));
              // A frame's id names one picture for good.
              res.set_header("Cache-Control", "private, max-age=3600, immutable");
          });
    s.Get(R"(/frame/(\d{1,18})\.png)", [this](const httplib::Request& req, httplib::Response& res) {
        auto png = session_.framePng(std::stoull(req.matches[1].str()));
        if (!png) return answerError(res, 404, kFrameGone);
        res.set_content(reinterpret_cast<const char*>(png->data()), png->size(), "image/png");
        res.set_header("Cache-Control", "private, max-age=3600, immutable");
    });

    // The session's state as server-sent events: the newest state whenever it changes (states
    // in between are skipped), and a comment every kHeartbeat while nothing does.
    s.Get("/api/events", [this](const httplib::Request&, httplib::Response& res) {
        if (streams_.fetch_add(1) >= kMaxEventStreams) {
            streams_.fetch_sub(1);
            return answerError(
                res, 503,
                fmt::format("at most {} pages may follow the scene at once", kMaxEventStreams));
        }
        auto seen = std::make_shared<uint64_t>(0);
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream",
            [this, seen](size_t, httplib::DataSink& sink) {
                std::optional<StateChannel::State> st =
                    session_.channel().waitNewer(*seen, kHeartbeat);
                if (session_.channel().closed()) {
                    sink.done();
                    return true;
                }
                std::string chunk = ": heartbeat\n\n";
                if (st) {
                    *seen = st->version;
                    chunk = "event: state\ndata: " + st->json + "\n\n";
                }
                return sink.write(chunk.data(), chunk.size());
            },
            [this](bool) { streams_.fetch_sub(1); });
    });
}

} // namespace moire::serve
